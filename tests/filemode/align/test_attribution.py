"""Attribution: each rule pinned by the smallest planted change where it and its nearest wrong
variant disagree. A joint frame moved along its axis is one finding with the full vector (not an
axis finding for the part across it and centres of mass for the rest); a frame turned about
another axis than its joint's is one finding with that axis and angle (not a tilt of the axis and
the twist left to the centres of mass); a tilt below a turned parent is measured in its own right
(not on its parent's axis); what a moved frame carries is compared in that frame; a first axis
tilted where nothing but the joints places the MJCF's world is that axis, not a turned world."""

from __future__ import annotations

import dataclasses
import math
import os
from pathlib import Path

import mujoco
import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.filemode.align.attribution import Attribution, _merged_base, attribute, findings_count
from kinverify.filemode.align.match import Matching
from kinverify.filemode.align.result import Alignment, JointMap
from kinverify.filemode.compare.context import FileModeInfo
from kinverify.filemode.compare.inertials import analyse
from kinverify.filemode.pipeline import diagnose_files, verify_files
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.filemode.read.precision import Floors
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


# --- each decision of attribute() on a small three-joint arm, described by the readers and laid out by hand ---
#
# base_link -> j1 (z, l1 turned 90° about z) -> l2 -> j2 (y) -> l3 -> j3 (y) -> tool (a fixed link, the MJCF's site).
# Both files at their own zero, the alignment the identity unless a test says otherwise.

URDF_INERTIA = 'ixx="0.02" iyy="0.03" izz="0.04" ixy="0" ixz="0" iyz="0"'
NAMES = ["j1", "j2", "j3"]


def urdf_link(name: str, mass: float = 1.0) -> str:
    return (
        f'<link name="{name}"><inertial><origin xyz="0.02 0 0.1"/><mass value="{mass!r}"/>'
        f"<inertia {URDF_INERTIA}/></inertial></link>"
    )


def urdf_joint(name: str, parent: str, child: str, origin: str, axis: str) -> str:
    return (
        f'<joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/>{origin}'
        f'<axis xyz="{axis}"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>'
    )


def small_urdf(base: str = '<link name="base_link"/>') -> str:
    return (
        f'<robot name="r">{base}{urdf_link("l1")}{urdf_link("l2")}{urdf_link("l3", 4.0)}<link name="tool"/>'
        + urdf_joint("j1", "base_link", "l1", '<origin xyz="0 0 0.1" rpy="0 0 1.5707963267948966"/>', "0 0 1")
        + urdf_joint("j2", "l1", "l2", '<origin xyz="0 0 0.3"/>', "0 1 0")
        + urdf_joint("j3", "l2", "l3", '<origin xyz="0 0 0.3"/>', "0 1 0")
        + '<joint name="tool_joint" type="fixed"><parent link="l3"/><child link="tool"/><origin xyz="0 0 0.2"/></joint>'
        "</robot>"
    )


def small_body(
    name: str,
    inner: str,
    pos="0 0 0.3",
    quat="1 0 0 0",
    axis="0 1 0",
    jpos="0 0 0",
    ipos="0.02 0 0.1",
    mass="1",
    inertia='diaginertia="0.02 0.03 0.04"',
) -> str:
    return (
        f'<body name="{name}" pos="{pos}" quat="{quat}"><joint name="j{name[1]}" axis="{axis}" pos="{jpos}" range="-2 2"/>'
        f'<inertial pos="{ipos}" mass="{mass}" {inertia}/>{inner}</body>'
    )


def small_mjcf(l1=None, l2=None, l3=None, site="0 0 0.2", base_pos="0 0 0") -> str:
    c = repr(math.cos(math.pi / 4))
    b3 = small_body("l3", f'<site name="tool" pos="{site}"/>', **{"mass": "4", **(l3 or {})})
    b2 = small_body("l2", b3, **(l2 or {}))
    b1 = small_body("l1", b2, **{"pos": "0 0 0.1", "quat": f"{c} 0 0 {c}", "axis": "0 0 1", **(l1 or {})})
    return f'<mujoco><worldbody><body name="base_link" pos="{base_pos}">{b1}</body></worldbody></mujoco>'


def words(v) -> str:
    return " ".join(repr(float(x)) for x in v)


