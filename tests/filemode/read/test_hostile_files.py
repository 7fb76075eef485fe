"""Files that used to crash file mode or pass when they should not: a planar base, a joint
named like a link, a huge file, non-physical inertials, a joint missing from one file."""

from __future__ import annotations

import json
import re
import time
from pathlib import Path

import numpy as np
import pytest

from kinverify.backends.pinocchio_ import PinocchioBackend
from kinverify.backends.yourdfpy_ import YourdfpyBackend
from kinverify.cli import main
from kinverify.errors import InputError
from kinverify.filemode.pipeline import diagnose_files, verify_files
from kinverify.filemode.read.loading import load_mjcf, load_urdf
from kinverify.filemode.read.validate import inertial_problem, validate_inertials
from kinverify.pipeline.limits import MAX_JOINTS, MAX_LINKS, MAX_MODEL_BYTES
from kinverify.run import VerifyOptions
from tests.filemode.pairs import NO_PICTURES, generated_pair, write_pair

FAST = VerifyOptions(samples=10, fd_samples=5, suites=NO_PICTURES)


def one_line_exit_2(capsys, argv) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("kinverify: error: ") and "Traceback" not in err, err
    return err


def verify_cli(tmp_path, urdf: str, mjcf: str, samples: int) -> int:
    """``kinverify verify --urdf --mjcf`` with its JSON and report in ``tmp_path`` (not the project's reports/)."""
    outputs = ["--quiet", "--json", f"{tmp_path}/r.json", "--report", f"{tmp_path}/r.html"]
    return main(["verify", "--urdf", urdf, "--mjcf", mjcf, "--samples", str(samples), *outputs])


def test_a_floating_root_joint_is_compared_and_a_planar_root_refused_in_one_line(tmp_path, capsys):
    urdf, mjcf = generated_pair("arm3")
    floating = urdf.replace('<joint name="world_to_base" type="fixed">', '<joint name="world_to_base" type="floating">')
    u, m = write_pair(tmp_path, floating, mjcf)
    # the MJCF's robot is welded to the world: the one difference, the rest compared with the base fixed
    assert verify_cli(tmp_path, u, m, 8) == 1
    errors = [f["kind"] for f in json.loads((tmp_path / "r.json").read_text())["findings"] if f["severity"] == "error"]
    assert errors == ["floating_one_file"]
    planar = urdf.replace('<joint name="world_to_base" type="fixed">', '<joint name="world_to_base" type="planar">')
    u, m = write_pair(tmp_path, planar, mjcf)
    err = one_line_exit_2(capsys, ["verify", "--urdf", u, "--mjcf", m, "--json", f"{tmp_path}/p.json"])
    assert f"{u}: joint 'world_to_base' is planar: unsupported: planar base" in err
    assert not (tmp_path / "p.json").exists()


def test_a_multi_dof_joint_inside_the_chain_is_refused_by_the_library_that_cannot_read_it(tmp_path):
    urdf, mjcf = generated_pair("arm3")
    urdf = urdf.replace('<joint name="joint3" type="revolute">', '<joint name="joint3" type="planar">')
    diag = diagnose_files(*write_pair(tmp_path, urdf, mjcf), FAST)
    refused = [f for f in diag["findings"] if f.kind == "parser_refused" and f.values.get("backend") == "yourdfpy"]
    assert refused and "yourdfpy refuses the URDF: ValueError: Dimensionality of configuration" in refused[0].message
    assert "joint3" in diag["matching"].unmatched_urdf or "joint3" not in [a for a, _, _ in diag["matching"].joints]


def test_a_joint_named_like_a_link_is_looked_up_as_the_link(tmp_path, capsys):
    urdf, mjcf = generated_pair("arm3")
    urdf = urdf.replace('name="joint2"', 'name="link2"')
    joints, frames = ["joint1", "link2", "joint3"], ["link1", "link2", "link3"]
    pin, ydf = PinocchioBackend.from_urdf(urdf, joints, frames), YourdfpyBackend.from_urdf(urdf, joints, frames)
    q = np.array([[0.3, -0.7, 1.1]])
    assert np.allclose(pin.poses(q), ydf.poses(q), atol=1e-9)  # the link frame, not the joint frame
    u, m = write_pair(tmp_path, urdf, mjcf)
    assert verify_cli(tmp_path, u, m, 5) == 0
    assert "Traceback" not in capsys.readouterr().err


def _chain_urdf(n: int) -> str:
    link = '<link name="l{i}"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>'
    joint = (
        '<joint name="j{i}" type="revolute"><parent link="l{p}"/><child link="l{i}"/><origin xyz="0 0 0.1"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
    )
    body = "\n".join(link.format(i=i) + joint.format(i=i, p=i - 1) for i in range(1, n))
    return f'<?xml version="1.0"?>\n<robot name="chain">\n<link name="l0"/>\n{body}\n</robot>\n'


def test_a_400000_link_urdf_is_refused_at_once(tmp_path, capsys):
    huge = tmp_path / "huge.urdf"
    huge.write_text(_chain_urdf(400_000))
    assert huge.stat().st_size > MAX_MODEL_BYTES
    _, mjcf = write_pair(tmp_path, *generated_pair("arm3"))
    t0 = time.perf_counter()
    err = one_line_exit_2(capsys, ["verify", "--urdf", str(huge), "--mjcf", mjcf])
    assert time.perf_counter() - t0 < 30  # a refusal, not a parse (measured: milliseconds)
    assert f"{huge} is " in err and f"MB, above the {MAX_MODEL_BYTES // 2**20} MB kinverify reads" in err


