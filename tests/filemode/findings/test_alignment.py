"""Findings of the alignment, each decision pinned by a pair built for it: a joint below a joint
that differs is measured in its own right, a zero offset of a whole turn's difference is no limit
difference, a constant turn of a link frame about its own joint is a convention, a floating
robot's base frames fix the frame."""

from __future__ import annotations

import math

import pytest

import tests.filemode.pairs as P
from kinverify.filemode.pipeline import verify_files
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import spec_from_dict
from kinverify.run import VerifyOptions

FAST = VerifyOptions(
    samples=8,
    fd_samples=4,
    backends=["pinocchio-urdf", "mujoco"],
    extra={"dynamics_samples": 12},
    suites=["kinematics", "limits", "inertia"],
)


def run(tmp_path, urdf, mjcf):
    return verify_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)


def serious(result) -> list:
    return sorted((f.kind, f.subject) for f in result.findings if f.severity != "info" and not P.ignored_by_drake(f))


def shifted(mjcf: str, body: str, dx: float) -> str:
    return P.body_attr(mjcf, body, "pos", P.nums(lambda v: [v[0] + dx, v[1], v[2]]))


def test_a_joint_below_one_that_differs_is_measured_in_its_own_right(tmp_path):
    """The MJCF's panda_link3 sits 1 mm further along x, and panda_link5 2 mm further again (two
    link lengths): two moved joint frames, each with its own offset vector in its parent link's
    axes, the second not 1 + 2 mm from where the first one left it, and nothing they carry blamed."""
    urdf, mjcf = P.generated_pair("panda")
    mjcf = shifted(shifted(mjcf, "panda_link3", 1e-3), "panda_link5", 2e-3)
    result = run(tmp_path, urdf, mjcf)
    assert serious(result) == [("joint_origin_moved", "panda_joint3"), ("joint_origin_moved", "panda_joint5")]
    found = {f.subject: f for f in result.findings if f.kind == "joint_origin_moved"}
    assert found["panda_joint3"].magnitude == pytest.approx(1e-3, abs=1e-9)
    assert found["panda_joint5"].magnitude == pytest.approx(2e-3, abs=1e-9)
    assert found["panda_joint5"].values["xyz"] == pytest.approx([2e-3, 0.0, 0.0], abs=1e-9)
    assert "on panda_link4" in found["panda_joint5"].message


def test_limits_through_a_zero_offset_are_compared_up_to_whole_turns(tmp_path):
    """panda_joint4's zero is 3 rad further in the MJCF (ref) and its range is the URDF's shifted
    by 3 − 2π: the same range, a whole turn apart. One zero_offset finding, no limit difference."""
    urdf, mjcf = P.generated_pair("panda")
    offset = 3.0
    mjcf = P.joint_attr(mjcf, "panda_joint4", "range", P.nums(lambda v: [x + offset - 2 * math.pi for x in v]))
    mjcf = P.re.sub(r'(<joint name="panda_joint4" )', lambda m: m[1] + f'ref="{offset!r}" ', mjcf, count=1)
    result = run(tmp_path, urdf, mjcf)
    assert [f.kind for f in result.findings if f.kind.startswith("limit")] == []
    (zero,) = [f for f in result.findings if f.kind == "zero_offset"]
    assert math.remainder(zero.values["offset"] - offset, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)


def test_a_link_frame_turned_about_its_own_joint_is_a_convention(tmp_path):
    urdf, mjcf = P.generated_pair("panda")
    result = run(tmp_path, urdf, P.reframed_body(mjcf, "panda_link5", math.pi / 2))
    assert result.passed and serious(result) == []
    (f,) = [f for f in result.findings if f.kind == "frame_convention"]
    assert f.subject == "panda_link5" and f.magnitude == pytest.approx(math.pi / 2, abs=1e-9)


def quadruped(dx: float = 0.0) -> dict:
    """A floating trunk with four legs (hip about x, thigh and knee about y); ``dx``: the hips
    that much further out along x, front and rear alike."""
    joints = []
    for leg, (x, y) in {"FL": (0.2, 0.05), "FR": (0.2, -0.05), "RL": (-0.2, 0.05), "RR": (-0.2, -0.05)}.items():
        x += math.copysign(dx, x)
        joints += [
            {
                "name": f"{leg}_hip",
                "parent": "trunk",
                "xyz": [x, y, 0.0],
                "axis": [1.0, 0.0, 0.0],
                "limits": {"lower": -0.8, "upper": 0.8, "unit": "rad"},
                "link": {"name": f"{leg}_hip_link", "mass": 0.5},
            },
            {
                "name": f"{leg}_thigh",
                "parent": f"{leg}_hip_link",
                "xyz": [0.0, math.copysign(0.08, y), 0.0],
                "axis": [0.0, 1.0, 0.0],
                "limits": {"lower": -1.5, "upper": 3.4, "unit": "rad"},
                "link": {
                    "name": f"{leg}_thigh_link",
                    "inertial": {"mass": 1.0, "com": [0.0, 0.0, -0.1], "inertia": [0.004, 0.004, 0.001, 0.0, 0.0, 0.0]},
                },
            },
            {
                "name": f"{leg}_knee",
                "parent": f"{leg}_thigh_link",
                "xyz": [0.0, 0.0, -0.2],
                "axis": [0.0, 1.0, 0.0],
                "limits": {"lower": -2.7, "upper": -0.9, "unit": "rad"},
                "link": {
                    "name": f"{leg}_calf_link",
                    "inertial": {"mass": 0.2, "com": [0.0, 0.0, -0.1], "inertia": [0.001, 0.001, 0.0002, 0.0, 0.0, 0.0]},
                },
            },
        ]
    return {"name": "dog", "base": {"floating": True, "link": {"name": "trunk", "mass": 6.0}}, "joints": joints}


