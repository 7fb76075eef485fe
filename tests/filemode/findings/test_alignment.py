"""Findings of the alignment, each decision pinned by a pair built for it: a joint below a joint
that differs is measured in its own right, a zero offset of a whole turn's difference is no limit
difference, a constant turn of a link frame about its own joint is a convention, a floating
robot's base frames fix the frame."""

from __future__ import annotations

import math

import numpy as np
import pytest

import tests.filemode.findings.descs as D
import tests.filemode.pairs as P
from kinverify.filemode.align.attribution import Attribution
from kinverify.filemode.align.match import Matching
from kinverify.filemode.align.result import FrameFit, JointMap
from kinverify.filemode.findings.alignment import (
    _alike_axes,
    _downstream,
    alignment_findings,
    convention_findings,
    length_units,
    origin_findings,
)
from kinverify.filemode.pipeline import verify_files
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import spec_from_dict
from kinverify.run import VerifyOptions
from kinverify.suites.base import Finding

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


# --- each decision on hand-made descriptions: the URDF's chain a -> b -> c, the MJCF's A -> B -> C --


def tol(frame):
    return (1e-6, 1e-5)  # position m, rotation rad


def chain(types=("revolute",) * 3, frames=None, mtypes=None, mframes=None):
    names = ["a", "b", "c"]
    parents = [None, "a", "b"]
    u = D.desc("urdf", [D.joint(n, p, t) for n, p, t in zip(names, parents, types, strict=True)], frames=frames)
    mjoints = [D.joint(n.upper(), p and p.upper(), t) for n, p, t in zip(names, parents, mtypes or types, strict=True)]
    m = D.desc("mjcf", mjoints, frames=mframes)
    return u, m


COMPARED = ["a_link", "b_link", "c_link"]


def found(al, u=None, m=None, pairs=None, how="same name", compared=COMPARED):
    if u is None:
        u, m = chain()
    match = D.matching(pairs or [(j.urdf, j.mjcf) for j in al.joints], how)
    return [f for f in alignment_findings(u, m, match, al, compared, tol) if f.kind != "joint_names"]  # the MJCF's names: A, B, C


def maps(**kw):
    """The joint map a->A, b->B, c->C; ``kw``: joint -> (sign, offset)."""
    return [JointMap(n, n.upper(), "revolute", *kw.get(n, (1, 0.0))) for n in "abc"]


def test_what_a_joint_moves_is_its_frame_and_every_frame_below_it():
    u, _ = chain(frames={"tool": [0.0, 0.0, 0.5]})
    u.frame_owner["tool"] = "c"
    u.frame_owner["base"] = None
    u.frames["base"] = np.eye(4)
    assert sorted(_downstream(u, "a")) == ["a_link", "b_link", "c_link", "tool"]
    assert sorted(_downstream(u, "b")) == ["b_link", "c_link", "tool"]
    assert sorted(_downstream(u, "c")) == ["c_link", "tool"]


def test_identical_files_have_no_finding_and_a_renamed_joint_is_one_info_naming_how_it_was_matched():
    u, m = chain()
    same = D.desc("mjcf", [D.joint(j.name, j.parent) for j in u.joints])
    al = D.alignment([JointMap(n, n, "revolute") for n in "abc"])
    assert alignment_findings(u, same, D.matching([(n, n) for n in "abc"]), al, COMPARED, tol) == []
    m.joints[1].name, m.joints[2].name = "B2", "C2"
    al = D.alignment([JointMap("a", "A", "revolute"), JointMap("b", "B2", "revolute"), JointMap("c", "C2", "revolute")])
    match = Matching([("a", "A", "name"), ("b", "B2", "position"), ("c", "C2", "suffix")], [], [], [])
    (f,) = [f for f in alignment_findings(u, m, match, al, COMPARED, tol) if f.kind == "joint_names"]
    assert (f.severity, f.subject, f.other) == ("info", "a, b, c", "A, B2, C2")
    assert f.values == {"pairs": [["a", "A", "name"], ["b", "B2", "position"], ["c", "C2", "suffix"]]}
    assert f.message == "3 joints have other names in the MJCF (matched by name, position, suffix): a=A, b=B2, c=C2"


