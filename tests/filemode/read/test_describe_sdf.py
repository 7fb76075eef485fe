"""Drake's reading of an SDFormat file: each joint's damping and armature (Drake's reflected
inertia) as the file states them, its axis taken to the world by its joint frame's rotation, and
file mode naming an SDF joint whose damping differs from the URDF's. Skipped without Drake."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("pydrake")

from kinverify.filemode.pipeline import verify_files  # noqa: E402
from kinverify.filemode.read.describe_sdf import describe_sdf  # noqa: E402
from kinverify.errors import BackendError  # noqa: E402
from kinverify.filemode.read.model import INF  # noqa: E402
from kinverify.generate import generate_sdf, generate_urdf  # noqa: E402
from kinverify.model.specfile import load_spec  # noqa: E402
from kinverify.run import VerifyOptions  # noqa: E402
from tests.paths import MODELS  # noqa: E402

FAST = VerifyOptions(samples=8, fd_samples=4, extra={"dynamics_samples": 8})


@pytest.fixture(scope="module")
def arm3() -> tuple[str, str]:
    """The generated arm3 URDF and SDF (damping 0.1 and armature 0.01 on every joint)."""
    spec = load_spec(MODELS / "arm3.toml")
    return generate_urdf(spec), generate_sdf(spec)


def damped(sdf: str, joint_index: int, value: float) -> str:
    """The SDF with the ``joint_index``-th joint's (0-based, chain order) damping set to ``value``."""
    parts = sdf.split("<damping>")
    assert len(parts) == 4
    head, rest = parts[joint_index + 1].split("</damping>", 1)
    parts[joint_index + 1] = f"{value!r}</damping>{rest}"
    return "<damping>".join(parts)


def test_damping_and_armature_are_read_as_the_sdf_states_them(arm3):
    desc = describe_sdf(damped(arm3[1], 1, 0.3))
    assert [(j.name, j.damping, j.armature, j.friction) for j in desc.joints] == [
        ("joint1", 0.1, 0.01, None),
        ("joint2", 0.3, 0.01, None),
        ("joint3", 0.1, 0.01, None),
    ]


def test_a_joint_axis_is_taken_to_the_world_by_its_frame_rotation():
    """A joint frame turned +90° about z with its axis along the frame's x: in the world, +y (the
    inverse rotation would give -y, the same line the other way round)."""
    sdf = f"""<?xml version="1.0"?><sdf version="1.9"><model name="m">
      <joint name="weld" type="fixed"><parent>world</parent><child>base</child></joint>
      <link name="base"><inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz>
        </inertia></inertial></link>
      <joint name="j" type="revolute"><pose relative_to="base">0 0 0.1 0 0 {math.pi / 2!r}</pose>
        <parent>base</parent><child>arm</child>
        <axis><xyz>1 0 0</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint>
      <link name="arm"><pose relative_to="j"/><inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy>
        <izz>0.01</izz></inertia></inertial></link>
    </model></sdf>"""
    (j,) = describe_sdf(sdf).joints
    assert np.allclose(j.axis, [0.0, 1.0, 0.0], atol=1e-12), j.axis
    assert np.allclose(j.anchor, [0.0, 0.0, 0.1], atol=1e-12)


def test_an_sdf_damping_other_than_the_urdfs_fails_naming_the_joint_and_the_size(tmp_path, arm3):
    urdf, sdf = arm3
    (tmp_path / "arm3.urdf").write_text(urdf)
    (tmp_path / "arm3.sdf").write_text(damped(sdf, 1, 0.3))
    result = verify_files(str(tmp_path / "arm3.urdf"), str(tmp_path / "arm3.sdf"), FAST, kinds=("urdf", "sdf"))
    failing = [f for f in result.findings if f.fails]
    assert result.verdict == "fail" and [(f.kind, f.subject, f.severity) for f in failing] == [
        ("damping_difference", "joint2", "error")
    ]
    assert failing[0].magnitude == pytest.approx(0.2, abs=1e-12) and failing[0].unit == "N·m·s/rad"
    assert "0.1 in the URDF, 0.3 in the SDF" in failing[0].message


def test_an_sdf_whose_damping_agrees_with_the_urdfs_passes(tmp_path, arm3):
    urdf, sdf = arm3
    (tmp_path / "arm3.urdf").write_text(urdf)
    (tmp_path / "arm3.sdf").write_text(sdf)
    result = verify_files(str(tmp_path / "arm3.urdf"), str(tmp_path / "arm3.sdf"), FAST, kinds=("urdf", "sdf"))
    assert result.verdict == "pass" and not result.internal_errors
    assert not [f for f in result.findings if "damping" in f.kind]
    (armature,) = [f for f in result.findings if f.kind == "inexpressible" and f.property == "dynamics.armature"]
    assert armature.severity == "warning" and armature.magnitude == pytest.approx(0.01)  # the SDF's, a URDF has none


