"""Attribution: each rule pinned by the smallest planted change where it and its nearest wrong
variant disagree. A joint frame moved along its axis is one finding with the full vector (not an
axis finding for the part across it and centres of mass for the rest); a frame turned about
another axis than its joint's is one finding with that axis and angle (not a tilt of the axis and
the twist left to the centres of mass); a tilt below a turned parent is measured in its own right
(not on its parent's axis); what a moved frame carries is compared in that frame; a first axis
tilted where nothing but the joints places the MJCF's world is that axis, not a turned world."""

from __future__ import annotations

import math
import os
from pathlib import Path

import mujoco
import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.filemode.compare.inertials import analyse
from kinverify.filemode.pipeline import diagnose_files, verify_files
from kinverify.model.transforms import axis_angle_to_matrix, matrix_to_quat, quat_to_matrix
from kinverify.run import VerifyOptions
from kinverify.testing.strategies import mesh_free_urdf, mujoco_mjcf
from tests.paths import REAL_ROBOTS

FAST = VerifyOptions(samples=6, fd_samples=3, backends=["pinocchio-urdf", "mujoco"])


def diagnose(tmp_path, mjcf):
    urdf, _ = P.generated_pair("panda")
    diag = diagnose_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)
    errors = sorted((f.kind, f.subject) for f in diag["findings"] if f.severity == "error")
    bodies = [r.label for r in analyse(diag["info"], (1e-6, 1e-6, 1e-9)) if r.status == "differs"]
    return diag, errors, bodies


def finding(diag, kind):
    (f,) = [f for f in diag["findings"] if f.kind == kind]
    return f


def body_quat(mjcf: str, body: str) -> np.ndarray:
    found = P.re.search(rf'<body name="{body}"[^>]*? quat="([^"]*)"', mjcf)
    return np.array([float(x) for x in found[1].split()]) if found else np.array([1.0, 0.0, 0.0, 0.0])


def turned(mjcf: str, body: str, axis, angle: float) -> str:
    """``body``'s frame turned by ``angle`` about ``axis`` (its own axes), nothing it holds turned back."""
    rot = quat_to_matrix(body_quat(mjcf, body)) @ axis_angle_to_matrix(np.asarray(axis, float), np.array([angle]))[0]
    return P.body_attr(mjcf, body, "quat", lambda _: " ".join(repr(float(x)) for x in matrix_to_quat(rot)))


def test_a_frame_moved_along_and_across_its_axis_is_one_finding_with_the_full_vector(tmp_path):
    """panda_link4 moved 3 mm along joint 4's axis and 4 mm across it: one moved frame of 5 mm,
    the vector in panda_link3's axes; no axis finding (the across part alone) and no centre of
    mass of panda_link4 or below differing (the along part)."""
    _, mjcf = P.generated_pair("panda")
    along = quat_to_matrix(body_quat(mjcf, "panda_link4")) @ np.array([0.0, 0.0, 1.0])  # joint axis: the body's z
    across = np.cross(along, [0.0, 0.0, 1.0]) if abs(along[2]) < 0.9 else np.cross(along, [1.0, 0.0, 0.0])
    d = 3e-3 * along + 4e-3 * across / np.linalg.norm(across)
    diag, errors, bodies = diagnose(tmp_path, P.body_attr(mjcf, "panda_link4", "pos", P.nums(lambda v: list(np.add(v, d)))))
    assert errors == [("joint_origin_moved", "panda_joint4")] and bodies == []
    moved = finding(diag, "joint_origin_moved")
    assert moved.magnitude == pytest.approx(5e-3, abs=1e-9)
    assert moved.values["xyz"] == pytest.approx(d.tolist(), abs=1e-9)


