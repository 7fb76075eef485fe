"""Limits in file mode: force bounds of joints several MJCF actuators drive, and joint ranges
compared without a whole turn nobody took."""

from __future__ import annotations

import math

import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.filemode.pipeline import verify_files
from kinverify.run import VerifyOptions

FAST = VerifyOptions(samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics", "limits"])


def servos(mjcf: str, joint: str, position: float, velocity: float) -> str:
    """A position and a velocity servo beside the joint's motor, as MJCFs offering three ways of
    driving a joint do (each with its own force range)."""
    return P.sub_once(
        r"<actuator>",
        f'<actuator><position name="{joint}_position" joint="{joint}" kp="100" '
        f'forcerange="-{position} {position}"/><velocity name="{joint}_velocity" joint="{joint}" kv="10" '
        f'forcerange="-{velocity} {velocity}"/>',
        mjcf,
    )


def above_info(result) -> list:
    return [f for f in result.findings if f.severity != "info" and not P.ignored_by_drake(f)]


def test_alternative_actuators_with_the_urdfs_bound_agree(tmp_path):
    """panda_joint1: a motor, a position servo and a velocity servo, each bounded to the URDF's
    87 N·m. Their forces are not meant to add up: no effort finding, the check passes."""
    urdf, mjcf = P.generated_pair("panda")
    result = verify_files(*P.write_pair(tmp_path, urdf, servos(mjcf, "panda_joint1", 87, 87)), FAST)
    assert above_info(result) == [] and result.passed, [f.message for f in above_info(result)]
    (f,) = [f for f in result.findings if f.kind == "several_actuators"]
    assert f.subject == "panda_joint1" and f.values["actuators"] == [3]


def test_an_alternative_actuator_with_another_bound_is_a_warning_naming_it(tmp_path):
    """The velocity servo allows 200 N·m where the URDF and the other two actuators say 87: a
    warning naming that actuator, not an effort difference."""
    urdf, mjcf = P.generated_pair("panda")
    result = verify_files(*P.write_pair(tmp_path, urdf, servos(mjcf, "panda_joint1", 87, 200)), FAST)
    (f,) = above_info(result)
    assert (f.kind, f.severity, f.subject) == ("actuator_alternatives", "warning", "panda_joint1")
    assert f.magnitude == pytest.approx(113) and "panda_joint1_velocity" in f.message
    assert result.passed


def test_actuators_none_of_which_has_the_urdfs_bound_differ_by_the_largest(tmp_path):
    """The motor bounded to 70 N·m, the servos to 50 and 60, the URDF 87: an effort difference of
    87 − 70 (the largest one actuator can exert)."""
    urdf, mjcf = P.generated_pair("panda")
    mjcf = P.sub_once(
        r'(<motor name="panda_joint1_motor" joint="panda_joint1" ctrlrange=")[^"]*',
        r"\g<1>-70 70",
        servos(mjcf, "panda_joint1", 50, 60),
    )
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)
    (f,) = above_info(result)
    assert (f.kind, f.severity, f.subject) == ("effort_difference", "error", "panda_joint1")
    assert f.magnitude == pytest.approx(17)


def test_a_range_on_the_other_side_of_zero_is_compared_as_written(tmp_path):
    """No zero offset between the files: panda_joint1 spans [−3.665, 0] in the URDF and [0, 3.665]
    in the MJCF. They differ by 3.665 rad, not by the 2.618 a whole turn added to the URDF's
    would leave."""
    urdf, mjcf = P.generated_pair("panda")
    urdf = P.sub_once(r'lower="-2.8973" upper="2.8973" effort="87.0"', 'lower="-3.665" upper="0.0" effort="87.0"', urdf)
    mjcf = P.joint_attr(mjcf, "panda_joint1", "range", lambda s: "0.0 3.665")
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)
    (f,) = above_info(result)
    assert (f.kind, f.subject) == ("limit_difference", "panda_joint1")
    assert f.magnitude == pytest.approx(3.665)