def test_too_many_links_or_joints_are_refused_after_a_linear_parse(tmp_path, capsys):
    small = tmp_path / "many.urdf"
    small.write_text(_chain_urdf(MAX_LINKS + 1))
    assert small.stat().st_size < MAX_MODEL_BYTES
    with pytest.raises(InputError, match=f"has {MAX_LINKS + 1} links, above the {MAX_LINKS}"):
        load_urdf(str(small))
    joints = tmp_path / "joints.urdf"
    joints.write_text(_chain_urdf(MAX_JOINTS + 2))
    with pytest.raises(InputError, match=f"has {MAX_JOINTS + 1} movable joints, above the {MAX_JOINTS}"):
        load_urdf(str(joints))
    replicated = tmp_path / "replicated.xml"
    replicated.write_text(
        '<mujoco><worldbody><replicate count="100000" offset="0 0 1"><body name="b"><joint/>'
        '<geom size="0.1"/></body></replicate></worldbody></mujoco>'
    )
    with pytest.raises(InputError, match="has 100000 bodies"):
        load_mjcf(str(replicated))
    flex = tmp_path / "flex.xml"
    flex.write_text(
        '<mujoco><worldbody><flexcomp name="f" type="grid" count="100 100 100" spacing="0.1 0.1 0.1" dim="3"/>'
        "</worldbody></mujoco>"
    )
    with pytest.raises(InputError, match="has 1000000 bodies"):
        load_mjcf(str(flex))


@pytest.mark.parametrize(
    "mass, inertia, problem",
    [
        (-1.0, np.eye(3), "mass -1 kg is negative"),
        (float("nan"), None, "mass nan is not finite"),
        (0.0, np.eye(3), "mass is zero but the inertia is not"),
        (1.0, np.diag([1.0, 1.0, -0.5]), "not positive semi-definite"),
        (1.0, np.diag([1.0, 1.0, 2.5]), "break the triangle inequality"),
        (1.0, np.array([[1.0, 2.0, 0], [2.0, 1.0, 0], [0, 0, 1.0]]), "not positive semi-definite"),
        (1.0, np.diag([1.0, 1.0, float("inf")]), "non-finite"),
    ],
)
def test_non_physical_inertials_are_named(mass, inertia, problem):
    assert problem in inertial_problem(mass, inertia)


@pytest.mark.parametrize(
    "mass, inertia",
    [
        (1.0, np.zeros((3, 3))),  # a point mass
        (1.0, np.diag([0.0, 0.5, 0.5])),  # a thin rod
        (1.0, np.diag([1.0, 1.0, 2.0])),  # a thin disk: A + B = C
        (0.0, np.zeros((3, 3))),  # a massless link
        (2.0, None),
    ],
)
def test_physical_limits_are_accepted(mass, inertia):
    assert inertial_problem(mass, inertia) is None


def test_a_urdf_link_with_negative_mass_fails_file_mode(tmp_path, capsys):
    urdf, mjcf = generated_pair("arm3")
    head, link2 = urdf.split('<link name="link2">')
    urdf = head + '<link name="link2">' + re.sub(r'<mass value="[^"]*"/>', '<mass value="-1"/>', link2, count=1)
    assert '<mass value="-1"/>' in urdf
    u, m = write_pair(tmp_path, urdf, mjcf)
    assert verify_cli(tmp_path, u, m, 5) == 1
    capsys.readouterr()
    found = [f for f in validate_inertials(load_urdf(u), load_mjcf(m))]
    assert [(f.kind, f.severity, f.subject, f.subject_type) for f in found] == [("nonphysical_inertia", "error", "link2", "link")]
    assert found[0].message == f"URDF {u}: link link2: non-physical inertial: mass -1 kg is negative"


def test_an_mjcf_lacking_one_of_the_urdf_joints_fails(tmp_path):
    urdf, mjcf = generated_pair("arm3")
    # the joint, and the actuator and sensor that act on it
    mjcf = "\n".join(line for line in mjcf.splitlines() if 'name="joint3"' not in line and 'joint="joint3"' not in line)
    result = verify_files(*write_pair(tmp_path, urdf, mjcf), FAST)
    missing = [f for f in result.findings if f.kind == "extra_parts"]
    assert [(f.subject, f.severity, f.values["file"]) for f in missing] == [("joint3", "error", "URDF")]
    assert not [f for f in result.findings if f.kind == "lumped_links"]  # link3 is in both files: no merged links
    assert result.verdict == "fail" and result.exit_code == 1


def test_mujoco_writes_no_log_file_into_the_current_folder(tmp_path, monkeypatch, capfd):
    monkeypatch.chdir(tmp_path)
    urdf, mjcf = generated_pair("arm3")
    u, m = write_pair(
        tmp_path, urdf, mjcf.replace('<body name="link1" pos="0.0 0.0 0.1">', '<body name="link1" pos="nan 0.0 0.1">')
    )
    assert 'pos="nan' in Path(m).read_text()
    assert main(["diff", m, m, "--samples", "2", "--report", str(tmp_path / "d.html")]) in (0, 1, 2)
    out, err = capfd.readouterr()
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists() and "WARNING: XML contains a 'NaN'" not in out