def _link(name: str, mass: float, inertial_pose: str, pose: str) -> str:
    return (
        f'<link name="{name}"><pose relative_to="{pose}"/><inertial><pose>{inertial_pose}</pose><mass>{mass}</mass>'
        "<inertia><ixx>0.01</ixx><iyy>0.02</iyy><izz>0.03</izz></inertia></inertial></link>"
    )


# base -(j1 revolute, +0.1 z turned +90° about z, axis x, rotor 0.001 × gear 10)- l1 -(j2 prismatic, +0.3 x in
# l1, no limit)- l2 -(j3 continuous, axis y)- l3 -(ball)- l4; l2 -(fixed)- welded (+0.5 z); frame tip on l1.
# The links are listed out of chain order: the joints come in chain order all the same.
ROBOT = f"""<?xml version="1.0"?><sdf version="1.9" xmlns:drake="http://drake.mit.edu"><model name="m">
<joint name="weld" type="fixed"><parent>world</parent><child>base</child></joint>
{_link("l3", 0.3, "0 0 0 0 0 0", "j3")}
{_link("l2", 0.5, "0 0 0 0 0 0", "j2")}
{_link("base", 2.0, "0 0 0.05 0 0 0", "__model__")}
<joint name="j1" type="revolute"><pose relative_to="base">0 0 0.1 0 0 {math.pi / 2!r}</pose><parent>base</parent>
 <child>l1</child><axis><xyz>1 0 0</xyz><limit><lower>-1</lower><upper>2</upper><effort>30</effort><velocity>4</velocity>
 </limit><dynamics><damping>0.2</damping></dynamics></axis>
 <drake:rotor_inertia>0.001</drake:rotor_inertia><drake:gear_ratio>10</drake:gear_ratio></joint>
{_link("l1", 1.0, "0 0.1 0 0 0 0.5", "j1")}
<joint name="j2" type="prismatic"><pose relative_to="l1">0.3 0 0 0 0 0</pose><parent>l1</parent><child>l2</child>
 <axis><xyz>0 0 1</xyz></axis></joint>
<joint name="j3" type="continuous"><pose relative_to="l2"/><parent>l2</parent><child>l3</child>
 <axis><xyz>0 1 0</xyz><limit><effort>5</effort></limit></axis></joint>
<joint name="ball" type="ball"><pose relative_to="l3"/><parent>l3</parent><child>l4</child></joint>
{_link("l4", 0.1, "0 0 0 0 0 0", "ball")}
<link name="welded"><pose relative_to="l2">0 0 0.5 0 0 0</pose></link>
<joint name="w2" type="fixed"><parent>l2</parent><child>welded</child></joint>
<frame name="tip" attached_to="l1"><pose relative_to="l1">0.5 0 0 0 0 0</pose></frame>
</model></sdf>"""
TURNED = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # +90° about z
DIAG = np.diag([0.01, 0.02, 0.03])


@pytest.fixture  # per test: mutmut credits a call only to the test that makes it
def robot():
    return describe_sdf(ROBOT)


def test_movable_joints_in_chain_order_with_their_links_axes_and_anchors(robot):
    assert (robot.kind, robot.library) == ("sdf", "drake")
    assert [(j.name, j.type, j.parent, j.child, j.parent_frame) for j in robot.joints] == [
        ("j1", "revolute", None, "l1", "base"),
        ("j2", "prismatic", "j1", "l2", "l1"),
        ("j3", "revolute", "j2", "l3", "l2"),  # continuous: revolute, unlimited
    ]
    axes = {"j1": [0, 1, 0], "j2": [0, 0, 1], "j3": [-1, 0, 0]}  # x and y of l1's turned frame: +y, -x
    anchors = {"j1": [0, 0, 0.1], "j2": [0, 0.3, 0.1], "j3": [0, 0.3, 0.1]}
    for j in robot.joints:
        assert j.axis == pytest.approx(axes[j.name], abs=1e-12), j.name
        assert j.anchor == pytest.approx(anchors[j.name], abs=1e-12), j.name


def test_limits_effort_velocity_and_armature_as_drake_reads_them(robot):
    """j1's armature: rotor inertia × gear ratio² = 0.001 × 10²; j2 states no limit: unlimited, its
    effort SDFormat's default (unbounded), no velocity bound."""
    assert [(j.name, j.lower, j.upper, j.effort, j.velocity) for j in robot.joints] == [
        ("j1", -1.0, 2.0, 30.0, 4.0),
        ("j2", -INF, INF, INF, None),
        ("j3", -INF, INF, 5.0, None),
    ]
    assert [j.armature for j in robot.joints] == [pytest.approx(0.1, rel=1e-12), 0.0, 0.0]
    assert [j.damping for j in robot.joints] == [0.2, 0.0, 0.0]
    assert {j.effort_how for j in robot.joints} == {"SDFormat <limit><effort> (Drake's actuator)"}