def test_the_world_transform_is_one_finding_with_its_move_its_turn_and_the_fit_it_came_from():
    t = np.eye(4)
    t[:3, :3] = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]  # a quarter turn about z
    t[:3, 3] = [0.25, 1e-13, 0.0]  # a noise term: zero
    (f,) = found(D.alignment(maps(), T=t, residual=(2e-7, 3e-8)))
    assert (f.kind, f.severity, f.unit) == ("base_transform", "error", "m|rad")
    assert f.magnitude == pytest.approx(math.pi / 2, rel=1e-12)
    assert f.values["xyz"] == [0.25, 0.0, 0.0] and f.values["rpy"] == pytest.approx([0.0, 0.0, math.pi / 2], abs=1e-15)
    assert f.values["translation_m"] == pytest.approx(0.25, rel=1e-12) and f.values["rotation_rad"] == pytest.approx(math.pi / 2)
    assert (f.values["residual_m"], f.values["residual_rad"]) == (2e-7, 3e-8)
    assert f.values["T_mjcf_from_urdf"][0] == [0.0, -1.0, 0.0, 0.25] and f.values["T_mjcf_from_urdf"][1][3] == 0.0
    assert f.message == (
        "the MJCF's world is the URDF's moved by xyz = [0.25, 0, 0] m, rpy = [0, 0, 1.5708] rad (90° turn): the same "
        "joint values put the robot elsewhere in the world; fitted over 0 frames and 3 axes, residual 2e-07 m, 3e-08 rad"
    )


def test_a_world_moved_only_or_turned_only_is_a_difference_and_below_double_precision_none():
    moved = np.eye(4)
    moved[:3, 3] = [0.0, 0.0, 2e-9]
    (f,) = found(D.alignment(maps(), T=moved))
    assert f.magnitude == pytest.approx(2e-9) and f.values["rotation_rad"] == 0.0
    turned = np.eye(4)
    turned[:3, :3] = [[1.0, 0.0, 0.0], [0.0, math.cos(2e-9), -math.sin(2e-9)], [0.0, math.sin(2e-9), math.cos(2e-9)]]
    turned[:3, 3] = [1e-10, 0.0, 0.0]  # below double precision: no move
    (g,) = found(D.alignment(maps(), T=turned))
    assert g.values["translation_m"] == 0.0 and g.values["xyz"] == [0.0, 0.0, 0.0]
    assert g.magnitude == pytest.approx(2e-9, rel=1e-6) and g.values["T_mjcf_from_urdf"][0][3] == 0.0
    tiny = np.eye(4)
    tiny[:3, 3] = [5e-10, 0.0, 0.0]
    assert found(D.alignment(maps(), T=tiny)) == []
    assert found(D.alignment(maps(), T=np.eye(4))) == []  # the same world exactly: nothing to say
    far = np.eye(4)
    far[:3, 3] = [3000.0, 2e-6, 0.0]  # 2e-6 is below the double precision at 3 km: zero
    (h,) = found(D.alignment(maps(), T=far))
    assert h.values["xyz"] == [3000.0, 0.0, 0.0] and h.values["T_mjcf_from_urdf"][1][3] == 0.0


def test_a_sign_flip_and_a_zero_offset_are_each_their_finding_moving_the_frames_below():
    (flip, zero) = found(D.alignment(maps(b=(-1, 0.5))), compared=["b_link", "c_link"])
    assert (flip.kind, flip.subject, flip.other) == ("axis_sign_flip", "b", "B")
    assert (zero.kind, zero.subject, zero.magnitude) == ("zero_offset", "b", 0.5)
    assert flip.values["moves"] == ["b_link", "c_link"] and zero.values["moves"] == ["b_link", "c_link"]
    (only,) = found(D.alignment(maps(c=(1, -0.25))), compared=["a_link", "b_link"])  # c moves no compared frame
    assert only.kind == "zero_offset" and only.values["moves"] == []


def test_a_joint_of_another_type_is_one_finding_and_its_axis_is_not_compared():
    u, m = chain(mtypes=("revolute", "prismatic", "revolute"))
    al = D.alignment(maps(), axis_errors={"b": (0.5, 0.5)})
    (f,) = found(al, u, m)
    assert (f.kind, f.severity, f.subject) == ("type_difference", "error", "b")
    assert f.values == {"urdf": "revolute", "mjcf": "prismatic", "frames": COMPARED[1:]}
    assert f.message == "joint b/B: revolute in the URDF, prismatic in the MJCF"


