"""MuJoCo's reading of an MJCF, the decisions pinned one by one on the smallest file: a motor's
gear in the joint's force bound, an ``<equality joint>`` with ``ref`` values read as the coupling
it makes at q = 0, an inactive one read as none, and a ``<flexcomp>``'s bodies named and left out."""

from __future__ import annotations

import math

import mujoco
import numpy as np
import pytest

from kinverify.filemode.read.describe_mjcf import actuator_efforts, describe_mjcf, flex_bodies, free_joint_values
from kinverify.filemode.read.model import INF


def two_hinges(extra: str = "", refs=(0.0, 0.0)) -> str:
    """Two hinges a (leader) and b, b's body on a's; ``extra``: elements after the worldbody."""
    return f"""<mujoco><compiler angle="radian"/><worldbody>
      <body name="l1"><joint name="a" type="hinge" axis="0 0 1" range="-1 1" ref="{refs[0]!r}"/>
        <geom type="sphere" size="0.05" mass="1"/>
        <body name="l2" pos="0.2 0 0"><joint name="b" type="hinge" axis="0 0 1" range="-1 1" ref="{refs[1]!r}"/>
          <geom type="sphere" size="0.05" mass="1"/></body></body>
    </worldbody>{extra}</mujoco>"""


def test_a_motors_gear_multiplies_its_control_range_in_the_joint_force_bound():
    desc = describe_mjcf(two_hinges('<actuator><motor name="ma" joint="a" ctrlrange="-1 1" gear="100"/></actuator>'))
    a, b = desc.joints
    assert a.effort == pytest.approx(100.0) and "gear 100" in a.effort_how  # N·m: 1 × 100
    assert b.effort is None and b.effort_how == "no actuator in the MJCF"


def test_an_equality_with_refs_carries_each_joints_ref_into_the_offset():
    """b − ref_b = 0.1 + 2·(a − ref_a), ref_a 0.2, ref_b 0.05: b = 2·a + (0.05 + 0.1 − 2·0.2) = 2·a − 0.25
    (the leader's ref with the other sign would give + 0.55)."""
    eq = '<equality><joint joint1="b" joint2="a" polycoef="0.1 2 0 0 0"/></equality>'
    (c,) = describe_mjcf(two_hinges(eq, refs=(0.2, 0.05))).couplings
    assert (c.follower, c.leader, c.multiplier, c.nonlinear) == ("b", "a", 2.0, False)
    assert c.offset == pytest.approx(-0.25, abs=1e-12)


def test_an_inactive_equality_is_no_coupling():
    eq = '<equality><joint joint1="b" joint2="a" polycoef="0 1 0 0 0" active="{}"/></equality>'
    assert describe_mjcf(two_hinges(eq.format("false"))).couplings == []
    assert [(c.follower, c.leader) for c in describe_mjcf(two_hinges(eq.format("true"))).couplings] == [("b", "a")]


def test_a_flexcomps_bodies_are_named_and_left_out():
    m = mujoco.MjModel.from_xml_string(
        '<mujoco><worldbody><body name="arm"><joint name="j"/><geom size="0.1" mass="1"/></body>'
        '<flexcomp name="cloth" type="grid" count="2 2 1" spacing="0.1 0.1 0.1" radius="0.01" dim="2" mass="0.1"><edge damping="0.1"/></flexcomp>'
        "</worldbody></mujoco>"
    )
    assert flex_bodies(m) == (
        {2, 3, 4, 5},
        ["flex cloth: a deformable object of 4 bodies (<flexcomp>), not part of the robot: not compared"],
    )