def small_info(mjcf: str, urdf: str | None = None, sign=None, offset=None, floors=None, poses_m=None) -> FileModeInfo:
    u, m = describe_urdf(urdf or small_urdf()), describe_mjcf(mjcf)
    matching = Matching([(n, n, "name") for n in NAMES], [], [], [(f, f, "name") for f in u.frames if f in m.frames])
    joints = [JointMap(n, n, "revolute", (sign or {}).get(n, 1), (offset or {}).get(n, 0.0)) for n in NAMES]
    info = FileModeInfo(u, m, matching, Alignment(np.eye(4), joints, {}, NAMES), floors=floors or Floors())
    info.poses_u, info.poses_m = dict(u.frames), dict(poses_m or m.frames)
    return info


def attributed(info: FileModeInfo) -> dict[str, Attribution]:
    info.alignment.attribution = attribute(info)
    return info.alignment.attribution


def turned_about(poses: dict, frames: list[str], axis, point, angle: float) -> dict:
    """``poses`` with ``frames`` turned by ``angle`` about the world line (``axis``, ``point``): a joint at ``angle``."""
    motion = np.eye(4)
    motion[:3, :3] = axis_angle_to_matrix(np.asarray(axis, float), np.array([angle]))[0]
    motion[:3, 3] = point - motion[:3, :3] @ point
    return {k: motion @ v if k in frames else v for k, v in poses.items()}


def unchanged(att: Attribution) -> bool:
    return att.moved is None and att.turn is None and att.contents == 0 and not att.changed


def test_identical_files_attribute_nothing():
    info = small_info(small_mjcf())
    out = attributed(info)
    assert list(out) == NAMES
    for name, parent in zip(NAMES, ["", "l1", "l2"], strict=True):
        att = out[name]
        assert unchanged(att) and att.parent_frame == parent and att.merged_base == "" and not att.base_placed
        assert att.carry == pytest.approx(np.eye(4), abs=1e-12) and att.axis == pytest.approx((0.0, 0.0), abs=1e-12)
    assert findings_count(info) == 0


def test_a_moved_frame_is_its_joint_s_difference_in_its_parent_link_s_axes():
    # l2 moved by (3, 4, 0) mm in l1's axes; l1 is turned 90° about z, so the world offset is (-4, 3, 0) mm
    info = small_info(small_mjcf(l2={"pos": "0.003 0.004 0.3"}))
    out = attributed(info)
    assert out["j2"].moved == pytest.approx([0.003, 0.004, 0.0], abs=1e-12) and out["j2"].turn is None
    assert out["j2"].changed and out["j2"].contents == 0
    assert out["j2"].carry[:3, 3] == pytest.approx([0.004, -0.003, 0.0], abs=1e-12)
    # what j2 carries moves with it: j3 inherits the carry and has nothing of its own
    assert unchanged(out["j3"]) and out["j3"].carry == pytest.approx(out["j2"].carry, abs=1e-15)
    assert unchanged(out["j1"])
    assert findings_count(info) == 1


def test_a_turned_frame_is_one_turn_with_its_tilt_and_twist():
    # l2 turned by 0.1 rad about (1, 1, 0)/√2 of its own axes; joint 2's axis is the body's y
    n = np.array([1.0, 1.0, 0.0]) / math.sqrt(2)
    q = [math.cos(0.05), *(math.sin(0.05) * n)]
    info = small_info(small_mjcf(l2={"quat": words(q)}))
    out = attributed(info)
    att = out["j2"]
    assert att.moved is None and att.turn == pytest.approx(0.1 * n, abs=1e-12)
    turned_y = axis_angle_to_matrix(n, np.array([0.1]))[0] @ [0.0, 1.0, 0.0]
    tilt = math.acos(turned_y[1])
    twist = 2 * math.atan2(math.sin(0.05) / math.sqrt(2), math.cos(0.05))
    assert att.tilt_twist == pytest.approx((tilt, twist), abs=1e-9)
    assert att.folded == 0.0 and att.contents == 0 and att.axis == pytest.approx((0.0, 0.0), abs=1e-12)
    assert unchanged(out["j3"]) and out["j3"].carry == pytest.approx(att.carry, abs=1e-15)
    assert findings_count(info) == 1