def test_an_axis_turned_beyond_the_rotation_tolerance_is_an_axis_direction_else_a_line_apart_an_axis_position():
    al = D.alignment(maps(), axis_errors={"b": (2e-5, 5.0), "c": (1e-5, 2e-6)})
    (direction, position) = found(al)
    assert (direction.kind, direction.subject, direction.magnitude, direction.unit) == ("axis_direction", "b", 2e-5, "rad")
    assert direction.values == {"angle_rad": 2e-5, "frames": ["b_link", "c_link"]}
    assert direction.message == (
        "joint b/B: the axes differ by 2e-05 rad (0.001146°) after alignment (and everything it moves with it)"
    )
    assert (position.kind, position.subject, position.magnitude, position.unit) == ("axis_position", "c", 2e-6, "m")
    assert position.values == {"distance_m": 2e-6, "frames": ["c_link"]}
    assert position.message == "joint c/C: the axis lines are 2e-06 m apart after alignment"
    assert found(D.alignment(maps(), axis_errors={"b": (1e-5, 1e-6)})) == []  # each at its tolerance: agrees


def test_a_joint_below_one_that_differs_is_measured_in_its_own_right_when_attributed():
    """b's frame moved (attributed); c's axis then 2 µm off: said after what b changes above it."""
    moved = Attribution("b", np.eye(4), moved=np.array([1e-3, 0.0, 0.0]), parent_frame="a_link")
    al = D.alignment(maps(), attribution={"b": moved, "c": Attribution("c", np.eye(4), axis=(0.0, 2e-6))})
    kinds = [(f.kind, f.subject) for f in found(al)]
    assert kinds == [("joint_origin_moved", "b"), ("axis_position", "c")]
    (c,) = [f for f in found(al) if f.subject == "c"]
    assert c.message == "joint c/C: the axis lines are 2e-06 m apart in its own right, after what b changes above it"
    # the same axis error without an attribution of c: after alignment, as the fit leaves it
    al = D.alignment(maps(), attribution={"b": moved}, axis_errors={"c": (0.0, 2e-6)})
    assert [f for f in found(al) if f.subject == "c"][0].message.endswith("apart after alignment")
    # a difference above that is no frame of its own (an axis) also makes c's measured in its own right
    al = D.alignment(maps(), axis_errors={"a": (1.0, 0.0)}, attribution={"c": Attribution("c", np.eye(4), axis=(0.0, 2e-6))})
    assert found(al)[-1].message.endswith("in its own right, after what a changes above it")
    # nothing differing above: after alignment
    al = D.alignment(maps(), attribution={"c": Attribution("c", np.eye(4), axis=(0.0, 2e-6))})
    assert found(al)[-1].message.endswith("2e-06 m apart after alignment")


def test_a_moved_joint_frame_says_the_offset_vector_where_it_sits_and_what_it_carries():
    att = Attribution("b", np.eye(4), moved=np.array([3e-3, 4e-3, 0.0]), parent_frame="a_link")
    (f,) = origin_findings(att, ["b_link", "c_link"], {"joint": "b", "mjcf_joint": "B"})
    assert (f.kind, f.severity, f.subject, f.other, f.unit) == ("joint_origin_moved", "error", "b", "B", "m")
    assert f.magnitude == pytest.approx(5e-3, rel=1e-12)
    assert f.values["xyz"] == [3e-3, 4e-3, 0.0] and f.values["frames"] == ["b_link", "c_link"]
    assert f.values["distance_m"] == pytest.approx(5e-3, rel=1e-12)
    assert f.message == (
        "joint b/B: its frame sits 0.005 m from the URDF's on a_link (moved by xyz [0.003, 0.004, 0] m in a_link axes): "
        "everything it carries moved with it"
    )
    world = Attribution("a", np.eye(4), moved=np.array([0.0, 0.0, 1e-3]))
    (g,) = origin_findings(world, ["a_link"], {"joint": "a", "mjcf_joint": "A"})
    assert (
        g.message == "joint a/A: its frame sits 0.001 m from the URDF's in the world (moved by xyz [0, 0, 0.001] m in world axes)"
    )


