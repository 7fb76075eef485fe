"""MuJoCo's reading of an MJCF, the decisions pinned one by one on the smallest file: a motor's
gear in the joint's force bound, an ``<equality joint>`` with ``ref`` values read as the coupling
it makes at q = 0, an inactive one read as none, and a ``<flexcomp>``'s bodies named and left out."""

from __future__ import annotations

import mujoco
import pytest

from kinverify.filemode.read.describe_mjcf import describe_mjcf, flex_bodies


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
        '<flexcomp name="cloth" type="grid" count="2 2 1" spacing="0.1 0.1 0.1" radius="0.01" dim="2" mass="0.1"/>'
        "</worldbody></mujoco>"
    )
    assert flex_bodies(m) == (
        {2, 3, 4, 5},
        ["flex cloth: a deformable object of 4 bodies (<flexcomp>), not part of the robot: not compared"],
    )