def test_a_turn_against_the_joint_s_sense_gives_a_positive_twist():
    n = np.array([0.0, -1.0, 1.0]) / math.sqrt(2)
    q = [math.cos(0.05), *(math.sin(0.05) * n)]
    att = attributed(small_info(small_mjcf(l2={"quat": words(q)})))["j2"]
    assert att.tilt_twist[1] == pytest.approx(2 * math.atan2(math.sin(0.05) / math.sqrt(2), math.cos(0.05)), abs=1e-9)


def test_a_frame_turned_with_a_zero_offset_the_fit_took_is_one_turn_with_the_offset_folded():
    # l2 turned by 0.1 rad about (1, 1, 0)/√2; the fit took 0.03 rad of it for joint 2's zero offset, so the
    # MJCF's frames below j2 sit turned by 0.03 about j2's axis line at the aligned zero
    n = np.array([1.0, 1.0, 0.0]) / math.sqrt(2)
    mjcf = small_mjcf(l2={"quat": words([math.cos(0.05), *(math.sin(0.05) * n)])})
    m = describe_mjcf(mjcf)
    j2 = m.joint("j2")
    poses = turned_about(m.frames, ["l2", "l3", "tool"], j2.axis, j2.anchor, 0.03)
    info = small_info(mjcf, offset={"j2": 0.03}, poses_m=poses)
    out = attributed(info)
    att = out["j2"]
    assert att.folded == 0.03 and info.alignment.joint("j2").offset == 0.0
    assert att.turn == pytest.approx(0.1 * n, abs=1e-12) and att.moved is None
    assert att.contents == 0 and unchanged(out["j3"])
    assert findings_count(info) == 1  # the turn; the offset is part of it


def test_a_frame_turned_about_its_own_axis_with_its_contents_turned_back_is_the_files_choice():
    # l3's frame turned 0.3 rad about its joint's axis (y), its inertial and site turned back: no difference
    back = axis_angle_to_matrix(np.array([0.0, 1.0, 0.0]), np.array([-0.3]))[0]
    inertia = back @ np.diag([0.02, 0.03, 0.04]) @ back.T
    full = [inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1], inertia[0, 2], inertia[1, 2]]
    l3 = {
        "quat": words([math.cos(0.15), 0.0, math.sin(0.15), 0.0]),
        "ipos": words(back @ [0.02, 0.0, 0.1]),
        "inertia": f'fullinertia="{words(full)}"',
    }
    info = small_info(small_mjcf(l3=l3, site=words(back @ [0.0, 0.0, 0.2])))
    out = attributed(info)
    assert all(unchanged(out[n]) for n in NAMES)
    assert out["j3"].axis == pytest.approx((0.0, 0.0), abs=1e-9)
    assert findings_count(info) == 0


def test_a_frame_moved_with_its_contents_moved_back_is_the_files_choice():
    # l3's origin 1 cm further along its axis (y), the joint, inertial and site moved back: nothing differs
    l3 = {"pos": "0 0.01 0.3", "jpos": "0 -0.01 0", "ipos": "0.02 -0.01 0.1"}
    info = small_info(small_mjcf(l3=l3, site="0 -0.01 0.2"))
    out = attributed(info)
    assert all(unchanged(out[n]) for n in NAMES) and findings_count(info) == 0


def test_a_moved_frame_whose_contents_differ_in_its_own_axes_is_not_taken():
    # l3 moved 1 cm across its axis (l3's x, the world's y) and its centre of mass moved back: not one moved
    # frame (the centre of mass differs in l3's axes) but an axis line 1 cm off, what it carries seated on it
    # (its site agrees then), and the centre of mass
    info = small_info(small_mjcf(l3={"pos": "0.01 0 0.3", "ipos": "0.01 0 0.1"}))
    att = attributed(info)["j3"]
    assert att.moved is None and att.turn is None
    assert att.axis == pytest.approx((0.0, 0.01), abs=1e-12)
    assert att.carry[:3, 3] == pytest.approx([0.0, -0.01, 0.0], abs=1e-12)
    assert att.contents == 1