def test_a_frame_placed_from_a_merged_base_link_says_so_once():
    att = Attribution("a", np.eye(4), moved=np.array([0.0, 0.0, 1e-3]), parent_frame="base", merged_base="base")
    names = {"joint": "a", "mjcf_joint": "A"}
    (f,) = origin_findings(att, ["a_link"], names)
    assert "on base (the URDF's on its base link base, which the MJCF merges into its world) (moved by" in f.message
    placed = Attribution(
        "a", np.eye(4), moved=np.array([0.0, 0.0, 1e-3]), parent_frame="base", merged_base="base", base_placed=True
    )
    (g,) = origin_findings(placed, ["a_link"], names)
    assert "which the MJCF merges into its world; equally, where the URDF places that base link in its world) (moved" in g.message


def test_a_turned_joint_frame_says_its_axis_angle_tilt_twist_and_a_folded_zero_offset():
    att = Attribution("b", np.eye(4), turn=np.array([0.0, 0.0, -0.2]), parent_frame="a_link", tilt_twist=(0.0, 0.2))
    names = {"joint": "b", "mjcf_joint": "B"}
    (f,) = origin_findings(att, ["b_link"], names)
    assert (f.kind, f.unit, f.subject) == ("joint_origin_turned", "rad", "b") and f.magnitude == pytest.approx(0.2)
    assert f.values == {
        "angle_rad": pytest.approx(0.2),
        "axis": [0.0, 0.0, -1.0],
        "rotation_vector": [0.0, 0.0, -0.2],
        "tilt_rad": 0.0,
        "twist_rad": 0.2,
        "zero_offset": 0.0,
        "frames": ["b_link"],
    }
    assert f.message == (
        "joint b/B: its frame is turned by 0.2 rad (11.46°) about [0, 0, -1] (its own axes) from the URDF's on a_link "
        "(its axis tilted 0° and turned 11.46° about itself)"
    )
    both = Attribution(
        "b", np.eye(4), moved=np.array([1e-3, 0, 0]), turn=np.array([0.1, 0, 0]), tilt_twist=(0.1, 0.0), folded=0.05
    )
    moved, turned = origin_findings(both, ["b_link", "c_link"], names)
    assert moved.kind == "joint_origin_moved" and turned.values["zero_offset"] == 0.05
    assert turned.message.endswith(
        "(its axis tilted 5.73° and turned 0° about itself; the 0.05 rad a zero offset would take is part of it): "
        "everything it carries moved with it"
    )


def test_joints_that_differ_alike_are_one_finding_naming_them_all():
    legs = [
        Attribution(n, np.eye(4), moved=np.array([s * 2.5e-3, 0.0, 0.0]), parent_frame="trunk") for n, s in (("a", 1), ("b", -1))
    ]
    single = [
        origin_findings(att, [f"{att.joint}_link"], {"joint": att.joint, "mjcf_joint": att.joint.upper()})[0] for att in legs
    ]
    other = origin_findings(
        Attribution("c", np.eye(4), moved=np.array([2.501e-3, 0.0, 0.0])), ["c_link"], {"joint": "c", "mjcf_joint": "C"}
    )[0]
    note = Finding("zero_offset", "error", "z", "z", magnitude=2.5e-3)  # alike in size, but no axis or frame
    out = _alike_axes([single[0], note, single[1], other])
    assert [f.kind for f in out] == ["joint_origin_moved", "zero_offset", "joint_origin_moved"]
    legs_f = out[0]
    assert (legs_f.subject, legs_f.other, legs_f.magnitude, legs_f.unit) == ("a, b", "A, B", 2.5e-3, "m")
    assert legs_f.values["xyz_each"] == [[2.5e-3, 0.0, 0.0], [-2.5e-3, 0.0, 0.0]]
    assert legs_f.values["frames"] == ["a_link", "b_link"]
    assert legs_f.message == (
        "2 joints alike: a, b: each frame sits 0.0025 m from the URDF's on its parent (xyz [0.0025, 0, 0], [-0.0025, 0, 0] "
        "m in the parents' axes)"
    )
    assert out[2] is other  # 2.501 mm: not alike to 4 significant digits


