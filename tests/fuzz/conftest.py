"""Valid inputs of every kind, made once per test process, for the hostile-input tests: a spec, its
URDF and MJCF, an MJCF that includes a file, a xacro that includes one, an accepted-differences
file, a baseline, a passing and a failing results JSON, IK targets and initial guesses."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import load_spec
from tests.paths import MODELS

FAST = [
    "--samples",
    "2",
    "--skip",
    "ik",
    "--skip",
    "tracking",
    "--skip",
    "pictures",
    "--skip",
    "workspace",
    "--backends",
    "analytic,mujoco",
    "--quiet",
]
FILES = ["--samples", "0", "--skip", "pictures", "--quiet"]  # file mode and the one-file audit
XACRO_NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


@pytest.fixture(scope="session")
def valid(tmp_path_factory) -> Path:
    """A folder of valid inputs (never modified: copy it, see :func:`work`)."""
    from kinverify.cli import main

    d = tmp_path_factory.mktemp("valid")
    spec = load_spec(MODELS / "arm3.toml")
    shutil.copy(MODELS / "arm3.toml", d / "m.toml")
    urdf, mjcf = generate_urdf(spec), generate_mjcf(spec)
    (d / "u.urdf").write_text(urdf)
    (d / "r.xml").write_text(mjcf)
    (d / "inc.xml").write_text("<mujoco><option timestep='0.002'/></mujoco>\n")
    (d / "main.xml").write_text(mjcf.replace("<worldbody>", '<include file="inc.xml"/>\n  <worldbody>', 1))
    (d / "part.xacro").write_text(f'<robot {XACRO_NS}><link name="end_effector"/></robot>\n')
    (d / "robot.urdf.xacro").write_text(
        urdf.replace('<robot name="arm3">', f'<robot name="arm3" {XACRO_NS}>').replace(
            '<link name="end_effector"/>', '<xacro:include filename="part.xacro"/>'
        )
    )
    (d / "accept.toml").write_text('[[accepted]]\nkind = "x"\nsubject = "y"\nmagnitude = 1.0\nreason = "reviewed: keep"\n')
    targets = np.tile(np.eye(4), (3, 1, 1))
    targets[:, :3, 3] = [0.2, 0.1, 0.6]
    np.save(d / "t.npy", targets)
    np.save(d / "q.npy", np.zeros((3, 3)))
    assert main(["baseline", "save", str(d / "m.toml"), "--out", str(d / "b.json"), "--samples", "2"]) == 0
    assert main(["verify", str(d / "m.toml"), *FAST, "--json", str(d / "res.json"), "--report", str(d / "res.html")]) == 0
    flipped = d / "flip.xml"
    flipped.write_text(mjcf.replace('axis="0.0 1.0 0.0"', 'axis="0.0 -1.0 0.0"', 1))
    assert (
        main(
            [
                "verify",
                "--urdf",
                str(d / "u.urdf"),
                "--mjcf",
                str(flipped),
                "--samples",
                "0",
                "--quiet",  # pictures too
                "--json",
                str(d / "fail.json"),
                "--report",
                str(d / "res.html"),
            ]
        )
        == 1
    )
    flipped.unlink()
    (d / "res.html").unlink()
    return d


@pytest.fixture
def work(valid, tmp_path, monkeypatch) -> Path:
    """A copy of the valid inputs, the current folder for the test (default outputs land here)."""
    for p in valid.iterdir():
        shutil.copy(p, tmp_path / p.name)
    (tmp_path / "out").mkdir()
    monkeypatch.chdir(tmp_path)
    return tmp_path