def test_several_actuators_on_a_joint_the_urdf_gives_no_force_bound(tmp_path):
    """panda_joint1 is continuous in both files, with no <limit> in the URDF (as a wheel is); the
    MJCF drives it by three actuators. The URDF's silence on the force is the one finding (a
    warning), whatever the actuators state."""
    urdf, mjcf = P.generated_pair("panda")
    urdf = P.sub_once(r'<joint name="panda_joint1" type="revolute">', '<joint name="panda_joint1" type="continuous">', urdf)
    urdf = P.sub_once(r'<limit lower="-2.8973" upper="2.8973" effort="87.0" velocity="2.175"/>', "", urdf)
    mjcf = P.sub_once(r'(<joint name="panda_joint1"[^>]*?) range="[^"]*"', r"\1", mjcf)
    result = verify_files(*P.write_pair(tmp_path, urdf, servos(mjcf, "panda_joint1", 87, 200)), FAST)
    (f,) = above_info(result)
    assert (f.kind, f.severity, f.subject) == ("effort_unset", "warning", "panda_joint1")
    assert f.values["unset_in"] == "URDF" and not result.failed


def test_a_joint_the_mjcf_couples_to_a_joint_the_urdf_lacks_is_driven_through_it(tmp_path):
    """The MJCF hangs panda_link7 from a slide the URDF lacks and couples joint 7 to it (as a
    gripper's fingers follow its slide), with no actuator of joint 7's own: its force comes
    through the slide's, so the MJCF does not leave it unbounded."""
    urdf, mjcf = P.generated_pair("panda")
    mjcf = P.suspended(mjcf, "panda_link7", 0.05)
    mjcf = P.re.sub(r'<motor name="panda_joint7_motor"[^>]*/>', "", mjcf)
    mjcf = P.sub_once(
        r"</mujoco>",
        '<equality><joint joint1="panda_joint7" joint2="suspension_joint" polycoef="0 10 0 0 0"/></equality></mujoco>',
        mjcf,
    )
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)
    assert not [f for f in result.findings if f.kind in ("effort_unset", "effort_difference")], [
        f.message for f in result.findings if f.kind.startswith("effort")
    ]


def twisted(mjcf: str, body: str, angle: float) -> str:
    """The generated MJCF with ``body``'s frame turned by ``angle`` about its joint's axis (its own
    z), all it holds turned with it: the joint's zero moved, its range left as written."""
    turn = [math.cos(angle / 2), 0.0, 0.0, math.sin(angle / 2)]
    return P.body_attr(mjcf, body, "quat", P.nums(lambda q: list(P._quat_mul(np.array(q), np.array(turn)))))


def test_a_range_written_alike_in_each_files_own_zero_is_the_zero_offsets_finding(tmp_path):
    """panda_link4 turned by 0.1 rad about joint 4's axis, its range left as written: physically the
    range sits 0.1 rad apart at both ends, which is the zero offset, said once (its finding names
    the range and explains the limits check); no limit_difference of 0.1 beside it."""
    urdf, mjcf = P.generated_pair("panda")
    result = verify_files(*P.write_pair(tmp_path, urdf, twisted(mjcf, "panda_link4", 0.1)), FAST)
    (f,) = above_info(result)
    assert (f.kind, f.severity, f.subject) == ("zero_offset", "error", "panda_joint4")
    assert f.magnitude == pytest.approx(0.1, abs=1e-6) and f.values["range_written_alike"]
    assert "written alike in each file's own zero" in f.message
    (check,) = [c for c in result.checks if c.property == "limits.position"]
    assert not check.passed and check.kind == "explained" and result.verdict == "fail"


def test_a_range_end_changed_besides_a_zero_offset_differs_by_the_change(tmp_path):
    """The same turn, and the MJCF's upper end of joint 4 moved by 0.2 rad: a limit_difference of
    0.2 (the lower end agrees as each file writes it), not the 0.3 the carried reading leaves at the
    upper end; and the zero offset of 0.1, which no longer claims the range."""
    urdf, mjcf = P.generated_pair("panda")
    mjcf = P.joint_attr(twisted(mjcf, "panda_link4", 0.1), "panda_joint4", "range", P.nums(lambda v: [v[0], v[1] + 0.2]))
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)
    found = {f.kind: f for f in above_info(result)}
    assert sorted(found) == ["limit_difference", "zero_offset"] and found["limit_difference"].subject == "panda_joint4"
    assert found["limit_difference"].magnitude == pytest.approx(0.2, abs=1e-6)
    assert found["limit_difference"].values["beyond_zero_offset"]
    assert (
        found["zero_offset"].magnitude == pytest.approx(0.1, abs=1e-6)
        and "range_written_alike" not in found["zero_offset"].values
    )


