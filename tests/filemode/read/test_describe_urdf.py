"""Pinocchio's reading of a URDF, pinned on one small hand-made robot whose every number follows from
its text by hand: joint axes and anchors taken to the world through turned origins, limits (a
continuous joint and ±1e308 read as unlimited), the effort and velocity the file states (none
stated: None), a floating joint held and named, each link's inertial (a fixed link's own, a moving
link's without the fixed links Pinocchio fused into it), ``<mimic>`` couplings with their defaults
and the ``<transmission>`` gear ratio and rotor inertia Drake reads."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kinverify.filemode.read.describe_urdf import describe_urdf

INF = math.inf
DIAG = np.diag([0.01, 0.02, 0.03])  # every link's principal moments, about its centre of mass


def inertial(mass: float, xyz: str = "0 0 0", rpy: str = "0 0 0") -> str:
    return (
        f'<inertial><origin xyz="{xyz}" rpy="{rpy}"/><mass value="{mass}"/>'
        '<inertia ixx="0.01" iyy="0.02" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial>'
    )


def rot_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


# base -(fixed, +0.2 z)- mount -(j1 revolute, +0.1 z, turned +90° about z, axis x)- l1
# l1 -(fixed, +0.3 x in l1)- tool -(j2 prismatic, +0.05 z, axis -2 z)- l2 -(j3 continuous, axis y)- l3
# l3 -(j4 mimic of j1, ×-2 +0.1)- l4, l3 -(j5 mimic of j1, defaults)- l5, l3 -(j6, limits ±1e308)- l6
# base -(floating)- float; l2 -(fixed)- empty (no inertial); l2 -(fixed)- dust (1e-12 kg)
ROBOT = f"""<robot name="r" xmlns:drake="http://drake.mit.edu">
<link name="base">{inertial(0.8, "0 0 0.05")}</link>
<link name="mount">{inertial(0.5, "0.1 0 0")}</link>
<joint name="base_mount" type="fixed"><parent link="base"/><child link="mount"/><origin xyz="0 0 0.2"/></joint>
<link name="l1">{inertial(1.0, "0 0.1 0", "0 0 0.5")}</link>
<joint name="j1" type="revolute"><parent link="mount"/><child link="l1"/>
  <origin xyz="0 0 0.1" rpy="0 0 1.5707963267948966"/><axis xyz="1 0 0"/>
  <limit lower="-1" upper="2" effort="30" velocity="4"/><dynamics damping="0.2" friction="0.3"/></joint>
<link name="tool">{inertial(0.25, "0 0 0.02")}</link>
<joint name="l1_tool" type="fixed"><parent link="l1"/><child link="tool"/><origin xyz="0.3 0 0"/></joint>
<link name="l2">{inertial(0.7)}</link>
<joint name="j2" type="prismatic"><parent link="tool"/><child link="l2"/><origin xyz="0 0 0.05"/>
  <axis xyz="0 0 -2"/><limit lower="0" upper="0.1" effort="0" velocity="0"/></joint>
<link name="l3">{inertial(0.3)}</link>
<joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/><axis xyz="0 1 0"/></joint>
<link name="l4">{inertial(0.1)}</link>
<joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/><axis xyz="0 0 1"/>
  <limit lower="-0.5" upper="0.5" effort="1" velocity="1.5"/><mimic joint="j1" multiplier="-2" offset="0.1"/></joint>
<link name="l5">{inertial(0.1)}</link>
<joint name="j5" type="revolute"><parent link="l3"/><child link="l5"/><axis xyz="0 0 1"/>
  <limit lower="-0.5" upper="0.5" effort="1" velocity="1"/><mimic joint="j1"/></joint>
<link name="l6">{inertial(0.1)}</link>
<joint name="j6" type="revolute"><parent link="l3"/><child link="l6"/><axis xyz="1 0 0"/>
  <limit lower="-1e308" upper="1e308" effort="2" velocity="3"/></joint>
<link name="float">{inertial(0.2)}</link>
<joint name="free" type="floating"><parent link="base"/><child link="float"/></joint>
<link name="empty"/>
<joint name="l2_empty" type="fixed"><parent link="l2"/><child link="empty"/></joint>
<link name="dust"><inertial><mass value="1e-12"/><inertia ixx="1e-9" iyy="1e-9" izz="1e-9" ixy="0" ixz="0" iyz="0"/>
  </inertial></link>
<joint name="l3_dust" type="fixed"><parent link="l3"/><child link="dust"/><origin xyz="0 0 0.4"/></joint>
<transmission name="t1"><joint name="j1"/><actuator name="a1">
  <drake:gear_ratio value="50"/><drake:rotor_inertia value="0.001"/></actuator></transmission>
<transmission name="t2"><joint name="j2"/><actuator name="a2">
  <drake:gear_ratio value="fifty"/><drake:rotor_inertia value="0.002"/></actuator></transmission>
<transmission name="t3"><joint name="j3"/><actuator name="a3"><drake:gear_ratio/><mechanicalReduction>7</mechanicalReduction>
  </actuator></transmission>