def test_two_floating_bases_fix_the_frame_and_a_difference_is_reported_where_it_is(tmp_path):
    """The MJCF's four hips sit 2.5 mm further out along x, front and rear alike: each hip's frame is
    2.5 mm off (along its axis: one finding for the four, nothing on what they carry), and the base
    frames are not said to differ (a fitted world would have moved the
    difference onto the rear legs, 5 mm, and called the base frames apart)."""
    urdf = generate_urdf(spec_from_dict(quadruped()))
    mjcf = generate_mjcf(spec_from_dict(quadruped(2.5e-3)))
    result = run(tmp_path, urdf, mjcf)
    assert not [f for f in result.findings if f.kind in ("base_frame_offset", "base_transform")]
    (hips,) = [f for f in result.findings if f.kind == "joint_origin_moved"]  # four legs alike: one finding
    assert hips.subject == "FL_hip, FR_hip, RL_hip, RR_hip" and hips.message.startswith("4 joints alike")
    assert hips.magnitude == pytest.approx(2.5e-3, abs=1e-9)
    assert [abs(x) for xyz in hips.values["xyz_each"] for x in xyz] == pytest.approx([2.5e-3, 0, 0] * 4, abs=1e-9)
    assert not [f for f in result.findings if f.kind in ("axis_position", "axis_direction")]


def test_an_orientation_rounded_upstream_is_a_rounding_note_not_a_zero_offset(tmp_path):
    """The MJCF writes panda_link2's quaternion to 5 decimals (0.707107 −0.70711: 4e-6 rad off) and
    panda_link5's position rounded: everything downstream agrees only to that precision, and a
    point near joint 7's axis (its link's centre of mass, 1 cm off it) turns those micrometres into
    2e-4 rad. That is rounding, not a zero offset of joint 7, a limit difference or dynamics."""
    urdf, mjcf = P.generated_pair("panda")
    mjcf = P.body_attr(mjcf, "panda_link2", "quat", lambda s: "0.707107 -0.70711 0 0")
    mjcf = P.body_attr(mjcf, "panda_link5", "pos", lambda s: "-0.0825 0.384 0")
    result = verify_files(
        *P.write_pair(tmp_path, urdf, mjcf),
        VerifyOptions(samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], extra={"dynamics_samples": 12}),
    )
    assert serious(result) == [] and result.passed
    rounding = [f for f in result.findings if f.kind == "rounding" and f.subject == "panda_link2"]
    assert len(rounding) == 1 and "0.70711" in rounding[0].message


def test_a_named_tool_frame_placed_elsewhere_on_its_link_is_an_error(tmp_path):
    """The MJCF's end_effector site sits 1 cm further out along link3 than the URDF's tool frame of
    that name: the joints and their motion agree, but a tool frame is where the tool is, so the
    offset is a difference (it fails the verdict), not a choice of link frame."""
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = P.sub_once(r'<site name="end_effector" pos="0.0 0.0 0.05"', '<site name="end_effector" pos="0.0 0.0 0.06"', mjcf)
    result = run(tmp_path, urdf, mjcf)
    assert [x for x in serious(result) if x[0] != "inexpressible"] == [("frame_offset", "end_effector")]
    assert result.verdict == "fail"
    (f,) = [f for f in result.findings if f.kind == "frame_offset"]
    assert f.severity == "error" and f.fails and f.unit == "m" and f.magnitude == pytest.approx(0.01, abs=1e-9)


def test_a_slide_moved_along_its_axis_is_one_zero_offset_carrying_its_range_and_follower(tmp_path):
    """The gripper's right finger follows the left one (URDF <mimic>, MJCF <equality joint>); the
    MJCF's left finger body sits 5 mm further along its slide, its range and the coupling left as
    written. One error: finger_left's zero offset of 5 mm, which says its range and its follower
    carry it (no limit_difference, no coupling_difference of 5 mm or of size 0 beside it)."""
    urdf, mjcf = P.generated_pair("gripper")
    urdf = P.sub_once(
        r'(<joint name="finger_right" type="prismatic">)', r'\1<mimic joint="finger_left" multiplier="1" offset="0"/>', urdf
    )
    mjcf = P.sub_once(
        r"</mujoco>",
        '<equality><joint joint1="finger_right" joint2="finger_left" polycoef="0 1 0 0 0"/></equality></mujoco>',
        mjcf,
    )
    mjcf = P.body_attr(mjcf, "finger_left_link", "pos", P.nums(lambda v: [v[0], v[1] + 5e-3, v[2]]))
    result = run(tmp_path, urdf, mjcf)
    errors = [f for f in result.findings if f.severity == "error"]
    assert [(f.kind, f.subject) for f in errors] == [("zero_offset", "finger_left")], [f.message for f in errors]
    (f,) = errors
    assert f.magnitude == pytest.approx(5e-3, abs=1e-9) and f.unit == "m"
    assert f.values["range_written_alike"] and f.values["couplings_written_alike"] == ["finger_right"]
    assert "finger_right follows finger_left" in f.message and result.verdict == "fail"