def test_an_axis_tilted_within_its_frame_is_an_axis_difference_only():
    info = small_info(small_mjcf(l2={"axis": f"0 {math.cos(0.05)!r} {math.sin(0.05)!r}"}))
    out = attributed(info)
    assert out["j2"].axis == pytest.approx((0.05, 0.0), abs=1e-12)
    assert unchanged(out["j2"]) and out["j2"].carry == pytest.approx(np.eye(4), abs=1e-12)
    assert unchanged(out["j3"])
    assert findings_count(info) == 1


def test_an_axis_line_moved_alone_keeps_the_parent_s_carry():
    info = small_info(small_mjcf(l2={"jpos": "0.005 0 0"}))
    out = attributed(info)
    assert out["j2"].axis == pytest.approx((0.0, 0.005), abs=1e-12)
    assert unchanged(out["j2"]) and out["j2"].carry == pytest.approx(np.eye(4), abs=1e-12)
    assert findings_count(info) == 1


def test_an_axis_line_moved_with_what_it_carries_is_seated_on_it():
    # j3's axis, centre of mass and site all 5 mm along l3's x (world y): its body seated on the axis
    info = small_info(small_mjcf(l3={"jpos": "0.005 0 0", "ipos": "0.025 0 0.1"}, site="0.005 0 0.2"))
    att = attributed(info)["j3"]
    assert att.axis == pytest.approx((0.0, 0.005), abs=1e-12)
    assert att.carry[:3, 3] == pytest.approx([0.0, -0.005, 0.0], abs=1e-12)
    assert att.carry[:3, :3] == pytest.approx(np.eye(3), abs=1e-12)
    assert att.contents == 0 and att.moved is None and att.turn is None
    assert findings_count(info) == 1


@pytest.mark.parametrize(
    ("l3", "site", "contents"),
    [
        ({"ipos": "0.02 0.001 0.1"}, "0 0 0.2", 1),  # centre of mass
        ({}, "0 0.001 0.2", 1),  # site
        ({"ipos": "0.02 0.001 0.1"}, "0 0.001 0.2", 2),
        ({"inertia": 'diaginertia="0.02 0.03 0.041"'}, "0 0 0.2", 1),  # tensor, same mass
        ({"mass": "4.002", "inertia": 'diaginertia="0.02 0.03 0.041"'}, "0 0 0.2", 1),  # mass within 1e-3: tensor compared
        ({"mass": "4.01", "inertia": 'diaginertia="0.02 0.03 0.041"'}, "0 0 0.2", 0),  # another mass: tensor not compared
    ],
)
def test_contents_that_still_differ_after_the_carry(l3, site, contents):
    info = small_info(small_mjcf(l3=l3, site=site))
    out = attributed(info)
    assert out["j3"].contents == contents and out["j3"].moved is None and out["j3"].turn is None
    assert out["j2"].contents == 0
    assert findings_count(info) == contents


def test_a_tensor_within_its_orientation_tolerance_agrees():
    # tolerance: (1e-9 + 2·(1e-6 rad + 1e-9)) of the largest principal moment (0.04); half of it agrees, twice not
    tol = (1e-9 + 2 * (1e-6 + 1e-9)) * 0.04
    for change, contents in ((0.5 * tol, 0), (2.0 * tol, 1)):
        info = small_info(small_mjcf(l3={"inertia": f'diaginertia="0.02 0.03 {0.04 + change!r}"'}))
        assert attributed(info)["j3"].contents == contents


def test_the_written_precision_widens_the_content_tolerances():
    # floors: 0.1 mm for centres of mass (twice, plus the rotation tolerance times the lever arm), 1 % of a tensor
    com = small_mjcf(l3={"ipos": "0.02 0.00015 0.1"})
    assert attributed(small_info(com, floors=Floors(com=1e-4)))["j3"].contents == 0
    assert attributed(small_info(com, floors=Floors(com=0.5e-4)))["j3"].contents == 1
    tensor = small_mjcf(l3={"inertia": 'diaginertia="0.02 0.03 0.0404"'})  # 4e-4 off: 1 % of 0.04
    assert attributed(small_info(tensor, floors=Floors(relative=0.011)))["j3"].contents == 0
    assert attributed(small_info(tensor, floors=Floors(relative=0.009)))["j3"].contents == 1
    assert attributed(small_info(tensor, floors=Floors(inertial_angle=0.0055)))["j3"].contents == 0
    assert attributed(small_info(tensor, floors=Floors(inertial_angle=0.0045)))["j3"].contents == 1