# One robot with most of what MuJoCo's reading decides: a hinge with a joint force cap, dynamics
# and actuators (a geared motor, a servo, a fixed tendon through it); a body with a slide and a
# hinge with ``ref``; a ball joint (named and not); a body moved by an unnamed hinge; a site.
ROBOT = """<mujoco model="m"><compiler angle="radian"/><option gravity="0 0 -3"/>
<worldbody>
 <body name="massless" pos="1 0 0" gravcomp="1"/>
 <body name="b1" pos="0 0 0.1">
  <joint name="h1" type="hinge" axis="0 0 1" range="-1 2" damping="0.2" frictionloss="0.3" armature="0.04"
    stiffness="5" actuatorfrcrange="-7 7" actuatorfrclimited="true"/>
  <geom type="sphere" size="0.05" mass="1"/>
  <site name="tip" pos="0.1 0 0"/>
  <body name="b2" pos="0.2 0 0" gravcomp="0.5">
   <joint name="s1" type="slide" axis="1 0 0"/>
   <joint name="h2" type="hinge" axis="0 1 0" ref="0.5" range="-1 1"/>
   <inertial pos="0.01 0.02 0" quat="0.9238795325112867 0 0 0.3826834323650898" mass="2" diaginertia="0.1 0.2 0.3"/>
   <site name="b2" pos="0.5 0 0"/>
   <body name="b3" pos="0 0 0.3"><joint name="ball" type="ball"/><geom type="sphere" size="0.05" mass="0.5"/></body>
   <body pos="0 0 -0.3"><joint type="ball"/><geom type="sphere" size="0.02" mass="0.1"/></body>
  </body>
  <body name="ub" pos="0 0.3 0" gravcomp="0.3"><joint type="hinge" axis="1 0 0"/><geom type="sphere" size="0.05" mass="1"/>
    <body name="ubchild"><geom type="sphere" size="0.05" mass="1"/><site name="ubsite"/></body></body>
 </body>
</worldbody>
<tendon><fixed name="tn"><joint joint="h1" coef="2"/><joint joint="s1" coef="-0.5"/></fixed></tendon>
<actuator>
 <motor site="tip" ctrlrange="-1 1"/>
 <motor name="m1" joint="h1" ctrlrange="-1 1" gear="3"/>
 <position name="p1" joint="h1" kp="10"/>
 <motor name="m2" joint="s1" forcerange="-4 6" forcelimited="true" ctrlrange="-100 100"/>
 <motor tendon="tn" ctrlrange="-2 2" gear="1"/>
</actuator>
<equality><joint joint1="h1" joint2="s1" active="false"/><joint joint1="h2" joint2="s1" polycoef="0 1 0.5 0 0"/></equality>
</mujoco>"""


@pytest.fixture  # per test: mutmut credits a call only to the test that makes it
def robot():
    return describe_mjcf(ROBOT)