def reversed_axis(mjcf: str, joint: str, rng=lambda v: v) -> str:
    mjcf = P.joint_attr(mjcf, joint, "axis", P.nums(lambda v: [-x for x in v]))
    return P.joint_attr(mjcf, joint, "range", P.nums(rng))


def test_an_asymmetric_range_left_as_written_on_a_reversed_axis_is_the_sign_flips_finding(tmp_path):
    """panda_joint4's axis reversed in the MJCF, its range [-3.0718, -0.0698] left as written: the
    reversed axis mirrors it physically (3.1416 rad apart at each end); one axis_sign_flip finding
    names the range and explains the limits check, no limit_difference beside it."""
    urdf, mjcf = P.generated_pair("panda")
    result = verify_files(*P.write_pair(tmp_path, urdf, reversed_axis(mjcf, "panda_joint4")), FAST)
    (f,) = above_info(result)
    assert (f.kind, f.severity, f.subject) == ("axis_sign_flip", "error", "panda_joint4")
    assert f.values["range_written_alike"] and "reversed axis mirrors it" in f.message
    assert "3.1416 rad apart" in f.message
    (check,) = [c for c in result.checks if c.property == "limits.position"]
    assert not check.passed and check.kind == "explained" and result.verdict == "fail"


def test_a_range_mirrored_with_its_reversed_axis_agrees_and_an_end_changed_besides_differs_by_the_change(tmp_path):
    """The reversed axis with the range mirrored as it should be ([0.0698, 3.0718]): the sign flip
    alone, no range claimed. The same with the mirrored upper end moved by 0.2 rad: a limit_difference
    of 0.2, named beyond the reversed axis (not the 3.0 the range as written would leave)."""
    urdf, mjcf = P.generated_pair("panda")
    mirrored = reversed_axis(mjcf, "panda_joint4", lambda v: [-v[1], -v[0]])
    (f,) = above_info(verify_files(*P.write_pair(tmp_path, urdf, mirrored), FAST))
    assert f.kind == "axis_sign_flip" and "range_written_alike" not in f.values
    moved = reversed_axis(mjcf, "panda_joint4", lambda v: [-v[1], -v[0] + 0.2])
    found = {f.kind: f for f in above_info(verify_files(*P.write_pair(tmp_path, urdf, moved), FAST))}
    assert sorted(found) == ["axis_sign_flip", "limit_difference"], [f.message for f in found.values()]
    assert found["limit_difference"].magnitude == pytest.approx(0.2, abs=1e-6)
    assert (
        not found["limit_difference"].values["beyond_reversed_axis"]
        and "range_written_alike" not in found["axis_sign_flip"].values
    )


def test_ranges_read_in_degrees_are_one_units_finding_beside_a_zero_offset(tmp_path):
    """The MJCF drops <compiler angle="radian"> (MuJoCo reads every range in degrees) and gives
    panda_joint4 a zero offset of 20° (ref, read in degrees too), its range left as the URDF writes
    it: joint 4's range is the URDF's times π/180 in its own zero, so it is one of the joints the
    units finding names, not a limit_difference of its own (carried through the offset, its bounds
    are no multiple of the URDF's)."""
    urdf, mjcf = P.degrees_mjcf(*P.generated_pair("panda"))
    mjcf = P.re.sub(r'(<joint name="panda_joint4" )', lambda m: m[1] + 'ref="20" ', mjcf, count=1)
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)
    found = {f.kind: f for f in above_info(result)}
    assert "limit_difference" not in found, found["limit_difference"].message
    assert "panda_joint4" in found["limit_units"].subject.split(", ") and len(found["limit_units"].subject.split(", ")) == 7
    assert found["zero_offset"].subject == "panda_joint4" and found["zero_offset"].magnitude == pytest.approx(math.radians(20))