def test_a_frame_floor_hides_a_move_within_it():
    mjcf = small_mjcf(l2={"pos": "0.0003 0 0.3"})
    assert attributed(small_info(mjcf, floors=Floors(frames={"l2": (2e-4, 0.0)})))["j2"].moved is None
    moved = attributed(small_info(mjcf, floors=Floors(frames={"l2": (1e-4, 0.0)})))["j2"].moved
    assert moved == pytest.approx([0.0003, 0.0, 0.0], abs=1e-12)


def test_a_flipped_axis_is_compared_with_its_sign():
    info = small_info(small_mjcf(l2={"axis": "0 -1 0"}), sign={"j2": -1})
    out = attributed(info)
    assert out["j2"].axis == pytest.approx((0.0, 0.0), abs=1e-12) and all(unchanged(out[n]) for n in NAMES)
    assert findings_count(info) == 1  # the sign flip
    info = small_info(small_mjcf(l2={"axis": "0 -1 0"}))
    assert attributed(info)["j2"].axis[0] == pytest.approx(math.pi, abs=1e-12)


def offset_case(turned: bool, ipos: str = "0.02 0.001 0.1") -> FileModeInfo:
    """j2's frame moved 5 mm and the fit gave j3 a zero offset of 0.02 rad; the MJCF's l3 at the aligned
    zero is where that offset turns it (``turned``: the MJCF's own zero agrees with the URDF's, the offset is
    not needed) or where the URDF's is (its zero truly differs); l3's centre of mass differs either way (so
    no frame change of j3 takes the turn)."""
    mjcf = small_mjcf(l2={"pos": "0.003 0.004 0.3"}, l3={"ipos": ipos})
    m = describe_mjcf(mjcf)
    poses = turned_about(m.frames, ["l3", "tool"], m.joint("j3").axis, m.joint("j3").anchor, 0.02) if turned else None
    return small_info(mjcf, offset={"j3": 0.02}, poses_m=poses)


def test_a_zero_offset_standing_only_for_the_frame_above_is_dropped():
    info = offset_case(turned=True)
    out = attributed(info)
    assert out["j2"].moved is not None and info.alignment.joint("j3").offset == 0.0
    att = out["j3"]
    assert att.moved is None and att.turn is None and att.folded == 0.0
    assert att.contents == 1 and att.axis == pytest.approx((0.0, 0.0), abs=1e-12)
    # the carry turns the MJCF's l3 back by the offset about its axis line: its site lands on the URDF's
    assert att.carry @ info.poses_m["tool"] == pytest.approx(info.poses_u["tool"], abs=1e-12)
    assert findings_count(info) == 2  # the moved frame and l3's centre of mass


def test_a_zero_offset_the_body_below_needs_is_kept():
    info = offset_case(turned=False)
    out = attributed(info)
    assert info.alignment.joint("j3").offset == 0.02 and out["j3"].contents == 1
    assert out["j3"].carry == pytest.approx(out["j2"].carry, abs=1e-15)
    assert findings_count(info) == 3  # the moved frame, the offset, the centre of mass
    # a prismatic joint's offset is never taken for a turn
    info = offset_case(turned=True)
    info.alignment.joint("j3").type = "prismatic"
    attributed(info)
    assert info.alignment.joint("j3").offset == 0.02


def test_an_offset_turning_the_whole_body_below_a_moved_frame_is_folded_into_its_frame():
    # as above with l3's contents agreeing: j3's frame change takes the offset's turn and leaves nothing
    info = offset_case(turned=True, ipos="0.02 0 0.1")
    att = attributed(info)["j3"]
    assert info.alignment.joint("j3").offset == 0.0 and att.folded == 0.02
    assert att.moved is None and att.turn is None and att.contents == 0
    assert findings_count(info) == 1