<transmission name="t4"><actuator name="a4"><drake:gear_ratio value="3"/></actuator></transmission>
<transmission name="t5"><joint name="j6"/><actuator name="a6"><gear_ratio value="9"/></actuator></transmission>
</robot>"""

TURNED = rot_z(math.pi / 2)  # l1 and everything below it: j1's origin turns +90° about z
L1 = np.array([0.0, 0.0, 0.3])  # 0.2 (mount) + 0.1 (j1's origin)
TOOL = L1 + TURNED @ [0.3, 0.0, 0.0]  # (0, 0.3, 0.3)
L2 = TOOL + [0.0, 0.0, 0.05]  # (0, 0.3, 0.35); l3 ... l6 sit there too


@pytest.fixture  # per test: mutmut credits a call only to the test that makes it
def desc():
    return describe_urdf(ROBOT)


def joint(desc, name):
    (j,) = [j for j in desc.joints if j.name == name]
    return j


def body(desc, name):
    (b,) = [b for b in desc.bodies if b.name == name]
    return b


def test_the_description_names_its_format_and_library(desc):
    assert (desc.kind, desc.library) == ("urdf", "pinocchio")


def test_movable_joints_in_chain_order_with_parent_joint_child_and_parent_links(desc):
    assert [(j.name, j.type, j.parent, j.child, j.parent_frame) for j in desc.joints] == [
        ("j1", "revolute", None, "l1", "mount"),
        ("j2", "prismatic", "j1", "l2", "tool"),  # j1 is the nearest movable joint above tool
        ("j3", "revolute", "j2", "l3", "l2"),  # continuous: a revolute joint
        ("j4", "revolute", "j3", "l4", "l3"),
        ("j5", "revolute", "j3", "l5", "l3"),
        ("j6", "revolute", "j3", "l6", "l3"),
    ]


def test_axes_and_anchors_are_taken_to_the_world_through_the_turned_origins(desc):
    """j1: x turned +90° about z is +y; j2: -2 z normalised; j3: y of l1's turned frame is -x."""
    expected = {
        "j1": ([0, 1, 0], L1),
        "j2": ([0, 0, -1], L2),
        "j3": ([-1, 0, 0], L2),
        "j4": ([0, 0, 1], L2),
        "j6": ([0, 1, 0], L2),  # x turned +90° about z
    }
    for name, (axis, anchor) in expected.items():
        j = joint(desc, name)
        assert j.axis == pytest.approx(axis, abs=1e-12), name
        assert j.anchor == pytest.approx(anchor, abs=1e-12), name


def test_limits_a_continuous_joint_and_1e308_bounds_read_as_unlimited(desc):
    assert [(j.name, j.lower, j.upper) for j in desc.joints] == [
        ("j1", -1.0, 2.0),
        ("j2", 0.0, 0.1),
        ("j3", -INF, INF),
        ("j4", -0.5, 0.5),
        ("j5", -0.5, 0.5),
        ("j6", -INF, INF),
    ]


def test_dynamics_effort_and_velocity_as_the_urdf_states_them(desc):
    """A stated 0 is 0 (not "not stated"); a joint with no <limit> states neither (None)."""
    assert [(j.name, j.damping, j.friction, j.armature, j.effort, j.velocity) for j in desc.joints] == [
        ("j1", 0.2, 0.3, None, 30.0, 4.0),
        ("j2", 0.0, 0.0, None, 0.0, 0.0),
        ("j3", 0.0, 0.0, None, None, None),
        ("j4", 0.0, 0.0, None, 1.0, 1.5),
        ("j5", 0.0, 0.0, None, 1.0, 1.0),
        ("j6", 0.0, 0.0, None, 2.0, 3.0),
    ]
    assert joint(desc, "j1").effort_how == "URDF <limit effort>"
    assert joint(desc, "j2").effort_how == "URDF <limit effort>"
    assert joint(desc, "j3").effort_how == "no effort in the URDF"


def test_a_floating_joint_is_held_and_named_with_its_coordinates(desc):
    assert desc.held == ["free"]
    assert desc.skipped == ["free: JointModelFreeFlyer has 7 coordinates; only 1-DOF joints are compared (held at neutral)"]
    assert "free" not in [j.name for j in desc.joints]


def test_link_frames_their_owner_joint_and_depth(desc):
    """Depth counts Pinocchio's frames up to the universe: a link and the joint above it are two."""
    assert desc.frame_owner == {
        "base": None,
        "mount": None,
        "l1": "j1",
        "tool": "j1",
        "l2": "j2",
        "l3": "j3",
        "l4": "j4",
        "l5": "j5",
        "l6": "j6",
        "float": None,  # the floating joint is held: nothing movable above
        "empty": "j2",
        "dust": "j3",
    }
    assert desc.frame_depth == {
        "base": 1,
        "mount": 3,
        "l1": 5,
        "tool": 7,
        "l2": 9,
        "l3": 11,
        "l4": 13,
        "l5": 13,
        "l6": 13,
        "float": 3,
        "empty": 11,
        "dust": 13,
    }
    assert set(desc.frame_kind.values()) == {"link"} and desc.frame_kind.keys() == desc.frame_owner.keys()
    assert desc.frames["tool"][:3, :3] == pytest.approx(TURNED, abs=1e-12)
    assert desc.frames["tool"][:3, 3] == pytest.approx(TOOL, abs=1e-12)
    assert desc.frames["dust"][:3, 3] == pytest.approx(L2 + [0, 0, 0.4], abs=1e-12)
    assert desc.frames["base"] == pytest.approx(np.eye(4), abs=1e-12)


