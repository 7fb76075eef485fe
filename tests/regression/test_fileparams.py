"""Parameter-level differences of two model files (``kinverify diff``), each decision pinned on a
two-joint URDF: a number changed by more than ATOL (and not by ATOL), a non-numeric change, a joint
origin relative to its parent, a fixed frame's pose, names removed or renamed, the pairs given or
found, and the mass moving with a joint that one file leaves without any."""

from __future__ import annotations

import pytest

from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.regression.fileparams import pair_names, param_changes
from kinverify.regression.specdiff import ATOL, ParamChange

INERTIA = '<inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/>'


def urdf(*, effort="10", damping="0", j1_type="revolute", j1="j1", tool_z="0.2", l2_mass: str | None = "1", with_j2=True) -> str:
    l2 = f'<inertial><mass value="{l2_mass}"/>{INERTIA}</inertial>' if l2_mass else ""
    limit = f'<limit lower="-1" upper="1" effort="{effort}" velocity="2"/>'
    second = f"""
 <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.2"/><axis xyz="0 1 0"/>{limit}</joint>
 <link name="l2">{l2}</link>
 <joint name="tool_joint" type="fixed"><parent link="l2"/><child link="tool"/><origin xyz="0 0 {tool_z}"/></joint>
 <link name="tool"/>"""
    return f"""<robot name="r">
 <link name="base"/>
 <joint name="{j1}" type="{j1_type}"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>{limit}
  <dynamics damping="{damping}"/></joint>
 <link name="l1"><inertial><mass value="2"/>{INERTIA}</inertial></link>{second if with_j2 else ""}
</robot>"""


OLD = describe_urdf(urdf())


def changes(**kwargs) -> list[ParamChange]:
    return param_changes(OLD, describe_urdf(urdf(**kwargs)))


def test_a_file_against_itself_has_no_change():
    # j2's origin is compared in l1's frame (0.2 m), not in the world's (0.3 m)
    assert param_changes(OLD, OLD) == []


def test_a_number_changed_by_more_than_atol():
    assert changes(effort="20") == [
        ParamChange("joint j1", "limits.effort", "changed", 10.0, 20.0, 10.0),
        ParamChange("joint j2", "limits.effort", "changed", 10.0, 20.0, 10.0),
    ]
    assert changes(damping=repr(ATOL)) == []  # by ATOL exactly: the same
    assert changes(damping=repr(2 * ATOL)) == [ParamChange("joint j1", "damping", "changed", 0.0, 2 * ATOL, 2 * ATOL)]


def test_a_non_numeric_change():
    assert ParamChange("joint j1", "type", "changed", "revolute", "prismatic") in changes(j1_type="prismatic")


def test_a_fixed_frame_moved_on_its_link():
    (moved,) = changes(tool_z="0.25")
    assert (moved.where, moved.field, moved.kind) == ("frame tool", "origin.xyz", "changed")
    assert moved.old == pytest.approx((0, 0, 0.2), abs=1e-12) and moved.new == pytest.approx((0, 0, 0.25), abs=1e-12)
    assert moved.delta == pytest.approx(0.05, abs=1e-12)


def test_names_removed_and_renamed():
    removed = changes(with_j2=False)
    assert ParamChange("joint j2", "name", "removed", "j2", None) in removed
    assert ParamChange("frame l2", "name", "removed", "l2", None) in removed
    assert changes(j1="k1")[0] == ParamChange("joint j1", "name", "changed", "j1", "k1")


def test_the_pairs_given_are_used():
    assert pair_names(OLD, OLD)[0] == [("j1", "j1"), ("j2", "j2")]
    unpaired = param_changes(OLD, OLD, joints=[], frames=[])
    assert ParamChange("joint j1", "name", "removed", "j1", None) in unpaired
    assert ParamChange("joint j1", "name", "added", None, "j1") in unpaired


def test_the_mass_moving_with_a_joint_that_one_file_leaves_without_any():
    lost = ParamChange("inertia moving with j2", "mass", "changed", 1.0, 0.0, 1.0)
    assert changes(l2_mass=None) == [lost]
    assert param_changes(describe_urdf(urdf(l2_mass=None)), OLD) == [
        ParamChange("inertia moving with j2", "mass", "changed", 0.0, 1.0, 1.0)
    ]