def test_a_frame_turned_about_another_axis_is_one_turn_with_its_axis_and_angle(tmp_path):
    """panda_link5's frame turned by 7° about (1, 0, 1)/√2 of its own axes (a tilt of joint 5's axis
    and a twist about it at once): one turned frame of 7° about that axis; no axis finding, no zero
    offset for the twist, no centre of mass below differing."""
    _, mjcf = P.generated_pair("panda")
    axis = np.array([1.0, 0.0, 1.0]) / math.sqrt(2)
    diag, errors, bodies = diagnose(tmp_path, turned(mjcf, "panda_link5", axis, math.radians(7)))
    assert errors == [("joint_origin_turned", "panda_joint5")] and bodies == []
    turn = finding(diag, "joint_origin_turned")
    assert turn.magnitude == pytest.approx(math.radians(7), abs=1e-9)
    assert turn.values["axis"] == pytest.approx(axis.tolist(), abs=1e-9)
    half = math.radians(3.5)  # the twist about joint 5's axis (the body's z): its part of the turn's quaternion
    assert turn.values["twist_rad"] == pytest.approx(2 * math.atan2(math.sin(half) / math.sqrt(2), math.cos(half)), abs=1e-9)
    assert turn.values["tilt_rad"] > math.radians(4)


def test_a_tilt_below_a_turned_parent_is_measured_in_its_own_right(tmp_path):
    """panda_link3's frame turned by 5° about its x, and joint 4's axis tilted by 2.5° in its own
    frame: the turn and a 2.5° axis difference, not the tilt measured on joint 3's axis (a fraction
    of it) nor joint 4's axis carried 5° off by its parent."""
    _, mjcf = P.generated_pair("panda")
    tilt = math.radians(2.5)
    mjcf = turned(mjcf, "panda_link3", [1.0, 0.0, 0.0], math.radians(5))
    mjcf = P.joint_attr(
        mjcf,
        "panda_joint4",
        "axis",
        P.nums(lambda v: list(axis_angle_to_matrix(np.array([0.0, 1.0, 0.0]), np.array([tilt]))[0] @ np.asarray(v))),
    )
    diag, errors, bodies = diagnose(tmp_path, mjcf)
    assert errors == [("axis_direction", "panda_joint4"), ("joint_origin_turned", "panda_joint3")] and bodies == []
    assert finding(diag, "axis_direction").magnitude == pytest.approx(tilt, abs=1e-9)
    assert finding(diag, "joint_origin_turned").magnitude == pytest.approx(math.radians(5), abs=1e-9)


def test_a_tilted_first_axis_is_that_axis_when_nothing_else_places_the_world(tmp_path):
    """The MJCF MuJoCo writes from the URDF (its base merged into the world, so only the joints
    place that world), joint 1's axis tilted by 0.05 rad: one axis_direction of 0.05 rad, not a
    world turned to lay that axis and joint 2's axis then blamed for it."""
    urdf, _ = P.generated_pair("panda")
    (tmp_path / "robot.urdf").write_text(urdf)
    mujoco.mj_saveLastXML(str(tmp_path / "written.xml"), mujoco.MjModel.from_xml_path(str(tmp_path / "robot.urdf")))
    mjcf = (
        (tmp_path / "written.xml")
        .read_text()
        .replace('<joint name="panda_joint1" ', f'<joint name="panda_joint1" axis="0 {-math.sin(0.05)!r} {math.cos(0.05)!r}" ', 1)
    )
    diag, errors, bodies = diagnose(tmp_path, mjcf)
    assert errors == [("axis_direction", "panda_joint1")] and bodies == []
    assert finding(diag, "axis_direction").magnitude == pytest.approx(0.05, abs=1e-9)