def test_each_link_with_mass_has_its_own_inertial_and_massless_ones_none(desc):
    assert [(b.name, b.owner, b.mass) for b in desc.bodies] == [
        ("base", None, 0.8),  # the root link (under 1 kg): its inertia stays on its own frame
        ("mount", None, 0.5),  # a fixed link: its own, not fused into the base
        ("l1", "j1", pytest.approx(1.0, rel=1e-12)),  # j1's inertia without the tool fused into it
        ("tool", "j1", 0.25),
        ("l2", "j2", 0.7),
        ("l3", "j3", 0.3),
        ("l4", "j4", 0.1),
        ("l5", "j5", 0.1),
        ("l6", "j6", 0.1),
        ("float", None, 0.2),
    ]  # empty (no inertial) and dust (1e-12 kg, the bound) are no inertial


def test_a_moving_links_inertial_is_its_own_once_the_fused_fixed_link_is_removed(desc):
    """l1 states its CoM at (0, 0.1, 0) and its principal axes turned 0.5 rad about z."""
    l1 = body(desc, "l1")
    turned = rot_z(0.5) @ DIAG @ rot_z(0.5).T
    assert l1.com_local == pytest.approx([0.0, 0.1, 0.0], abs=1e-12)
    assert l1.inertia_local == pytest.approx(turned, abs=1e-12)
    assert l1.com == pytest.approx(L1 + TURNED @ [0.0, 0.1, 0.0], abs=1e-12)  # (-0.1, 0, 0.3)
    assert l1.inertia == pytest.approx(TURNED @ turned @ TURNED.T, abs=1e-12)


def test_fixed_links_keep_their_inertial_in_their_own_frame(desc):
    mount, tool, base = body(desc, "mount"), body(desc, "tool"), body(desc, "base")
    assert mount.com_local == pytest.approx([0.1, 0.0, 0.0], abs=1e-12)
    assert mount.com == pytest.approx([0.1, 0.0, 0.2], abs=1e-12)
    assert tool.com_local == pytest.approx([0.0, 0.0, 0.02], abs=1e-12)
    assert tool.com == pytest.approx(TOOL + [0.0, 0.0, 0.02], abs=1e-12)
    assert tool.inertia_local == pytest.approx(DIAG, abs=1e-12)
    assert tool.inertia == pytest.approx(TURNED @ DIAG @ TURNED.T, abs=1e-12)  # diag(0.02, 0.01, 0.03)
    assert base.com == pytest.approx([0.0, 0.0, 0.05], abs=1e-12) and base.inertia == pytest.approx(DIAG, abs=1e-12)


def test_mimic_couplings_with_their_multiplier_offset_and_defaults(desc):
    assert [(c.follower, c.leader, c.multiplier, c.offset, c.source) for c in desc.couplings] == [
        ("j4", "j1", -2.0, 0.1, "<mimic>"),
        ("j5", "j1", 1.0, 0.0, "<mimic>"),
    ]


def test_transmission_gear_ratio_and_rotor_inertia_are_kept_for_drake(desc):
    """A value that is no number is dropped (the rest of that transmission kept); a tag with no
    value, other tags and a transmission naming no joint give nothing; a tag with no namespace counts."""
    assert desc.extensions == {
        "j1": {"gear_ratio": 50.0, "rotor_inertia": 0.001},
        "j2": {"rotor_inertia": 0.002},
        "j6": {"gear_ratio": 9.0},
    }


def test_a_robot_with_no_inertial_fused_reads_each_link_from_its_joint():
    """A single moving link with no fixed link below: its inertial is its joint's, none subtracted."""
    text = f"""<robot name="one"><link name="a"/><link name="b">{inertial(3.0, "0.2 0 0")}</link>
      <joint name="j" type="prismatic"><parent link="a"/><child link="b"/><origin xyz="1 2 3"/><axis xyz="0 1 0"/>
      <limit lower="-0.2" upper="0.4" effort="5" velocity="0.5"/></joint></robot>"""
    d = describe_urdf(text)
    (b,) = d.bodies
    assert (b.name, b.owner, b.mass) == ("b", "j", 3.0)
    assert b.com == pytest.approx([1.2, 2.0, 3.0], abs=1e-12) and b.inertia == pytest.approx(DIAG, abs=1e-12)
    (j,) = d.joints
    assert (j.type, j.parent, j.parent_frame, j.lower, j.upper) == ("prismatic", None, "a", -0.2, 0.4)
    assert j.anchor == pytest.approx([1, 2, 3], abs=1e-12) and j.axis == pytest.approx([0, 1, 0], abs=1e-12)
    assert d.held == [] and d.skipped == [] and d.couplings == [] and d.extensions == {}