def rot_y(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def test_movable_joints_their_parents_bodies_and_world_axes(robot):
    """s1 and h2 share b2: h2's parent is s1 (the joint before it on the body), s1's the joint above."""
    assert (robot.kind, robot.library) == ("mjcf", "mujoco")
    assert [(j.name, j.type, j.parent, j.child, j.parent_frame) for j in robot.joints] == [
        ("h1", "revolute", None, "b1", "world"),
        ("s1", "prismatic", "h1", "b2", "b1"),
        ("h2", "revolute", "s1", "b2", "b1"),
    ]
    assert [list(j.axis) for j in robot.joints] == [[0, 0, 1], [1, 0, 0], [0, 1, 0]]
    assert robot.joints[1].anchor == pytest.approx([0.2, 0.0, 0.1], abs=1e-12)


def test_limits_dynamics_and_an_unlimited_slide(robot):
    assert [(j.name, j.lower, j.upper) for j in robot.joints] == [("h1", -1, 2), ("s1", -INF, INF), ("h2", -1, 1)]
    h1 = robot.joints[0]
    assert (h1.damping, h1.friction, h1.armature, h1.stiffness, h1.velocity) == (0.2, 0.3, 0.04, 5.0, None)
    assert (robot.joints[1].damping, robot.joints[1].armature, robot.joints[1].stiffness) == (0.0, 0.0, 0.0)


def test_a_joints_force_cap_below_its_actuators_bound_is_its_effort(robot):
    """h1: motor 1 × gear 3, a servo without forcerange (unbounded), the tendon 2 × 2: the cap 7 wins."""
    h1 = robot.joints[0]
    assert (h1.effort, h1.effort_how, h1.effort_each) == (7.0, "joint actuatorfrcrange ±7", ())


def test_each_actuator_on_a_joint_is_kept_and_the_largest_bounds_it(robot):
    """s1: m2's forcerange 6 (not its ctrlrange), the tendon's |coef -0.5| × ctrl 2 = 1; the site actuator
    (the first, #0) drives no joint."""
    s1, h2 = robot.joints[1], robot.joints[2]
    assert s1.effort == 6.0
    assert s1.effort_each == (
        (6.0, "m2: forcerange ±6"),
        (1.0, "actuator #4 on tendon tn (coef -0.5): ctrlrange ±2 × gain 1"),
    )
    assert s1.effort_how == "m2: forcerange ±6; actuator #4 on tendon tn (coef -0.5): ctrlrange ±2 × gain 1"
    assert (h2.effort, h2.effort_how, h2.effort_each) == (None, "no actuator in the MJCF", ())


def test_a_joint_force_cap_bounds_a_joint_without_actuators_and_ties_keep_the_actuators_word():
    """a: a motor 1 × gear 7 and the cap ±7: the motor's bound says it; b: no actuator, the cap
    (-3, 2) bounds it at 3 (the larger side)."""
    text = two_hinges('<actuator><motor name="ma" joint="a" ctrlrange="-1 1" gear="7"/></actuator>')
    text = text.replace('ref="0.0"/>', 'ref="0.0" actuatorfrcrange="-7 7" actuatorfrclimited="true"/>', 1)
    text = text.replace(
        'range="-1 1" ref="0.0"/>', 'range="-1 1" ref="0.0" actuatorfrcrange="-3 2" actuatorfrclimited="true"/>', 1
    )
    a, b = describe_mjcf(text).joints
    assert (a.effort, a.effort_how, a.effort_each) == (7.0, "ma: ctrlrange ±1 × gain 1 × gear 7", ())  # one actuator: no list
    assert (b.effort, b.effort_how, b.effort_each) == (3.0, "joint actuatorfrcrange ±3", ())


def test_actuator_bounds_gear_gain_servos_and_the_joint_in_parent_transmission():
    m = mujoco.MjModel.from_xml_string(
        """<mujoco><worldbody><body name="a"><joint name="j" axis="0 0 1"/><geom size="0.1" mass="1"/>
        <body name="c"><joint name="k" axis="0 0 1"/><geom size="0.1" mass="1"/></body></body></worldbody>
        <actuator><general name="g" joint="j" gainprm="5" ctrlrange="-2 1" gear="-3"/><velocity joint="k" kv="1"/>
        <motor joint="k"/><motor jointinparent="k" ctrlrange="0 0.5" gear="2"/>
        <motor joint="j" forcerange="-1 1" forcelimited="true" gear="-4"/></actuator></mujoco>"""
    )
    assert actuator_efforts(m) == {
        0: (
            30.0,
            "g: ctrlrange ±2 × gain 5 × gear -3; actuator #4: forcerange ±1 × gear -4",
            ((30.0, "g: ctrlrange ±2 × gain 5 × gear -3"), (4.0, "actuator #4: forcerange ±1 × gear -4")),
        ),
        1: (
            INF,
            "actuator #1: no forcerange (a servo: unbounded force); actuator #2: no forcerange; "
            "actuator #3: ctrlrange ±0.5 × gain 1 × gear 2",
            (
                (INF, "actuator #1: no forcerange (a servo: unbounded force)"),
                (INF, "actuator #2: no forcerange"),
                (1.0, "actuator #3: ctrlrange ±0.5 × gain 1 × gear 2"),
            ),
        ),
    }


def test_frames_are_named_bodies_and_sites_at_qpos_0_not_at_ref(robot):
    """h2's ref 0.5: at qpos 0 b2's children stand turned -0.5 about y from the file's pose; a site
    named as a body is not a second frame; unnamed bodies and the unnamed hinge's subtree are none."""
    assert robot.frame_kind == {"b1": "link", "b2": "link", "b3": "link", "massless": "link", "tip": "site"}  # no ubsite
    assert robot.frame_owner == {"b1": "h1", "b2": "h2", "b3": "h2", "massless": None, "tip": "h1"}
    assert robot.frame_depth == {"b1": 1, "b2": 2, "b3": 3, "massless": 1, "tip": 2}
    b3 = robot.frames["b3"]
    assert b3[:3, 3] == pytest.approx(np.array([0.2, 0.0, 0.1]) + rot_y(-0.5) @ [0.0, 0.0, 0.3], abs=1e-12)
    assert b3[:3, :3] == pytest.approx(rot_y(-0.5), abs=1e-12)
    assert robot.frames["tip"][:3, 3] == pytest.approx([0.1, 0.0, 0.1], abs=1e-12)


def test_joints_not_compared_are_noted_and_the_named_ones_held(robot):
    assert robot.skipped == [
        "ball: mjJNT_BALL joints are not compared (held at 0)",
        "joint #4: mjJNT_BALL joints are not compared (held at 0)",
        "body ub: moved by an unnamed joint; it and the bodies it carries are not compared (name the joint to compare them)",
    ]
    assert robot.held == ["ball"]


def test_bodies_with_mass_their_inertial_in_the_world_and_their_own_frame(robot):
    """b2's inertia: diag(0.1, 0.2, 0.3) turned 45° about z in its frame, which h2's ref turns -0.5 about y."""
    assert [(b.name, b.owner, b.mass) for b in robot.bodies] == [
        ("b1", "h1", 1.0),
        ("b2", "h2", 2.0),
        ("b3", "h2", 0.5),
        ("", "h2", 0.1),
    ]
    b2 = robot.bodies[1]
    turn = np.array([[1, -1, 0], [1, 1, 0], [0, 0, math.sqrt(2)]]) / math.sqrt(2)  # 45° about z
    local = turn @ np.diag([0.1, 0.2, 0.3]) @ turn.T
    assert b2.com_local == pytest.approx([0.01, 0.02, 0.0], abs=1e-12)
    assert b2.inertia_local == pytest.approx(local, abs=1e-9)
    assert b2.com == pytest.approx(np.array([0.2, 0.0, 0.1]) + rot_y(-0.5) @ [0.01, 0.02, 0.0], abs=1e-12)
    assert b2.inertia == pytest.approx(rot_y(-0.5) @ local @ rot_y(-0.5).T, abs=1e-9)
    assert (b2.snapped, b2.snapped_com) == (0.0, 0.0)


def test_gravity_gravity_compensation_and_couplings(robot):
    """h2 = s1 + 0.5 (h2's ref) with a quadratic term: nonlinear; the inactive equality is none."""
    assert list(robot.gravity) == [0.0, 0.0, -3.0]
    assert robot.gravcomp == {"b2": 0.5}  # not the massless body's, nor the unnamed hinge's body's
    (c,) = robot.couplings
    assert (c.follower, c.leader, c.multiplier, c.source, c.nonlinear) == ("h2", "s1", 1.0, "<equality joint>", True)
    assert c.offset == pytest.approx(0.5, abs=1e-12)


def test_an_equality_on_a_joint_not_compared_is_no_coupling():
    """c is named but rides on a body an unnamed hinge moves: not compared, so neither is its coupling."""
    text = """<mujoco><worldbody><body name="l1"><joint name="a" axis="0 0 1"/><geom size="0.1" mass="1"/>
      <body name="l2"><joint name="e" axis="0 1 0"/><geom size="0.1" mass="1"/></body>
        <body name="u"><joint axis="0 0 1"/><geom size="0.1" mass="1"/>
        <body name="l3"><joint name="c" axis="0 0 1"/><geom size="0.1" mass="1"/></body></body></body></worldbody>
      <equality><joint joint1="c" joint2="a"/><joint joint1="a" joint2="c"/><joint joint1="e" joint2="a"/></equality>
      </mujoco>"""
    d = describe_mjcf(text)
    assert [j.name for j in d.joints] == ["a", "e"]
    assert [(c.follower, c.leader) for c in d.couplings] == [("e", "a")]  # the one between joints compared


def test_principal_axes_and_a_centre_of_mass_the_compiler_snapped_to_the_body_frame():
    """MuJoCo keeps a 2e-7 quaternion part (0.4 µrad) and a 3e-7 m CoM offset it then treats as 0."""
    text = """<mujoco><worldbody><body name="f"><joint name="r" axis="0 0 1"/><geom size="0.1" mass="1"/>
      <body name="a"><joint name="j" axis="0 0 1"/>
        <inertial pos="3e-7 0 0" quat="1 2e-7 0 0" mass="1" diaginertia="0.1 0.2 0.3"/></body>
      <body name="c"><joint name="k" axis="0 0 1"/>
        <inertial pos="0.1 0 0" quat="1 2e-7 0 0" mass="1" diaginertia="0.1 0.2 0.3"/></body>
      </body></worldbody></mujoco>"""
    snapped = {b.name: (b.snapped, b.snapped_com) for b in describe_mjcf(text).bodies}
    assert snapped["f"] == (0.0, 0.0)
    assert snapped["a"] == (pytest.approx(4e-7, rel=1e-6), pytest.approx(3e-7, rel=1e-9))
    assert snapped["c"] == (pytest.approx(4e-7, rel=1e-6), 0.0)  # its CoM is kept where stated


def test_free_joint_values_are_the_nonzero_largest_of_its_dofs():
    text = """<mujoco><default><joint armature="{a}" damping="{d}"/></default><worldbody><body name="f">
      <joint type="free"/><geom size="0.1" mass="1"/></body></worldbody></mujoco>"""
    assert free_joint_values(text.format(a=0.1, d=0)) == {"armature": 0.1}
    assert free_joint_values(text.format(a=0, d=0.2)) == {"damping": 0.2}
    assert free_joint_values("<mujoco><worldbody/></mujoco>") == {}
    assert free_joint_values("not xml <") == {}


def test_a_flexcomp_is_left_out_of_the_description():
    """Two of them: both objects' bodies left out, each named."""
    flex = (
        '<flexcomp name="{}" type="grid" count="2 2 1" spacing="0.1 0.1 0.1" radius="0.01" dim="2" mass="0.1">'
        '<edge damping="0.1"/></flexcomp>'
    )
    d = describe_mjcf(
        '<mujoco><worldbody><body name="arm"><joint name="j"/><geom size="0.1" mass="1"/></body>'
        + flex.format("cloth")
        + flex.format("sheet")
        + "</worldbody></mujoco>"
    )
    assert list(d.frames) == ["arm"] and [b.name for b in d.bodies] == ["arm"] and [j.name for j in d.joints] == ["j"]
    assert d.skipped == [
        f"flex {name}: a deformable object of 4 bodies (<flexcomp>), not part of the robot: not compared"
        for name in ("cloth", "sheet")
    ]