HAND = """<robot name="hand">
  <link name="base_link"/>
  <link name="link0"><inertial><origin xyz="0 0 0.05"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="link1"><inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="palm"><inertial><origin xyz="0 0 0.02"/><mass value="0.5"/><inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="finger"><inertial><origin xyz="0 0 0.02"/><mass value="0.1"/><inertia ixx="0.0001" iyy="0.0001" izz="0.00005" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="joint0" type="revolute"><parent link="base_link"/><child link="link0"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
  <joint name="joint1" type="revolute"><parent link="link0"/><child link="link1"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
  <joint name="palm_joint" type="fixed"><parent link="link1"/><child link="palm"/><origin xyz="0 0 0.2" rpy="0 0 -0.785398163397"/></joint>
  <joint name="finger_joint" type="prismatic"><parent link="palm"/><child link="finger"/><origin xyz="0 0 0.05"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="10" velocity="1"/></joint>
</robot>"""


def test_a_frame_below_a_moved_one_turned_by_the_written_precision_only_is_not_turned(tmp_path):
    """MuJoCo writes the fused palm as a <frame> whose quat (0.92388 0 0 -0.382683) is 6 digits:
    the finger below it sits 1.2e-6 rad off the URDF's. Link 1 moved by 5 mm: one joint_origin_moved,
    not a joint_origin_turned of 1.2e-6 rad on the finger's joint (the turn is the written precision)."""
    urdf = tmp_path / "hand.urdf"
    urdf.write_text(HAND)
    mujoco.mj_saveLastXML(str(tmp_path / "hand.xml"), mujoco.MjModel.from_xml_path(str(urdf)))
    written = (tmp_path / "hand.xml").read_text()
    assert '<frame pos="0 0 0.2" quat="0.92388 0 0 -0.382683">' in written
    (tmp_path / "moved.xml").write_text(
        written.replace('<body name="link1" pos="0 0 0.1">', '<body name="link1" pos="0.003 -0.004 0.1">')
    )
    diag = diagnose_files(str(urdf), str(tmp_path / "moved.xml"), FAST)
    errors = [(f.kind, f.subject, f.severity) for f in diag["findings"] if f.severity == "error"]
    assert errors == [("joint_origin_moved", "joint1", "error")]
    assert finding(diag, "joint_origin_moved").magnitude == pytest.approx(0.005, abs=1e-12)
    assert diag["alignment"].attribution["finger_joint"].turn is None


A1 = Path(os.environ.get("KINVERIFY_REAL_ROBOTS", REAL_ROBOTS)) / "a1" / "a1_unitree_ros.urdf"


@pytest.mark.skipif(not A1.is_file(), reason="the shared a1 is absent")
def test_a_zero_offset_that_only_stands_for_the_turned_frame_above_is_dropped(tmp_path):
    """a1's MJCF (as MuJoCo writes it, with its free joint), the rear right thigh's frame turned by
    0.0355 rad about a slanted axis (1.7° tilt, 1.1° twist): the fit takes the twist for the
    thigh's zero offset and gives the calf 3.5e-6 rad to make up the rest; once the thigh's turn is
    said whole, the calf's contents agree without it: one joint_origin_turned, no zero_offset (and
    no limit_difference it would shift) on the calf."""
    urdf = mesh_free_urdf(A1.read_text())
    (tmp_path / "a1.urdf").write_text(urdf)
    body = '<body name="RR_thigh" pos="0 -0.0838 0">'
    mjcf = mujoco_mjcf(urdf, free=True)
    assert body in mjcf
    quat = "0.9998427488604547 -0.00017301469128384606 0.00965722177766459 0.014872312685774474"
    (tmp_path / "a1.xml").write_text(mjcf.replace(body, body[:-1] + f' quat="{quat}">'))
    options = VerifyOptions(samples=4, fd_samples=1, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics", "limits"])
    result = verify_files(str(tmp_path / "a1.urdf"), str(tmp_path / "a1.xml"), options)
    errors = [f for f in result.findings if f.severity == "error"]
    assert [(f.kind, f.subject, f.severity) for f in errors] == [("joint_origin_turned", "RR_thigh_joint", "error")]
    assert errors[0].magnitude == pytest.approx(0.0354689, abs=1e-6)