def test_a_world_transform_and_base_frames_that_differ_are_counted():
    info = small_info(small_mjcf())
    t = np.eye(4)
    t[:3, 3] = [0.0, 0.0, 1e-6]
    info.alignment.T = t
    info.poses_m = {k: t @ v for k, v in info.poses_m.items()}
    assert all(unchanged(a) for a in attributed(info).values())
    assert findings_count(info) == 1
    turned = np.eye(4)
    turned[:3, :3] = axis_angle_to_matrix(np.array([0.0, 0.0, 1.0]), np.array([1e-6]))[0]
    info.alignment.T = turned
    info.poses_m = {k: turned @ v for k, v in small_info(small_mjcf()).poses_m.items()}
    assert findings_count(info) == 1
    # the MJCF's fixed base 1 cm higher, the world the identity: j1's frame moved, and the base frame differs
    info = small_info(small_mjcf(base_pos="0 0 0.01"))
    out = attributed(info)
    assert out["j1"].moved == pytest.approx([0.0, 0.0, 0.01], abs=1e-12)
    assert findings_count(info) == 2


def test_a_first_joint_hanging_from_a_base_link_the_mjcf_merges_into_its_world():
    # the URDF places base_link 0.5 m up through a fixed joint from world; MuJoCo's world holds l1 directly
    placed = '<link name="world"/><joint name="w" type="fixed"><parent link="world"/><child link="base_link"/><origin xyz="0 0 0.5"/></joint><link name="base_link"/>'
    mjcf = (
        small_mjcf(base_pos="0 0 0.5")
        .replace('<body name="base_link" pos="0 0 0.5">', "")
        .replace("</body></worldbody>", "</worldbody>")
    )
    mjcf = mjcf.replace('<body name="l1" pos="0 0 0.1"', '<body name="l1" pos="0 0 0.6"')
    out = attributed(small_info(mjcf, urdf=small_urdf(placed)))
    assert (out["j1"].merged_base, out["j1"].base_placed) == ("base_link", True)
    assert out["j2"].merged_base == "" and not out["j2"].base_placed
    mjcf = small_mjcf().replace('<body name="base_link" pos="0 0 0">', "").replace("</body></worldbody>", "</worldbody>")
    out = attributed(small_info(mjcf))
    assert (out["j1"].merged_base, out["j1"].base_placed) == ("base_link", False)


def test_a_joint_without_poses_is_left_out():
    info = small_info(small_mjcf())
    del info.poses_u["l3"]
    assert list(attributed(info)) == ["j1", "j2"]
    info = small_info(small_mjcf())
    del info.poses_m["l2"]
    assert list(attributed(info)) == ["j1", "j3"]


def test_a_joint_matched_in_neither_file_is_held_and_its_child_hangs_from_the_one_above():
    # j2 not matched: j3 is attributed after j1, whose frame it does not hang from directly (no frame change taken)
    info = small_info(small_mjcf(l2={"pos": "0.003 0.004 0.3"}))
    info.alignment.joints = [x for x in info.alignment.joints if x.urdf != "j2"]
    info.matching.joints = [x for x in info.matching.joints if x[0] != "j2"]
    out = attributed(info)
    assert list(out) == ["j1", "j3"]
    assert out["j3"].parent_frame == "l1" and out["j3"].moved is None
    # j3's axis line (world -x) moved with l2 by (-4, 3, 0) mm: 3 mm across it
    assert out["j3"].axis[1] == pytest.approx(0.003, abs=1e-12)


def test_a_body_without_mass_has_no_inertial_to_compare():
    info = small_info(small_mjcf(l3={"ipos": "0.02 0.001 0.1"}))
    for b in info.m.bodies:
        if b.name == "l3":
            b.mass = 0.0
    assert attributed(info)["j3"].contents == 0
    info = small_info(small_mjcf(l3={"ipos": "0.02 0.001 0.1"}))
    info.u.bodies = [b for b in info.u.bodies if b.name != "l3"]
    assert attributed(info)["j3"].contents == 0


def test_only_an_mjcf_site_counts_among_a_body_s_contents():
    # the tool as a fixed MJCF body moved 1 mm: a frame of its own (compared elsewhere), not the joint's contents
    mjcf = small_mjcf(site="0 0.001 0.2").replace(
        '<site name="tool" pos="0 0.001 0.2"/>', '<body name="tool" pos="0 0.001 0.2"/>'
    )
    info = small_info(mjcf)
    assert info.m.frame_kind["tool"] == "link" and info.m.frame_owner["tool"] == "j3"
    assert attributed(info)["j3"].contents == 0


