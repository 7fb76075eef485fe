"""Fuzz the command line itself: every subcommand with hostile argument values (NaN, inf, huge and
negative numbers, text for numbers, unknown names, paths that are inputs, directories or devices).
Whatever the mix: exit 0, 1 or 2, one line, no traceback, inputs untouched."""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

import pytest
from hypothesis import given, note
from hypothesis import strategies as st

from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import load_spec
from tests.fuzz.harness import fuzz_settings, log_example, run_checked
from tests.paths import MODELS

NUMBERS = ["nan", "inf", "-inf", "-1", "0", "1", "2", "1e308", "-1e308", str(10**30), "abc", "", "0x10", "1_000"]
NAMES = [
    "fk.position=1e-12",
    "fk.position=-1",
    "fk.position=nan",
    "ik.failure_rate",
    "ik.success_rate",
    "nope=1",
    "=",
    "",
    "ik",
    "everything",
    "analytic",
    "mujoco,analytic",
    "pybullet",
    "base=base",
    "joint1=joint1",
    "a=b=c",
]
QUICK = [
    "--backends",
    "analytic,mujoco",
    "--skip",
    "ik",
    "--skip",
    "tracking",
    "--skip",
    "pictures",
    "--skip",
    "workspace",
    "--skip",
    "dynamics",
]
PATHS = ["IN_SPEC", "IN_URDF", "IN_MJCF", "DIR", "/dev/null", "OUT/new.json", "OUT/new.html", "missing/deep/x.json", ""]


def _value(draw, kind: str) -> str:
    return draw(st.sampled_from({"number": NUMBERS, "name": NAMES, "path": PATHS}[kind]))


@st.composite
def command_lines(draw) -> list[str]:
    command = draw(st.sampled_from(["verify", "verify-files", "ik", "track", "diff", "baseline-check", "generate", "report"]))
    base = {
        "verify": ["verify", "IN_SPEC", *QUICK, "--quiet"],
        "verify-files": ["verify", "--urdf", "IN_URDF", "--mjcf", "IN_MJCF", "--quiet"],
        "ik": ["ik", "IN_SPEC", "--target", "0.2", "0.1", "0.5"],
        "track": ["track", "IN_SPEC", "--duration", "0.2", "--hold", "0"],
        "diff": ["diff", "IN_URDF", "IN_URDF2"],
        "baseline-check": ["baseline", "check", "IN_SPEC", "--baseline", "IN_BASELINE"],
        "generate": ["generate", "IN_SPEC", "--out", "OUT"],
        "report": ["report", "IN_RESULTS"],
    }[command]
    options = {
        "verify": [
            ("--samples", "number"),
            ("--seed", "number"),
            ("--jobs", "number"),
            ("--chunk", "number"),
            ("--tolerance", "name"),
            ("--gate", "name"),
            ("--backends", "name"),
            ("--skip", "name"),
            ("--json", "path"),
            ("--report", "path"),
            ("--ik-targets", "number"),
            ("--slow-samples", "number"),
        ],
        "verify-files": [
            ("--samples", "number"),
            ("--frames", "name"),
            ("--joints", "name"),
            ("--backends", "name"),
            ("--json", "path"),
            ("--report", "path"),
            ("--seed", "number"),
        ],
        "ik": [("--seed", "number"), ("--frame", "name"), ("--backend", "name"), ("--rpy", "number")],
        "track": [
            ("--duration", "number"),
            ("--hold", "number"),
            ("--controller", "name"),
            ("--json", "path"),
            ("--to", "number"),
        ],
        "diff": [("--samples", "number"), ("--seed", "number"), ("--report", "path")],
        "baseline-check": [("--tolerance", "number"), ("--report", "path")],
        "generate": [("--out", "path")],
        "report": [("--out", "path")],
    }[command]
    argv = list(base)
    for flag, kind in draw(st.lists(st.sampled_from(options), max_size=3)):
        argv += [flag, _value(draw, kind)]
    if command in ("verify", "verify-files", "diff") and "--samples" not in argv:
        argv += ["--samples", "2"]  # keep a run that is accepted short
    return argv


@pytest.fixture(scope="module")
def inputs(tmp_path_factory) -> Path:
    """A spec, its URDF and MJCF, a baseline and a results JSON, made once."""
    from kinverify.cli import main

    folder = tmp_path_factory.mktemp("inputs")
    spec = load_spec(MODELS / "arm3.toml")
    shutil.copy(MODELS / "arm3.toml", folder / "m.toml")
    (folder / "u.urdf").write_text(generate_urdf(spec))
    (folder / "u2.urdf").write_text(generate_urdf(spec))
    (folder / "r.xml").write_text(generate_mjcf(spec))
    assert main(["baseline", "save", str(folder / "m.toml"), "--out", str(folder / "b.json"), "--samples", "2"]) == 0
    assert (
        main(
            [
                "verify",
                str(folder / "m.toml"),
                "--samples",
                "2",
                *QUICK,
                "--quiet",
                "--json",
                str(folder / "res.json"),
                "--report",
                str(folder / "res.html"),
            ]
        )
        == 0
    )
    return folder


@fuzz_settings(15)
@given(command_lines())
def test_hostile_command_lines(capfd, inputs, argv):
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for name in ("m.toml", "u.urdf", "u2.urdf", "r.xml", "b.json", "res.json"):
            shutil.copy(inputs / name, work / name)
        (work / "dir").mkdir()
        names = {
            "IN_SPEC": "m.toml",
            "IN_URDF": "u.urdf",
            "IN_URDF2": "u2.urdf",
            "IN_MJCF": "r.xml",
            "IN_BASELINE": "b.json",
            "IN_RESULTS": "res.json",
            "DIR": "dir",
            "OUT": "out",
        }
        real = []
        for arg in argv:
            for key, name in sorted(names.items(), key=lambda kv: -len(kv[0])):
                if arg.startswith(key):
                    arg = str(work / name) + arg[len(key) :]
                    break
            real.append(arg)
        note(" ".join(real))
        # the files this command line reads (an existing file named as an output may be replaced)
        outputs = {real[i + 1] for i, a in enumerate(real[:-1]) if a in ("--json", "--report", "--out")}
        files = [
            work / n
            for n in ("m.toml", "u.urdf", "u2.urdf", "r.xml", "b.json", "res.json")
            if str(work / n) in real and str(work / n) not in outputs
        ]
        cwd = os.getcwd()
        os.chdir(work)  # default outputs (reports/...) land here
        try:
            run_checked(capfd, real, files, work)
        except SystemExit as exc:  # argparse's own refusals (unknown choice, a value that is not a number)
            assert exc.code == 2
            err = capfd.readouterr().err
            log_example(real, 2, "Traceback" in err, [])
            assert err.count("\n") == 1 and "Traceback" not in err, err
        finally:
            os.chdir(cwd)
