"""The command line: exit codes, JSON schema, generated files, and mangled input that must end
in exit 2 with one line, never a traceback."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kinverify import load_spec
from kinverify.backends import ModelSources
from kinverify.cli import main

ARM3 = Path("models/arm3.toml").read_text()


def test_verify_writes_json_and_html(tmp_path, capsys):
    code = main(
        [
            "verify",
            "models/arm3.toml",
            "--samples",
            "50",
            *("--skip", "tracking", "--skip", "pictures"),  # the files written, not those suites (full runs: test_report)
            "--json",
            str(tmp_path / "r.json"),
            "--report",
            str(tmp_path / "r.html"),
        ]
    )
    out = capsys.readouterr().out
    assert code == 0
    assert "verdict: PASS" in out
    data = json.loads((tmp_path / "r.json").read_text())
    assert data["verdict"] == "pass"
    assert {"pin", "mujoco", "yourdfpy", "numpy", "python", "kinverify"} <= set(data["versions"])
    check = data["checks"][0]
    assert {"property", "frame", "backends", "max_error", "p99_error", "tolerance", "passed", "worst_q"} <= set(check)
    assert (tmp_path / "r.html").read_text().count("<html") == 1


def test_verify_exits_1_when_a_check_fails(tmp_path, capsys):
    # Jacobians agree with central differences to ~1e-10; demanding 1e-13 must fail.
    code = main(
        [
            "verify",
            "models/arm3.toml",
            "--samples",
            "20",
            "--backends",
            "analytic,mujoco",
            *("--skip", "tracking", "--skip", "pictures", "--skip", "ik"),  # the kinematics decide (full runs: test_report)
            "--tolerance",
            "jacobian.fd=1e-13",
            "--json",
            str(tmp_path / "r.json"),
            "--report",
            str(tmp_path / "r.html"),
        ]
    )
    out = capsys.readouterr().out
    assert code == 1
    assert "verdict: FAIL" in out and "first disagreeing frame" in out
    data = json.loads((tmp_path / "r.json").read_text())
    assert data["verdict"] == "fail"
    failed = [c for c in data["checks"] if not c["passed"]]
    assert failed and {c["property"] for c in failed} == {"jacobian.fd"}
    assert all(c["max_error"] > 1e-13 for c in failed)


def test_generate_writes_the_four_files(tmp_path, capsys):
    pytest.importorskip("pxr")  # without usd-core: the next test checks the three files and the note
    assert main(["generate", "models/scara.toml", "--out", str(tmp_path)]) == 0
    assert (tmp_path / "scara.urdf").read_text().startswith("<?xml")
    assert "<mujoco" in (tmp_path / "scara.xml").read_text()
    assert '<sdf version="1.9"' in (tmp_path / "scara.sdf").read_text()
    assert (tmp_path / "scara.usda").read_text().startswith("#usda 1.0")
    assert capsys.readouterr().out.split() == [str(tmp_path / f"scara.{ext}") for ext in ("urdf", "xml", "sdf", "usda")]


def test_without_usd_core_generate_writes_three_files_and_says_why(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "pxr", None)  # as if usd-core were not installed
    monkeypatch.delitem(sys.modules, "kinverify.generate.usd", raising=False)
    assert main(["generate", "models/arm3.toml", "--out", str(tmp_path)]) == 0
    out, err = capsys.readouterr()
    assert out.split() == [str(tmp_path / f"arm3.{ext}") for ext in ("urdf", "xml", "sdf")]
    assert "no arm3.usda written: usd-core (pxr) is not installed; pip install 'kinverify[usd]'" in err
    assert not (tmp_path / "arm3.usda").exists()
    assert ModelSources.from_spec(load_spec("models/arm3.toml")).usd is None


@pytest.mark.parametrize(
    "argv, words",
    [
        (["verify", "models/nope.toml"], "models/nope.toml: cannot read spec file"),
        (["verify", "models/arm3.toml", "--backends", "pybullet"], "unknown backend 'pybullet'; available backends:"),
        (["verify", "models/arm3.toml", "--skip", "everything"], "unknown suite"),
        (["verify"], "give a spec MODEL"),
        (["verify", "models/arm3.toml", "--tolerance", "fk.position=abc"], "is not PROPERTY=NUMBER"),
        (["verify", "models/arm3.toml", "--tolerance", "fk.speed=1"], "unknown property 'fk.speed'"),
        (["verify", "models/arm3.toml", "--gate", "ik.success_rate"], "'ik.success_rate' is now named 'ik.failure_rate'"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(argv, words, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1 and "Traceback" not in err


def test_module_entry_point_runs_without_traceback(tmp_path):
    bad = tmp_path / "zero_axis.toml"
    bad.write_text(ARM3.replace("axis = [0.0, 1.0, 0.0]", "axis = [0.0, 0.0, 0.0]", 1))
    proc = subprocess.run([sys.executable, "-m", "kinverify", "verify", str(bad)], capture_output=True, text=True)
    assert proc.returncode == 2
    assert proc.stderr == f"kinverify: error: {bad}: joints[1].axis: axis must be non-zero\n"


NUMBER = re.compile(r"(?<![\w.])-?\d+(\.\d+)?")


@st.composite
def mangled_specs(draw) -> bytes:
    text = ARM3
    kind = draw(st.sampled_from(["truncate", "number", "line", "bytes", "key"]))
    if kind == "truncate":
        return text.encode()[: draw(st.integers(0, len(text) - 1))]
    if kind == "number":
        matches = list(NUMBER.finditer(text))
        m = draw(st.sampled_from(matches))
        new = draw(st.sampled_from(["nan", "inf", "1e308", "-1e308", '"text"', "true", "[]", "{}", "-0.5"]))
        return (text[: m.start()] + new + text[m.end() :]).encode()
    if kind == "line":
        lines = text.splitlines()
        del lines[draw(st.integers(0, len(lines) - 1))]
        return "\n".join(lines).encode()
    if kind == "key":
        return text.replace(
            draw(st.sampled_from(["name", "axis", "limits", "lower", "xyz", "type", "geometry"])), "bogus", 1
        ).encode()
    return draw(st.binary(min_size=0, max_size=200))


@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(mangled_specs())
def test_mangled_spec_files_give_one_line_and_exit_2(capsys, raw):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "mangled.toml"
        path.write_bytes(raw)
        capsys.readouterr()
        code = main(["generate", str(path), "--out", tmp])
        out, err = capsys.readouterr()
    if code == 0:  # the mangling happened to keep a valid spec (e.g. removed a comment line)
        from kinverify import load_spec

        assert load_spec is not None and err == ""
        return
    assert code == 2
    assert err.startswith(f"kinverify: error: {path}: ") and err.count("\n") == 1, err
    assert "Traceback" not in err


def test_argument_errors_are_one_line_and_exit_2(capsys):
    for argv, words in (
        (["verify", "models/arm3.toml", "--seed", "-1"], "--seed must be >= 0, got -1"),
        (["verify", "models/arm3.toml", "--samples", "abc"], "argument --samples: expected a whole number"),
        (["verify", "models/arm3.toml", "--seed", str(2**64)], "--seed 18446744073709551616 is above the maximum"),
        (["diff", "models/arm3.toml", "models/arm3.toml", "--samples", "-5"], "--samples must be >= 0"),
        (["baseline", "save", "models/arm3.toml", "--out", "b.json", "--seed", "-3"], "--seed must be >= 0"),
        (["nonsense"], "invalid choice"),
    ):
        if argv[-1] in ("abc", "nonsense"):  # argparse's own errors exit 2 through SystemExit
            with pytest.raises(SystemExit) as exc:
                main(argv)
            assert exc.value.code == 2
        else:
            assert main(argv) == 2
        err = capsys.readouterr().err
        assert words in err and err.count("\n") == 1 and "Traceback" not in err, err


def test_seed_minus_one_through_the_module_entry_point():
    proc = subprocess.run(
        [sys.executable, "-m", "kinverify", "verify", "models/arm3.toml", "--seed", "-1"], capture_output=True, text=True
    )
    assert proc.returncode == 2 and proc.stderr == "kinverify: error: --seed must be >= 0, got -1\n"


def test_an_internal_error_exits_3_with_one_line_and_where_to_report_it(capsys, monkeypatch):
    # A kinverify bug stands in as a real exception raised from the real generate command.
    import kinverify.commands.generate as generate

    def broken(args):
        return {}["missing key"]

    monkeypatch.setattr(generate, "run", broken)
    assert main(["generate", "models/arm3.toml", "--out", "unused"]) == 3
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("kinverify: internal error: KeyError: 'missing key' (please report it at the kinverify issue tracker")


def test_an_internal_error_in_a_suite_still_writes_the_report(tmp_path, capsys, monkeypatch):
    from kinverify.suites.workspace import WorkspaceSuite

    def broken(self, ctx):
        return 1 / 0

    monkeypatch.setattr(WorkspaceSuite, "run", broken)
    code = main(
        [
            "verify",
            "models/arm3.toml",
            "--samples",
            "5",
            "--skip",
            "ik",
            "--skip",
            "tracking",
            "--skip",
            "pictures",
            "--json",
            str(tmp_path / "r.json"),
            "--report",
            str(tmp_path / "r.html"),
        ]
    )
    assert code == 3
    data = json.loads((tmp_path / "r.json").read_text())
    assert data["verdict"] == "error" and data["internal_errors"][0].startswith("suite workspace: ZeroDivisionError")
    assert data["checks"] and (tmp_path / "r.html").exists()  # what the other suites computed is kept


def test_a_system_error_exits_2_naming_it_not_3(capsys, monkeypatch):
    """The system refusing a write (a full disk: /dev/full always is) is no kinverify bug: exit 2
    and one line saying so, as bad input, never 3. The generate command writes to it for real."""
    import kinverify.commands.generate as generate

    def fills_the_disk(args):
        with open("/dev/full", "w") as handle:
            handle.write("x")
            handle.flush()
        return 0

    monkeypatch.setattr(generate, "run", fills_the_disk)
    assert main(["generate", "models/arm3.toml", "--out", "unused"]) == 2
    err = capsys.readouterr().err
    assert err == "kinverify: error: No space left on device (a system error)\n"


@pytest.mark.skipif(not Path("/sys/kernel").is_dir(), reason="no sysfs here")
def test_an_output_folder_the_system_refuses_exits_2_in_one_line(capsys):
    """/sys refuses new files even to root (EPERM), as a read-only folder refuses them (EACCES)."""
    assert main(["generate", "models/arm3.toml", "--out", "/sys/kinverify-test"]) == 2
    err = capsys.readouterr().err
    assert re.fullmatch(
        r"kinverify: error: /sys/kinverify-test/arm3\.urdf: cannot write: "
        r"(Operation not permitted|Permission denied|Read-only file system)\n",
        err,
    ), err