def test_a_turned_base_frame_is_counted_once():
    # the MJCF's fixed base turned 0.01 rad about z under the identity alignment: j1's frame turns with it
    # (j1's one turn) and the base frame itself sits turned (one more)
    quat = f"{math.cos(0.005)!r} 0 0 {math.sin(0.005)!r}"
    info = small_info(small_mjcf().replace('pos="0 0 0">', f'pos="0 0 0" quat="{quat}">', 1))
    out = attributed(info)
    assert out["j1"].turn == pytest.approx([0.0, 0.0, 0.01], abs=1e-12) and out["j1"].moved is None
    assert findings_count(info) == 2
    del info.poses_m["base_link"]  # a base frame without a pose is not compared
    assert findings_count(info) == 1


def test_a_frame_s_rotation_floor_widens_its_contents_by_their_lever_arm():
    # l3's rotation floor 1e-3 rad (twice: 2e-3): its centre of mass, 0.102 m from l3's origin, may sit 2.04e-4 m
    # off; its tensor 2·2e-3 of 0.04 = 1.6e-4 off
    floors = Floors(frames={"l3": (0.0, 1e-3)})
    lever = math.hypot(0.02, 0.1)
    assert 2e-3 * lever == pytest.approx(2.04e-4, rel=1e-2)
    for dy, contents in ((1.5e-4, 0), (2.5e-4, 1)):
        mjcf = small_mjcf(l3={"ipos": f"0.02 {dy!r} 0.1"})
        assert attributed(small_info(mjcf, floors=floors))["j3"].contents == contents
        assert attributed(small_info(mjcf))["j3"].contents == 1
    for dz, contents in ((1e-4, 0), (2e-4, 1)):
        mjcf = small_mjcf(l3={"inertia": f'diaginertia="0.02 0.03 {0.04 + dz!r}"'})
        assert attributed(small_info(mjcf, floors=floors))["j3"].contents == contents
        assert attributed(small_info(mjcf))["j3"].contents == 1


@pytest.mark.parametrize(
    ("link", "in_mjcf", "mjcf_parent", "merged"),
    [
        ("base_link", False, "world", "base_link"),
        ("base_link", False, "", "base_link"),
        ("base_link", True, "world", ""),  # the MJCF has the link's frame
        ("base_link", False, "torso", ""),  # the MJCF's joint hangs from a frame of its own
        ("world", False, "world", ""),
        ("", False, "world", ""),
    ],
)
def test_merged_base(link, in_mjcf, mjcf_parent, merged):
    u, m = describe_urdf(small_urdf()), describe_mjcf(small_mjcf())
    ju, jm = dataclasses.replace(u.joint("j1"), parent_frame=link), dataclasses.replace(m.joint("j1"), parent_frame=mjcf_parent)
    if not in_mjcf:
        m.frames.pop("base_link")
    assert _merged_base(u, m, ju, jm) == merged


def test_findings_count_counts_a_flip_and_an_offset_without_an_attribution():
    info = small_info(small_mjcf(), sign={"j2": -1}, offset={"j3": 0.1})
    info.alignment.attribution = {}
    assert findings_count(info) == 2


def test_a_twist_only_the_next_axis_shows_is_read_from_it():
    # l2 holds a ball on its own axis (a centre on y, one inertia every way): only j3's axis, 0.3 m
    # along l2's z, shows l2's frame twisted 0.1 rad about joint 2's axis
    ball = (
        '<inertial><origin xyz="0 0.05 0"/><mass value="1.0"/><inertia ixx="0.03" iyy="0.03" izz="0.03" ixy="0" ixz="0" iyz="0"/>'
    )
    urdf = small_urdf().replace(urdf_link("l2"), f'<link name="l2">{ball}</inertial></link>')
    twist = [math.cos(0.05), 0.0, math.sin(0.05), 0.0]
    l2 = {"quat": words(twist), "ipos": "0 0.05 0", "inertia": 'diaginertia="0.03 0.03 0.03"'}
    out = attributed(small_info(small_mjcf(l2=l2), urdf))
    assert out["j2"].moved is None and out["j2"].turn == pytest.approx([0.0, 0.1, 0.0], abs=1e-9)
    assert unchanged(out["j3"]) and unchanged(out["j1"])