def test_joints_turned_alike_or_with_axes_alike_are_one_finding_each():
    names = {"joint": "a", "mjcf_joint": "A"}
    turns = [
        origin_findings(Attribution(n, np.eye(4), turn=np.array(v)), [f"{n}_link"], {**names, "joint": n})[0]
        for n, v in (("a", [0.0, 0.0, 0.1]), ("b", [0.1, 0.0, 0.0]))
    ]
    (f,) = _alike_axes(turns)
    assert f.subject == "a, b" and f.values["axis_each"] == [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]
    assert f.message == "2 joints alike: a, b: each frame is turned by 0.1 rad (5.73°) from the URDF's"
    al = D.alignment(maps(), axis_errors={"b": (2e-5, 0.0), "c": (2e-5, 0.0)})
    (g,) = found(al)
    assert (g.kind, g.subject, g.values["frames"]) == ("axis_direction", "b, c", ["b_link", "c_link", "c_link"])
    assert (
        g.message
        == "2 joints alike: b, c: the axes differ by 2e-05 rad (0.001146°) after alignment (and everything it moves with it)"
    )


def fit(urdf="f", mjcf="F", why="same name", position=0.0, rotation=0.0, xyz=(0.0, 0.0, 0.0), angle=0.0, residual=(0.0, 0.0)):
    c = np.eye(4)
    c[:3, :3] = [[math.cos(angle), -math.sin(angle), 0.0], [math.sin(angle), math.cos(angle), 0.0], [0.0, 0.0, 1.0]]
    c[:3, 3] = xyz
    return FrameFit(urdf, mjcf, why, position, rotation, c, *residual, True)


def conventions(*fits, kinds=None, moved=frozenset()):
    return convention_findings(D.alignment(maps(), frames=list(fits)), kinds or {}, tol, moved)


def test_a_link_frame_off_by_a_constant_is_a_convention_sized_by_its_turn_or_else_its_shift():
    (f,) = conventions(fit(position=3e-3, rotation=0.5, xyz=(3e-3, 0.0, 0.0), angle=0.5))
    assert (f.kind, f.severity, f.subject, f.other, f.unit) == ("frame_convention", "info", "f", "F", "rad")
    assert f.magnitude == pytest.approx(0.5) and f.values["translation_m"] == pytest.approx(3e-3)
    assert f.values["rpy"] == pytest.approx([0.0, 0.0, 0.5]) and f.values["xyz"] == [3e-3, 0.0, 0.0]
    assert f.values["frames"] == ["f"] and f.values["rotation_rad"] == pytest.approx(0.5)
    assert f.message == (
        "frame f/F: the files define this frame differently, by a constant 0.5 rad (28.65°) and 0.003 m (rpy [0, 0, 0.5], "
        "xyz [0.003, 0, 0]); the joint and its motion agree, so it is compared after removing that constant"
    )
    (g,) = conventions(fit(position=3e-3, xyz=(3e-3, 0.0, 0.0), angle=1e-5))  # a turn within tolerance: the shift
    assert (g.unit, g.magnitude) == ("m", pytest.approx(3e-3))


def test_a_frame_within_tolerance_or_not_constant_or_already_moved_is_no_convention():
    assert conventions(fit(position=1e-6, rotation=1e-5, xyz=(1e-6, 0, 0))) == []  # at the tolerances: agrees
    assert len(conventions(fit(position=2e-6, rotation=1e-5, xyz=(2e-6, 0, 0)))) == 1
    assert len(conventions(fit(position=1e-6, rotation=2e-5, angle=2e-5))) == 1
    assert conventions(fit(position=1.0, xyz=(1.0, 0, 0), residual=(2e-6, 0.0))) == []  # not a constant
    assert conventions(fit(position=1.0, xyz=(1.0, 0, 0), residual=(0.0, 2e-5))) == []
    assert len(conventions(fit(position=1.0, xyz=(1.0, 0, 0), residual=(1e-6, 1e-5)))) == 1  # residual at tolerance: constant
    assert conventions(fit(position=1.0, xyz=(1.0, 0, 0)), moved={"f"}) == []