def test_a_ball_joint_is_held_and_named(robot):
    assert robot.held == ["ball"]
    assert robot.skipped == ["ball: ball_rpy joint with 3 coordinates; only 1-DOF joints are compared (held at 0)"]


def test_links_and_frame_elements_with_owner_depth_and_pose(robot):
    assert robot.frame_kind == {
        "l3": "link",
        "l2": "link",
        "base": "link",
        "l1": "link",
        "l4": "link",
        "welded": "link",
        "tip": "site",
    }
    assert robot.frame_owner == {"l3": "j3", "l2": "j2", "base": None, "l1": "j1", "l4": "j3", "welded": "j2", "tip": "j1"}
    assert robot.frame_depth == {"l3": 4, "l2": 3, "base": 1, "l1": 2, "l4": 5, "welded": 4, "tip": 3}
    assert robot.frames["tip"][:3, :3] == pytest.approx(TURNED, abs=1e-12)
    assert robot.frames["tip"][:3, 3] == pytest.approx([0.0, 0.5, 0.1], abs=1e-12)
    assert robot.frames["welded"][:3, 3] == pytest.approx([0.0, 0.3, 0.6], abs=1e-12)


def test_each_links_inertial_about_its_centre_of_mass_in_its_frame_and_the_world(robot):
    assert [(b.name, b.owner, b.mass) for b in robot.bodies] == [
        ("l3", "j3", 0.3),
        ("l2", "j2", 0.5),
        ("base", None, 2.0),
        ("l1", "j1", 1.0),
        ("l4", "j3", 0.1),
        ("welded", "j2", 1.0),  # SDFormat's default mass
    ]
    l1 = robot.bodies[3]
    c, s = math.cos(0.5), math.sin(0.5)
    turned = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]]) @ DIAG @ np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])
    assert l1.com_local == pytest.approx([0.0, 0.1, 0.0], abs=1e-12)
    assert l1.inertia_local == pytest.approx(turned, abs=1e-12)
    assert l1.com == pytest.approx([-0.1, 0.0, 0.1], abs=1e-12)
    assert l1.inertia == pytest.approx(TURNED @ turned @ TURNED.T, abs=1e-12)
    assert list(robot.gravity) == [0.0, 0.0, -9.81] and robot.couplings == []


def test_a_urdf_read_by_drake_names_its_source_and_drakes_warnings():
    """No transmission: no actuator, no effort; ±1e308 limits are unlimited; a link without an
    inertial has no mass; Drake's warning (it models no friction) is kept, prefixed."""
    urdf = """<robot name="u"><link name="a"/><link name="b"><inertial><mass value="1"/>
      <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <link name="c"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
      <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
        <limit lower="-1" upper="1" effort="3" velocity="2"/><dynamics damping="0.1" friction="0.4"/></joint>
      <joint name="k" type="revolute"><parent link="b"/><child link="c"/><axis xyz="0 1 0"/>
        <limit lower="-1e308" upper="1e308" effort="3" velocity="2"/></joint></robot>"""
    d = describe_sdf(urdf, "urdf")
    assert (d.kind, d.library, [b.name for b in d.bodies]) == ("urdf", "drake", ["b", "c"])
    j, k = d.joints
    assert (j.effort, j.effort_how, j.velocity, j.damping, j.friction) == (None, "no actuator in Drake's model", 2.0, 0.1, None)
    assert j.armature == 0.0  # no actuator: no reflected inertia
    assert (j.lower, j.upper, k.lower, k.upper) == (-1.0, 1.0, -INF, INF)
    (warning,) = d.skipped
    assert warning.startswith("Drake: ") and "friction" in warning


def test_a_two_coordinate_joint_is_held_and_a_file_drake_refuses_is_named_by_its_reader():
    universal = """<sdf version="1.9"><model name="m"><link name="a"/><link name="b"/>
      <joint name="u" type="universal"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis>
      <axis2><xyz>0 1 0</xyz></axis2></joint></model></sdf>"""
    d = describe_sdf(universal)
    assert d.held == ["u"] and d.joints == []
    assert d.skipped[0] == "u: universal joint with 2 coordinates; only 1-DOF joints are compared (held at 0)"
    assert [s for s in d.skipped[1:] if not s.startswith("Drake: ")] == []
    with pytest.raises(BackendError, match=r"^drake-sdf: cannot load the SDF: .*nope"):
        describe_sdf(universal.replace("<child>b</child>", "<child>nope</child>"))