def test_a_named_frame_elsewhere_is_an_error_a_look_alike_an_info_and_a_turned_site_a_convention():
    site = {"f": "site"}
    (f,) = conventions(fit(position=0.01, xyz=(0.0, 0.0, 0.01)), kinds=site)
    assert (f.kind, f.severity, f.magnitude, f.unit) == ("frame_offset", "error", pytest.approx(0.01), "m")
    assert f.message == (
        "frame f/F: placed 0.01 m and 0 rad away from the other file's, on the same link (xyz [0, 0, 0.01] in its own axes)"
    )
    (given,) = conventions(fit(why="given", position=0.01, xyz=(0.0, 0.0, 0.01)), kinds=site)
    assert given.kind == "frame_offset"
    (twin,) = conventions(fit(why="similar name", position=0.01, xyz=(0.0, 0.0, 0.01)), kinds=site)
    assert (twin.kind, twin.severity, twin.magnitude) == ("frame_twin", "info", pytest.approx(0.01))
    assert twin.message == (
        "URDF frame f and the MJCF's site F have similar names but sit 0.01 m and 0 rad apart on the same link: not taken "
        "for one frame (compared after removing that offset)"
    )
    (turned,) = conventions(fit(position=1e-6, rotation=0.5, xyz=(1e-6, 0, 0), angle=0.5), kinds=site)
    assert turned.kind == "frame_convention"  # a site turned on its spot: no place differs
    (link,) = conventions(fit(position=0.01, xyz=(0.0, 0.0, 0.01)), kinds={"f": "link"})
    assert link.kind == "frame_convention"


def test_lengths_a_constant_multiple_apart_are_a_units_finding():
    frames = {"a_link": [0, 0, 0], "b_link": [0.0, 0.0, 0.1], "c_link": [0.0, 0.3, 0.1]}  # 0.1 + 0.3 long
    u, _ = chain(frames=frames)
    pairs = D.matching([("a", "A"), ("b", "B"), ("c", "C")])

    def scaled(k):
        _, m = chain(mframes={n.upper(): [k * x for x in v] for n, v in frames.items()})
        m.frames = {f"{n[0].upper()}_link": m.frames[n.upper()] for n in frames}
        return length_units(u, m, pairs, ["c_link"])

    (f,) = scaled(1000.0)
    assert (f.kind, f.severity, f.unit) == ("length_units", "error", "") and f.magnitude == pytest.approx(1000.0)
    assert f.values["frames"] == ["c_link"] and f.values["ratio"] == pytest.approx(1000.0)
    assert f.values["checks"] == [
        ["inertia.mass", "rigid bodies"],
        ["inertia.com", "rigid bodies"],
        ["inertia.tensor", "rigid bodies"],
    ]
    assert (
        f.message
        == "the MJCF's lengths are the URDF's ×1000 (millimetres as metres in the MJCF?): every link is 1000 times as long"
    )
    assert "(inches as metres in the URDF?)" in scaled(1 / 0.0254)[0].message
    assert scaled(1.0) == [] and scaled(1.005) == [] and scaled(1.5) == [] and scaled(0.0) == []


def test_a_zero_offset_is_judged_with_the_limits_tolerance_and_the_couplings_written_alike():
    """a's zero 0.25 further, its range [−1, 2] and the coupling b = 1·a written alike in each file:
    the offset sets both apart (said in its finding); with a limits tolerance of 0.5 the range's
    0.25 is no difference to explain."""
    u = D.desc("urdf", [D.joint("a"), D.joint("b", "a")], [D.couple("b", "a")])
    m = D.desc("mjcf", [D.joint("A"), D.joint("B", "A")], [D.couple("B", "A", source="<equality joint>")])
    al = D.alignment([JointMap("a", "A", "revolute", 1, 0.25), JointMap("b", "B", "revolute")])
    match = D.matching([("a", "A"), ("b", "B")])
    (zero,) = [f for f in alignment_findings(u, m, match, al, COMPARED, tol) if f.kind == "zero_offset"]
    assert zero.values["range_written_alike"] and zero.values["couplings_written_alike"] == ["b"]
    (loose,) = [f for f in alignment_findings(u, m, match, al, COMPARED, tol, 0.5) if f.kind == "zero_offset"]
    assert "range_written_alike" not in loose.values and loose.values["couplings_written_alike"] == ["b"]


def test_a_joint_below_one_of_another_type_is_measured_in_its_own_right():
    u, m = chain(mtypes=("revolute", "prismatic", "revolute"))
    al = D.alignment(maps(), attribution={"c": Attribution("c", np.eye(4), axis=(0.0, 2e-6))})
    (kind, axis) = found(al, u, m)
    assert (kind.kind, axis.kind, axis.subject) == ("type_difference", "axis_position", "c")
    assert axis.message.endswith("apart in its own right, after what b changes above it")
