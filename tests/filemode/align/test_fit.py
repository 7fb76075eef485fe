"""Alignment on random arms: a random world transform, random joint zero offsets and random
axis reversals put into one file are recovered exactly, each reported once, and nothing else
above information is reported (the checks compare after them and pass)."""

from __future__ import annotations

import math
import re
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from kinverify.filemode.align.fit import TOL, Aligner, _apply, _carry, _crossing, _gauss_newton, _is_identity, _line_local, align
from kinverify.filemode.align.match import Matching, match
from kinverify.filemode.align.result import Alignment, PairPoses
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.precision import Floors
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import spec_from_dict
from kinverify.model.transforms import axis_angle_to_matrix, matrix_to_quat, rpy_to_matrix
from kinverify.run import VerifyOptions
from kinverify.testing.strategies import angles_rpy, arm_specs, vectors
import tests.filemode.pairs as P
from tests.filemode.pairs import joint_attr, nums
from kinverify.filemode.align.geometry import line_distance
from tests.filemode.align.test_floating import floating_arm3

FAST = VerifyOptions(
    samples=6, fd_samples=3, backends=["pinocchio-urdf", "mujoco"], extra={"dynamics_samples": 8}, suites=P.NO_PICTURES
)
SETTINGS = settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def move_world(mjcf: str, xyz, rpy) -> str:
    quat = matrix_to_quat(rpy_to_matrix(rpy))
    pose = f'pos="{" ".join(repr(float(v)) for v in xyz)}" quat="{" ".join(repr(float(v)) for v in quat)}"'
    return mjcf.replace('<body name="world_mount">', f'<body name="world_mount" {pose}>', 1)


def remap_joint(mjcf: str, joint: str, sign: int, offset: float) -> str:
    """The MJCF's joint with q_mjcf = sign·q_urdf + offset: axis reversed when sign < 0, ``ref``
    at the offset, the range carried along (the same physical limits)."""
    mjcf = joint_attr(mjcf, joint, "range", nums(lambda v: sorted([sign * v[0] + offset, sign * v[1] + offset])))
    if sign < 0:
        mjcf = joint_attr(mjcf, joint, "axis", nums(lambda v: [-x for x in v]))
    if offset:
        mjcf = re.sub(rf'(<joint name="{joint}" )', lambda m: m[1] + f'ref="{offset!r}" ', mjcf, count=1)
    return mjcf


def observable(desc, joint: str) -> bool:
    """Whether a zero offset of ``joint`` moves a point: a next joint's axis line that does not
    meet its axis, or a frame it carries off its axis (prismatic: always). When everything it
    moves sits on its axis, a turn by it is only a change of frame conventions."""
    j = desc.joint(joint)
    if j.type == "prismatic":
        return True

    def off_axis(p):
        d = p - j.anchor
        return np.linalg.norm(d - (d @ j.axis) * j.axis) > 1e-3

    for c in desc.joints:
        if c.parent == joint and line_distance(j.anchor, j.axis, c.anchor, c.axis) > 1e-3:
            return True
    return any(off_axis(pose[:3, 3]) for f, pose in desc.frames.items() if desc.frame_owner.get(f) == joint)


def sign_observable(desc, joint: str, shared=None) -> bool:
    """Whether reversing ``joint``'s axis can be told from turning the world by π: not when it is
    the first joint and everything it moves (frame origins, the next joints' anchors and axis
    points) lies on one line ℓ that meets its axis at a right angle, with every base frame on its
    axis or on ℓ: a half-turn about ℓ maps the whole robot onto itself with the joint reversed."""
    j = desc.joint(joint)
    if j.parent is not None or j.type != "revolute":
        return True

    def on_axis(p):
        d = p - j.anchor
        return np.linalg.norm(d - (d @ j.axis) * j.axis) <= 1e-9

    roots = [
        pose[:3, 3] for f, pose in desc.frames.items() if desc.frame_owner.get(f) is None and (shared is None or f in shared)
    ]
    points = [pose[:3, 3] for f, pose in desc.frames.items() if desc.frame_owner.get(f) is not None]
    points += [p for c in desc.joints if c.name != joint for p in (c.anchor, c.anchor + c.axis)]
    points += [r for r in roots if not on_axis(r)]  # a base frame off the axis must lie on ℓ too
    if not points:
        return False
    d = np.array(points) - j.anchor
    if np.abs(d @ j.axis).max() > 1e-9:  # off the perpendicular plane through the anchor: on no such line
        return True
    return np.linalg.matrix_rank(d, tol=1e-9) > 1


def world_observable(desc, shared) -> bool:
    """Whether a world transform can be told from another: not when every frame origin and joint
    axis lies on one line, about which a turn moves no point (only link frames, a file's choice).
    ``shared``: the frames the other file has too."""
    points = [pose[:3, 3] for f, pose in desc.frames.items() if f in shared]
    points += [p for c in desc.joints for p in (c.anchor, c.anchor + c.axis)]
    d = np.array(points) - points[0]
    return np.linalg.matrix_rank(d, tol=1e-9) > 1


def verify(urdf: str, mjcf: str):
    with tempfile.TemporaryDirectory() as folder:
        (Path(folder) / "r.urdf").write_text(urdf)
        (Path(folder) / "r.xml").write_text(mjcf)
        return verify_files(str(Path(folder) / "r.urdf"), str(Path(folder) / "r.xml"), FAST)


def above_info(result) -> list[tuple[str, str]]:
    return sorted((f.kind, f.subject) for f in result.findings if f.severity != "info")


@SETTINGS
@given(spec=arm_specs(max_joints=4), xyz=vectors(-1.0, 1.0), rpy=angles_rpy())
def test_a_random_world_transform_is_recovered_exactly_and_alone(spec, xyz, rpy):
    urdf, mjcf = generate_urdf(spec), generate_mjcf(spec)
    assume(np.linalg.norm(xyz) > 1e-6 or max(abs(x) for x in rpy) > 1e-6)
    assume(world_observable(describe_urdf(urdf), describe_mjcf(mjcf).frames))
    result = verify(urdf, move_world(mjcf, xyz, rpy))
    t = np.array(result.sections["filemode"].data["alignment"]["T_mjcf_from_urdf"])
    assert np.allclose(t[:3, 3], xyz, atol=1e-9) and np.allclose(t[:3, :3], rpy_to_matrix(rpy), atol=1e-9)
    assert above_info(result) == [("base_transform", "")] and not result.failed


def test_a_prismatic_zero_offset_is_seen_across_a_nearly_parallel_next_axis():
    """Found by hypothesis: j3 slides along (1, 0.0625, 0) and j4's axis runs along x (3.6° apart),
    all frames at the origin. The MJCF's j3 zero sits 0.125 m further. j4's axis line, taken where
    it crosses a plane across j3's axis, moves only by the part of the shift across it (7.8 mm):
    the shift is still a zero offset of j3, not a frame convention of l3 and a moved j4."""

    def joint(name, kind, axis, rpy=(0.0, 0.0, 0.0)):
        upper, unit = (1.0, "rad") if kind == "revolute" else (0.25, "m")
        return {
            "name": name,
            "type": kind,
            "xyz": [0.0, 0.0, 0.0],
            "rpy": list(rpy),
            "axis": axis,
            "limits": {"lower": 0.0, "upper": upper, "unit": unit},
            "link": {"name": "l" + name[1:], "mass": 1.0},
        }

    spec = spec_from_dict(
        {
            "name": "slide",
            "joints": [
                joint("j1", "revolute", [1, 0, 0]),
                joint("j2", "revolute", [1, 0, 0]),
                joint("j3", "prismatic", [1.0, 0.0625, 0.0]),
                joint("j4", "revolute", [0, 0, 1], (math.pi / 2, 0.0, math.pi / 2)),
            ],
            "tools": [{"name": "tool", "parent": "l4", "xyz": [0.0, 0.0, 0.0], "rpy": [0.0, 0.0, 0.0]}],
        }
    )
    result = verify(generate_urdf(spec), remap_joint(generate_mjcf(spec), "j3", 1, 0.125))
    joints = {j["urdf"]: j for j in result.sections["filemode"].data["alignment"]["joints"]}
    assert joints["j3"]["offset"] == pytest.approx(0.125, abs=1e-9)
    assert above_info(result) == [("zero_offset", "j3")] and not result.failed


@SETTINGS
@given(spec=arm_specs(max_joints=4), data=st.data())
def test_random_zero_offsets_and_reversed_axes_are_recovered_exactly_and_alone(spec, data):
    urdf, mjcf = generate_urdf(spec), generate_mjcf(spec)
    desc = describe_urdf(urdf)
    expected = {}
    for joint in desc.joints:
        sign = data.draw(st.sampled_from([1, 1, -1]), label=f"sign {joint.name}")
        if sign < 0 and not sign_observable(desc, joint.name, describe_mjcf(mjcf).frames):
            sign = 1
        span = math.pi if joint.type == "revolute" else 0.2
        offset = data.draw(
            st.sampled_from([0.0, 0.0]) | st.floats(-span, span).filter(lambda x: abs(x) > 1e-3), label=f"offset {joint.name}"
        )
        if offset and not observable(desc, joint.name):
            offset = 0.0
        if sign < 0 or offset:
            expected[joint.name] = (sign, offset)
            mjcf = remap_joint(mjcf, joint.name, sign, offset)
    assume(expected)
    result = verify(urdf, mjcf)
    joints = {j["urdf"]: j for j in result.sections["filemode"].data["alignment"]["joints"]}
    for name, j in joints.items():
        sign, offset = expected.get(name, (1, 0.0))
        gap = j["offset"] - offset
        if j["type"] == "revolute":  # +π and −π are the same zero
            gap = math.remainder(gap, 2 * math.pi)
        assert j["sign"] == sign and abs(gap) <= 1e-9, (name, j, expected)
    wanted = sorted(
        [("axis_sign_flip", n) for n, (s, _) in expected.items() if s < 0]
        + [("zero_offset", n) for n, (_, o) in expected.items() if o]
    )
    assert above_info(result) == wanted and not result.failed


def test_a_turn_within_the_next_frames_written_precision_is_not_a_zero_offset():
    """As in a public 7-axis arm pair: the URDF turns panda_link7's frame 2.1e-8 rad about joint 6's
    axis (a quarter turn computed, then printed), the MJCF writes that body's quaternion to 6
    decimals (a rounding of up to 2e-6 rad). Joint 6's zero offset is measured on joint 7's axis,
    inside panda_link7: the turn is that frame's rounding, not an offset of joint 6."""
    urdf, mjcf = P.generated_pair("panda")
    urdf = urdf.replace(
        '<origin xyz="0.088 0.0 0.0" rpy="1.5707963267948966 0.0 0.0"/>',
        '<origin xyz="0.088 0.0 0.0" rpy="1.5707963267948966 0.0 2.1073424e-08"/>',
        1,
    )
    mjcf = P.body_attr(mjcf, "panda_link7", "quat", lambda s: "0.707107 0.707107 0 0")
    result = verify(urdf, mjcf)
    joints = {j["urdf"]: j for j in result.sections["filemode"].data["alignment"]["joints"]}
    assert all(j["offset"] == 0.0 and j["sign"] == 1 for j in joints.values()), joints
    assert above_info(result) == [] and not result.failed


def test_a_prismatic_zero_offset_is_read_off_the_next_axis_when_its_body_differs_too():
    """As in a public mobile manipulator's pair: the MJCF's lift (j2) sits 0.3 m higher at the same
    q, and its body's centre of mass differs on its own (2 cm). The next axis shows the shift in
    full: a zero offset of j2 and a centre of mass, not frame conventions and a moved j3."""

    def joint(name, kind, axis, xyz, upper):
        unit = "rad" if kind == "revolute" else "m"
        return {
            "name": name,
            "type": kind,
            "xyz": xyz,
            "rpy": [0.0, 0.0, 0.0],
            "axis": axis,
            "limits": {"lower": 0.0, "upper": upper, "unit": unit},
            "link": {"name": "l" + name[1:], "mass": 1.0},
        }

    spec = spec_from_dict(
        {
            "name": "lift",
            "joints": [
                joint("j1", "revolute", [0, 0, 1], [0.0, 0.0, 0.1], 1.0),
                joint("j2", "prismatic", [0, 0, 1], [0.0, 0.0, 0.1], 1.0),
                joint("j3", "revolute", [1, 0, 0], [0.2, 0.0, 0.0], 1.0),
            ],
            "tools": [{"name": "tool", "parent": "l3", "xyz": [0.1, 0.0, 0.0], "rpy": [0.0, 0.0, 0.0]}],
        }
    )
    mjcf = remap_joint(generate_mjcf(spec), "j2", 1, 0.3)
    mjcf = P.sub_once(
        r'(<body name="l2".*?<inertial pos=")([^"]*)(")',
        lambda m: m[1] + nums(lambda v: [v[0] + 0.02, v[1], v[2]])(m[2]) + m[3],
        mjcf,
    )
    result = verify(generate_urdf(spec), mjcf)
    joints = {j["urdf"]: j for j in result.sections["filemode"].data["alignment"]["joints"]}
    assert joints["j2"]["offset"] == pytest.approx(0.3, abs=1e-9)
    assert above_info(result) == [("com_difference", "l2"), ("zero_offset", "j2")]


def test_two_floating_files_keep_their_base_frames_when_those_explain_everything():
    # both bases float: the base bodies fix the frame (the identity, solved without refitting) and
    # nothing is left unexplained, so no world transform is reported
    result = verify(*floating_arm3())
    assert result.exit_code == 0 and result.passed
    assert "base_transform" not in [f.kind for f in result.findings]


def test_a_tilted_axis_between_two_crossing_axes_is_that_tilt_alone_not_a_zero_offset():
    """As on a public four-finger hand (the finger's MCP pair): j9 flexes the finger's base, j8
    (its abduction) is crossed 1.5 cm on by j10's flexion axis. The MJCF's j8 axis is tilted by
    2.81° within its frame (only its ``axis`` edited). At the zero nothing else differs, but j10's
    axis line meets the tilted axis elsewhere, which a turn about j8 seems to explain (a zero
    offset of 2.19°): it leaves the same differences over the sampled configurations as the tilt
    alone, so the tilt alone is the difference, said once, with nothing below blamed for it."""

    def joint(name, xyz, rpy, lower, upper, link):
        limits = {"lower": lower, "upper": upper, "unit": "rad"}
        return {"name": name, "xyz": xyz, "rpy": rpy, "axis": [0, 0, -1], "limits": limits, "link": {"name": link, "mass": 0.03}}

    h = 1.57079
    spec = spec_from_dict(
        {
            "name": "finger",
            "joints": [
                joint("j9", [-0.00709, -0.0678, -0.0187], [h, h, 0.0], -0.314, 2.23, "mcp"),
                joint("j8", [-0.0122, 0.0381, 0.0145], [-h, 0.0, h], -1.047, 1.047, "pip"),
                joint("j10", [0.015, 0.0143, -0.013], [h, -h, 0.0], -0.506, 1.885, "dip"),
            ],
        }
    )
    tilted = [-0.01758170473150989, -0.04574548585153592, -0.99879839516438]  # 0.0490275 rad off (0, 0, -1)
    result = verify(generate_urdf(spec), joint_attr(generate_mjcf(spec), "j8", "axis", nums(lambda _: tilted)))
    joints = {j["urdf"]: j for j in result.sections["filemode"].data["alignment"]["joints"]}
    assert all(j["offset"] == 0.0 and j["sign"] == 1 for j in joints.values()), joints
    errors = [(f.kind, f.subject, f.magnitude) for f in result.findings if f.severity == "error"]
    assert [e[:2] for e in errors] == [("axis_direction", "j8")], errors
    assert errors[0][2] == pytest.approx(math.acos(-tilted[2]), rel=1e-6)


# --- each decision of the aligner, on small pairs built here (no pipeline) ---------------------


def bent_spec():
    """Four joints whose every zero offset moves a point off its axis: j1 (z) carries j2 (y) 0.1 m
    out, j2 a prismatic j3 (x) 5 cm aside, j3 a j4 tilted 0.3 rad about x, j4 a tool off its axis."""

    def joint(name, kind, axis, xyz, rpy=(0.0, 0.0, 0.0), upper=1.0):
        unit = "rad" if kind == "revolute" else "m"
        limits = {"lower": -upper, "upper": upper, "unit": unit}
        return {"name": name, "type": kind, "xyz": list(xyz), "rpy": list(rpy), "axis": axis, "limits": limits,
                "link": {"name": "l" + name[1:], "mass": 1.0}}  # fmt: skip

    return spec_from_dict(
        {
            "name": "bent",
            "joints": [
                joint("j1", "revolute", [0, 0, 1], [0.0, 0.0, 0.1]),
                joint("j2", "revolute", [0, 1, 0], [0.1, 0.0, 0.2]),
                joint("j3", "prismatic", [1, 0, 0], [0.2, 0.05, 0.0], upper=0.2),
                joint("j4", "revolute", [0, 0, 1], [0.1, 0.0, 0.05], rpy=(0.3, 0.0, 0.0)),
            ],
            "tools": [{"name": "tool", "parent": "l4", "xyz": [0.05, 0.02, 0.0], "rpy": [0.0, 0.0, 0.0]}],
        }
    )


BENT = (generate_urdf(bent_spec()), generate_mjcf(bent_spec()))
ARM3 = P.generated_pair("arm3")
Q4 = np.array([[0.3, -0.4, 0.05, 0.7], [-0.6, 0.2, -0.1, -0.3], [0.9, 0.5, 0.15, 0.1]])  # bent's samples
Q3 = np.array([[0.3, -0.4, 0.7], [-0.6, 0.2, -0.3], [1.2, 0.5, 0.1]])  # arm3's samples


def aligner(urdf: str, mjcf: str, samples=None, floors=None) -> Aligner:
    u, m = describe_urdf(urdf), describe_mjcf(mjcf)
    matching = match(u, m)
    n = len(matching.independent)
    q = np.zeros((0, n)) if samples is None else samples
    return Aligner(PairPoses(u, m, matching, urdf, mjcf), matching, floors or Floors(), q)


def solved(urdf: str, mjcf: str, samples=None, floors=None, **kw) -> Alignment:
    a = aligner(urdf, mjcf, samples, floors)
    return align(a.p, a.matching, a.floors, a.q[1:], **kw)


def turn(axis, angle: float) -> np.ndarray:
    return axis_angle_to_matrix(np.asarray(axis, float) / np.linalg.norm(axis), np.array([angle]))[0]


def pose(rot=None, xyz=(0.0, 0.0, 0.0)) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = np.eye(3) if rot is None else rot, xyz
    return t


def joint_map(al: Alignment) -> dict:
    return {j.urdf: (j.sign, j.offset) for j in al.joints}


def test_a_joints_axis_line_is_read_in_its_moving_frame():
    # j4's frame is turned 0.3 rad about x: the world axis (0, -sin 0.3, cos 0.3) is z in the frame;
    # the MJCF places the axis 1 cm and 2 cm off the body origin (joint pos)
    u = describe_urdf(BENT[0])
    m = describe_mjcf(P.sub_once(r'(<joint name="j4" )', r'\1pos="0.01 0.02 0" ', BENT[1]))
    for desc, point in ((u, [0.0, 0.0, 0.0]), (m, [0.01, 0.02, 0.0])):
        axis, at = _line_local(desc, "j4")
        assert axis == pytest.approx([0.0, 0.0, 1.0], abs=1e-12)
        assert at == pytest.approx(point, abs=1e-12)


def test_the_small_geometric_helpers():
    t = pose(turn([0, 0, 1], math.pi / 2), (1.0, 2.0, 3.0))
    assert _apply(t, np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])) == pytest.approx(np.array([[1.0, 3.0, 3.0], [1.0, 2.0, 4.0]]))
    # the line (1, 1, 0) + s·(1, 0, 2) crosses the plane z = 1 at s = 1/2
    x = _crossing(np.array([5.0, 5.0, 1.0]), np.array([0.0, 0.0, 2.0]), np.array([1.0, 1.0, 0.0]), np.array([1.0, 0.0, 2.0]))
    assert x == pytest.approx([1.5, 1.0, 1.0])
    poses = np.stack([t, pose(xyz=(0.0, 0.0, -1.0))])
    assert _carry(poses, np.array([0.0, 1.0, 0.0])) == pytest.approx(np.array([[0.0, 2.0, 3.0], [0.0, 1.0, -1.0]]))


def test_the_identity_is_exact_to_double_precision_per_metre_of_robot():
    scale = 10.0
    assert _is_identity(pose(xyz=(0.0, 0.9 * TOL * scale, 0.0)), scale)
    assert not _is_identity(pose(xyz=(0.0, 1.1 * TOL * scale, 0.0)), scale)
    assert not _is_identity(pose(xyz=(0.0, 0.0, -1.1 * TOL * scale)), scale)
    assert _is_identity(pose(turn([0, 1, 0], 0.9 * TOL)), scale)
    assert not _is_identity(pose(turn([0, 1, 0], 1.5 * TOL)), scale)


def point_feature(name, a, t, tol=(1.0, 1.0)):
    return (name, "point", a, _apply(t, a), tol)


def line_feature(name, t, ua, up, slide=0.0, tol=(1.0, 1.0)):
    ma = ua @ t[:3, :3].T
    return (name, "line", (ua, up), (ma, _apply(t, up) + slide * ma), tol)


def test_gauss_newton_recovers_a_transform_from_points_and_from_lines():
    true = pose(turn([1, 2, 3], 0.4), (0.1, -0.2, 0.3))
    a = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.5], [0.3, -0.2, 1.0]])
    assert _gauss_newton([point_feature("p", a, true)], np.eye(4)) == pytest.approx(true, abs=1e-12)
    # three axis lines (directions and a point each), the MJCF's points slid along its lines; each
    # row and its residual scaled alike by the line's tolerances (1 mm, 2 mrad)
    ua = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    up = np.array([[0.0, 0.2, 0.0], [0.0, 0.0, 0.3], [0.4, 0.0, 0.0]])
    lines = [line_feature("l", true, ua[i : i + 1], up[i : i + 1], 0.7, (1e-3, 2e-3)) for i in range(3)]
    assert _gauss_newton(lines, np.eye(4)) == pytest.approx(true, abs=1e-10)


def test_gauss_newton_weighs_each_feature_by_its_tolerance_squared_and_keeps_a_free_turn():
    a = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    # one set of points says "no shift", the other "1 m along x" with a 1000× tighter tolerance
    feats = [point_feature("a", a, np.eye(4), (1.0, 1.0)), point_feature("b", a, pose(xyz=(1.0, 0.0, 0.0)), (1e-3, 1.0))]
    t = _gauss_newton(feats, np.eye(4))
    assert t[:3, 3] == pytest.approx([1e6 / (1e6 + 1), 0.0, 0.0], rel=1e-9, abs=1e-12)
    assert t[:3, :3] == pytest.approx(np.eye(3), abs=1e-12)
    # points all on the x axis leave a turn about x free: the turn it starts with stays
    on_x = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    start = pose(turn([1, 0, 0], 0.2))
    t = _gauss_newton([point_feature("x", on_x, pose(xyz=(0.0, 0.5, 0.0)))], start)
    assert t == pytest.approx(pose(turn([1, 0, 0], 0.2), (0.0, 0.5, 0.0)), abs=1e-12)


@pytest.fixture(scope="module")
def arm3():
    return aligner(*ARM3, samples=Q3)


def test_the_aligner_fits_over_the_zero_and_the_samples_of_the_matched_joints(arm3):
    assert arm3.pairs == [("joint1", "joint1"), ("joint2", "joint2"), ("joint3", "joint3")]
    assert arm3.types == {"joint1": "revolute", "joint2": "revolute", "joint3": "revolute"}
    assert arm3.children == {"joint1": ["joint2"], "joint2": ["joint3"], "joint3": []}
    assert [f[:2] for f in arm3.frame_pairs] == [(f, f) for f in ("base", "link1", "link2", "link3", "end_effector")]
    assert [(bu.name, bm.name) for bu, bm in arm3.bodies] == [(f, f) for f in ("base", "link1", "link2", "link3")]
    assert arm3.q == pytest.approx(np.vstack([np.zeros(3), Q3]))
    assert arm3.pu.shape == (4, len(arm3.p.uframes), 4, 4)
    # the end effector stands 1.12 m high at the zero; the samples fold the arm (no point higher)
    assert arm3.scale == pytest.approx(1.12, rel=1e-12)
    lone = aligner(*ARM3)
    assert lone.q == pytest.approx(np.zeros((1, 3))) and lone.scale == pytest.approx(1.12, rel=1e-12)


def test_a_robot_smaller_than_a_metre_is_scaled_as_one_metre():
    assert aligner(*P.generated_pair("lift")).scale == 1.0


def test_a_centre_of_mass_is_evidence_only_where_both_files_give_the_body_one_mass():
    def with_mass(factor):
        mjcf = P.sub_once(r'(<body name="link2".*?<inertial [^>]*?mass=")([^"]*)(")', lambda m: m[1] + repr(float(m[2]) * factor) + m[3], ARM3[1])  # fmt: skip
        return [bu.name for bu, _ in aligner(ARM3[0], mjcf).bodies]

    assert with_mass(1 + 0.9e-3) == ["base", "link1", "link2", "link3"]
    assert with_mass(1 + 1.1e-3) == ["base", "link1", "link3"]
    assert with_mass(1 - 1.1e-3) == ["base", "link1", "link3"]


def test_each_frames_tolerance_is_exact_agreement_plus_both_files_rounding(arm3):
    floors = Floors(frames={"link2": (1e-4, 1e-5), "link3": (3e-5, 5e-5), "end_effector": (1e-2, 2e-2)})
    a = Aligner(arm3.p, arm3.matching, floors, Q3)
    s = TOL * 1.12
    assert a.tol("link2") == pytest.approx((s + 2e-4, TOL + 2e-5), rel=1e-12)
    assert a.tol("base") == pytest.approx((s, TOL), rel=1e-12)
    # a joint's offset is read on the frames it carries and the next joint's frame: the loosest
    assert a.carried_tol("joint2") == pytest.approx((s + 2e-4, TOL + 1e-4), rel=1e-12)
    assert a.carried_tol("joint3") == pytest.approx((s + 2e-2, TOL + 4e-2), rel=1e-12)
    assert a.carried_tol("joint1") == pytest.approx((s + 2e-4, TOL + 2e-5), rel=1e-12)


def test_the_mjcf_is_posed_at_each_sampled_configuration_through_the_joint_map(arm3):
    signs, offsets = {"joint1": 1, "joint2": -1, "joint3": 1}, {"joint1": 0.0, "joint2": 0.0, "joint3": 0.25}
    q = np.vstack([np.zeros(3), Q3]) * [1, -1, 1] + [0.0, 0.0, 0.25]
    assert arm3.mjcf_poses(signs, offsets) == pytest.approx(arm3.p.mjcf(q), abs=1e-12)
    assert arm3.mjcf_poses(signs, offsets, rows=slice(1, 2)) == pytest.approx(arm3.p.mjcf(q[1:2]), abs=1e-12)


def test_an_axis_line_in_the_world_of_each_file():
    # the MJCF's world turned a quarter turn about z and raised 1 m: its lines are there
    urdf, mjcf = ARM3
    a = aligner(urdf, move_world(mjcf, [0.0, 0.0, 1.0], [0.0, 0.0, math.pi / 2]), samples=np.array([[math.pi / 2, 0.0, 0.0]]))
    pm = a.mjcf_poses({n: 1 for n in a.types}, {n: 0.0 for n in a.types})
    ua, up = a.line("u", "joint2", a.pu)
    ma, mp = a.line("m", "joint2", pm)
    # joint 2 (y through (0, 0, 0.82) at the zero) turns with joint 1 to -x at q1 = π/2
    assert ua == pytest.approx(np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]), abs=1e-12)
    assert up == pytest.approx(np.array([[0.0, 0.0, 0.82], [0.0, 0.0, 0.82]]), abs=1e-12)
    assert ma == pytest.approx(np.array([[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]]), abs=1e-12)
    assert mp == pytest.approx(np.array([[0.0, 0.0, 1.82], [0.0, 0.0, 1.82]]), abs=1e-12)


def remapped(mjcf: str, changes: dict) -> str:
    for joint, (sign, offset) in changes.items():
        mjcf = remap_joint(mjcf, joint, sign, offset)
    return mjcf


def test_each_joints_sign_and_zero_offset_is_read_on_what_it_moves():
    # j1, j2: the next axis's foot; j3 (prismatic): the next axis shifted; j4: the tool it carries
    wanted = {"j1": (1, 0.3), "j2": (-1, -0.2), "j3": (1, 0.05), "j4": (-1, 0.4)}
    a = aligner(BENT[0], remapped(BENT[1], wanted))
    signs, offsets = a.solve_joints(np.eye(4))
    assert signs == {j: s for j, (s, _) in wanted.items()}
    assert offsets == pytest.approx({j: o for j, (_, o) in wanted.items()}, abs=1e-12)


def test_a_zero_offset_within_the_carried_frames_rounding_is_none():
    # j2's offset is measured on l2 and the next frame l3; their rounding allows 2e-3 rad
    def offset(joint, value, floors):
        a = aligner(BENT[0], remap_joint(BENT[1], joint, 1, value), floors=Floors(frames=floors))
        return a.solve_joints(np.eye(4))[1][joint]

    turned = {"l2": (0.0, 1e-3), "l3": (0.0, 1e-3)}
    assert offset("j2", 1.5e-3, turned) == 0.0
    assert offset("j2", 3e-3, turned) == pytest.approx(3e-3, abs=1e-12)
    # j3 slides: its shift is held to the carried frames' position tolerance (2 mm), not 2e-3 rad
    moved = {"l3": (1e-3, 0.0), "l4": (1e-3, 0.0)}
    assert offset("j3", 1.5e-3, moved) == 0.0
    assert offset("j3", 3e-3, moved) == pytest.approx(3e-3, abs=1e-12)
    assert offset("j3", 1.5e-3, turned) == pytest.approx(1.5e-3, abs=1e-12)


def test_an_offset_of_a_joint_whose_next_axis_crosses_its_own_is_the_smaller_turn_of_that_axis():
    # arm3's joint 2 axis (y) crosses joint 1's (z), and all joint 1 carries lies on z: the next
    # axis's direction alone says the offset, up to a half turn (the next joint's own convention)
    for offset, seen in ((0.3, 0.3), (2.0, 2.0 - math.pi), (-2.5, math.pi - 2.5)):
        signs, offsets = aligner(ARM3[0], remap_joint(ARM3[1], "joint1", 1, offset)).solve_joints(np.eye(4))
        assert offsets["joint1"] == pytest.approx(seen, abs=1e-12) and signs["joint1"] == 1
    # joint 3 carries the tool 5 cm along its link: read there; joint 2 on joint 3's parallel axis
    signs, offsets = aligner(ARM3[0], remapped(ARM3[1], {"joint2": (-1, 0.7), "joint3": (1, -1.1)})).solve_joints(np.eye(4))
    assert signs == {"joint1": 1, "joint2": -1, "joint3": 1}
    assert offsets == pytest.approx({"joint1": 0.0, "joint2": 0.7, "joint3": -1.1}, abs=1e-12)


def test_a_slide_with_nothing_after_it_is_read_on_the_frames_it_carries():
    urdf, mjcf = P.generated_pair("lift")
    assert aligner(urdf, remap_joint(mjcf, "lift", 1, 0.12)).solve_joints(np.eye(4)) == ({"lift": 1}, {"lift": pytest.approx(0.12, abs=1e-12)})  # fmt: skip
    assert aligner(urdf, remap_joint(mjcf, "lift", -1, 0.0)).solve_joints(np.eye(4)) == ({"lift": -1}, {"lift": 0.0})


def test_a_turn_about_the_axis_that_carries_the_points_onto_their_twins():
    axis, point = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    # (2, 0, 5) about the line x = 1 by π/2 lands on (1, 1, 5); a height difference is along the axis
    pairs = [(np.array([2.0, 0.0, 5.0]), np.array([1.0, 1.0, 7.0]))]
    assert Aligner._turns_onto(pairs, math.pi / 2, axis, point, 1e-9)
    assert not Aligner._turns_onto(pairs, 0.0, axis, point, 1e-9)
    assert Aligner._turns_onto(pairs, math.pi / 2 + 0.9e-3, axis, point, 1e-3)
    assert not Aligner._turns_onto(pairs, math.pi / 2 + 1.1e-3, axis, point, 1e-3)
    assert not Aligner._turns_onto(
        pairs + [(np.array([3.0, 0.0, 0.0]), np.array([1.0, 2.1, 0.0]))], math.pi / 2, axis, point, 1e-3
    )


ONES = {"joint1": 1, "joint2": 1, "joint3": 1}
ZEROS = {"joint1": 0.0, "joint2": 0.0, "joint3": 0.0}


def arm3_edited(pattern: str, repl: str) -> Aligner:
    return aligner(ARM3[0], P.sub_once(pattern, repl, ARM3[1]), samples=Q3)


def test_nothing_is_unexplained_between_identical_files(arm3):
    bad, fits, errors = arm3.evaluate(np.eye(4), ONES, ZEROS)
    assert bad == 0 and list(errors) == list(ONES)
    assert np.array(list(errors.values())) == pytest.approx(np.zeros((3, 2)), abs=1e-12)
    assert [(f.urdf, f.mjcf, f.in_fit) for f in fits] == [
        (n, n, False) for n in ("base", "link1", "link2", "link3", "end_effector")
    ]
    assert [f.why for f in fits] == [w for _, _, w in arm3.matching.frames]
    assert max(max(f.position, f.rotation, f.residual_position, f.residual_rotation) for f in fits) < 1e-12


def test_a_frame_placed_differently_is_one_unexplained_feature_with_its_constant():
    # the MJCF's end effector 1 cm further along link3: constant in link3's frame
    a = arm3_edited(r'(<site name="end_effector" pos=")0.0 0.0 0.05', r"\g<1>0.0 0.0 0.06")
    bad, fits, _ = a.evaluate(np.eye(4), ONES, ZEROS)
    ee = fits[-1]
    assert bad == 1 and ee.urdf == "end_effector"
    assert (ee.position, ee.rotation) == pytest.approx((0.01, 0.0), abs=1e-12)
    assert ee.constant == pytest.approx(pose(xyz=(0.0, 0.0, -0.01)), abs=1e-12)
    assert (ee.residual_position, ee.residual_rotation) == pytest.approx((0.0, 0.0), abs=1e-12)
    assert [f.position for f in fits[:-1]] == pytest.approx([0.0] * 4, abs=1e-12)
    # under a world transform, the MJCF's frame is brought back into the URDF's world first
    t = pose(turn([0, 0, 1], 0.5), (0.0, 0.0, 0.2))
    bad, fits, _ = aligner(ARM3[0], move_world(ARM3[1], [0.0, 0.0, 0.2], [0.0, 0.0, 0.5]), samples=Q3).evaluate(t, ONES, ZEROS)
    assert bad == 0 and max(f.position + f.rotation for f in fits) < 1e-12


def test_a_frame_turned_about_its_origin_is_a_rotation_only():
    half = 0.05 / 2  # the end effector turned 0.05 rad about x
    a = arm3_edited(r'(<site name="end_effector" pos="0.0 0.0 0.05")', rf'\1 quat="{math.cos(half)!r} {math.sin(half)!r} 0 0"')
    bad, fits, _ = a.evaluate(np.eye(4), ONES, ZEROS)
    ee = fits[-1]
    assert bad == 0  # only a position counts: a frame's orientation is the file's choice
    assert (ee.position, ee.rotation) == pytest.approx((0.0, 0.05), abs=1e-12)
    assert ee.constant[:3, :3] == pytest.approx(turn([1, 0, 0], -0.05), abs=1e-12)
    assert (ee.residual_position, ee.residual_rotation) == pytest.approx((0.0, 0.0), abs=1e-12)


def test_a_centre_of_mass_placed_differently_counts_above_its_rounding():
    a = arm3_edited(r'(<body name="link2".*?<inertial pos=")0.0 0.0 0.135', r"\g<1>0.01 0.0 0.135")
    assert a.evaluate(np.eye(4), ONES, ZEROS)[0] == 1
    for com, bad in ((0.0051, 0), (0.0049, 1)):
        b = Aligner(a.p, a.matching, Floors(com=com), Q3)
        assert b.evaluate(np.eye(4), ONES, ZEROS)[0] == bad


def test_an_axis_tilted_or_moved_is_its_angle_and_its_distance():
    # joint 3's axis tilted by 0.02 rad about x within link3: the tool and link3's centre of mass
    # (5 cm out along z) leave it at every non-zero q3 too; link3's origin is on the axis
    tilted = [0.0, math.cos(0.02), math.sin(0.02)]
    a = arm3_edited(r'(<joint name="joint3" [^>]*?axis=")0.0 1.0 0.0', r"\g<1>" + " ".join(map(repr, tilted)))
    bad, fits, errors = a.evaluate(np.eye(4), ONES, ZEROS)
    assert errors["joint3"] == pytest.approx((0.02, 0.0), abs=1e-12)
    assert errors["joint2"] == pytest.approx((0.0, 0.0), abs=1e-12)
    tool = np.array([0.0, 0.0, 0.05])
    apart = max(np.linalg.norm((turn(tilted, q) - turn([0, 1, 0], q)) @ tool) for q in Q3[:, 2])
    assert bad == 3 and fits[3].position == pytest.approx(0.0, abs=1e-12)
    assert fits[4].position == pytest.approx(apart, rel=1e-9)
    # the tool's constant is read at the zero, where the tilt moves nothing: none
    assert fits[4].constant == pytest.approx(np.eye(4), abs=1e-12) and fits[4].residual_position == pytest.approx(apart, rel=1e-9)
    # joint 3's axis 1 cm along x at the zero (its body placed there), the body's axis line too
    b = arm3_edited(r'(<joint name="joint3" )', r'\1pos="0.01 0 0" ')
    bad, fits, errors = b.evaluate(np.eye(4), ONES, ZEROS)
    assert errors["joint3"] == pytest.approx((0.0, 0.01), abs=1e-12)
    # link3's origin, the tool and link3's centre of mass turn about a line 1 cm off: 2·1 cm·sin(q3/2)
    assert bad == 4 and [f.position for f in fits[3:]] == pytest.approx([0.02 * math.sin(0.35)] * 2, rel=1e-9)


def test_root_frames_that_disagree_in_orientation_under_a_world_transform(arm3):
    assert arm3.root_orientation_mismatch(np.eye(4)) == 0
    assert arm3.root_orientation_mismatch(pose(turn([0, 0, 1], 0.5))) == 1
    # a turn within the base frame's rounding is none
    floored = Aligner(arm3.p, arm3.matching, Floors(frames={"base": (0.0, 1e-3)}), Q3)
    assert floored.root_orientation_mismatch(pose(turn([0, 0, 1], 1.5e-3))) == 0
    assert floored.root_orientation_mismatch(pose(turn([0, 0, 1], 2.5e-3))) == 1


MOVED = pose(turn([0, 0, 1], 0.5), (0.1, 0.2, 0.3))  # the MJCF's world: turned 0.5 rad about z, shifted


def moved(mjcf: str) -> str:
    return move_world(mjcf, [0.1, 0.2, 0.3], [0.0, 0.0, 0.5])


def test_the_candidate_world_transforms():
    a = aligner(ARM3[0], moved(ARM3[1]), samples=Q3)
    got = dict(a.candidates())
    flip = np.diag([-1.0, 1.0, -1.0])  # the half turn about y taking z onto -z
    wanted = {
        "identity": np.eye(4),
        "least squares over frame origins": MOVED,
        "root frame base": MOVED,
        "axis of joint1": pose(xyz=(0.1, 0.2, 0.3)),  # joint 1's line laid onto the other: z onto z
        "axis of joint1 reversed": pose(flip, (0.1, 0.2, 0.82 + 0.52)),
    }
    assert list(got) == list(wanted)
    for label, t in wanted.items():
        assert got[label] == pytest.approx(t, abs=1e-12), label


def one_joint(tools=()):
    limits = {"lower": -1.0, "upper": 1.0, "unit": "rad"}
    j = {"name": "j1", "type": "revolute", "xyz": [0.1, 0.0, 0.1], "rpy": [0.0, 0.0, 0.0], "axis": [0, 0, 1], "limits": limits,
         "link": {"name": "l1", "mass": 1.0}}  # fmt: skip
    spec = spec_from_dict({"name": "one", "joints": [j], "tools": list(tools)})
    return generate_urdf(spec), generate_mjcf(spec)


def test_a_least_squares_world_needs_three_frame_origins():
    labels = [label for label, _ in aligner(*one_joint()).candidates()]  # base and l1 at the zero: two
    assert labels == ["identity", "root frame base", "axis of j1", "axis of j1 reversed"]
    tool = {"name": "tool", "parent": "l1", "xyz": [0.1, 0.0, 0.0], "rpy": [0.0, 0.0, 0.0]}
    labels = [label for label, _ in aligner(*one_joint([tool])).candidates()]
    assert labels[:2] == ["identity", "least squares over frame origins"]


def test_a_features_residual_is_its_largest_error_over_its_tolerance():
    a = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    feat = ("p", "point", a, a + [[0.0, 0.0, 0.0], [0.0, 3e-3, 4e-3]], (1e-3, 1.0))
    assert Aligner._residual(feat, np.eye(4)) == pytest.approx(5.0, rel=1e-12)
    assert Aligner._residual(feat, pose(xyz=(0.0, 3e-3, 4e-3))) == pytest.approx(5.0, rel=1e-12)
    # a line: its point's distance from the other line (sliding along it is no error), its angle
    ua, up = np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 0.0, 0.0]])
    line = line_feature("l", pose(turn([0, 0, 1], 0.01), (0.0, 2e-3, 0.0)), ua, up, slide=0.5, tol=(1e-3, 1e-3))
    assert Aligner._residual(line, np.eye(4)) == pytest.approx(10.0, rel=1e-9)  # 0.01 rad / 1e-3
    line = line_feature("l", pose(turn([0, 0, 1], 1e-4), (0.0, 2e-3, 0.0)), ua, up, slide=0.5, tol=(1e-3, 1e-3))
    assert Aligner._residual(line, np.eye(4)) == pytest.approx(2.0, rel=1e-6)  # 2 mm / 1 mm
    assert Aligner._residual(line, pose(turn([0, 0, 1], 1e-4), (0.0, 2e-3, 0.0))) == pytest.approx(0.0, abs=1e-9)


def test_the_fit_leaves_out_the_worst_feature_until_the_rest_agree(arm3):
    t = pose(turn([1, 1, 0], 0.3), (0.1, 0.0, -0.2))
    rng = np.random.default_rng(1)
    feats = [point_feature(f"f{i}", rng.normal(size=(2, 3)), t, (1e-6, 1e-6)) for i in range(4)]
    feats.append(point_feature("off", rng.normal(size=(2, 3)), pose(t[:3, :3], (0.1, 0.0, -0.19)), (1e-6, 1e-6)))
    feats.append(line_feature("axis", t, np.array([[0.0, 0.0, 1.0]]), np.array([[0.5, 0.0, 0.0]]), 0.3, (1e-6, 1e-6)))
    fitted, keep = arm3._eliminate(feats, list(range(6)), np.eye(4))
    assert keep == [0, 1, 2, 3, 5] and fitted == pytest.approx(t, abs=1e-10)
    assert Aligner._fit(feats[:4], np.eye(4)) == pytest.approx(t, abs=1e-10)
    assert Aligner._fit([], t) is t
    # two features are kept, whatever they say
    fitted, keep = arm3._eliminate(feats[3:5], [0, 1], np.eye(4))
    assert keep == [0, 1]


def test_a_fit_keeps_a_turn_its_features_leave_free():
    on_x = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    start = pose(turn([1, 0, 0], 0.2))
    fitted = Aligner._fit([point_feature("x", on_x, pose(xyz=(0.0, 0.5, 0.0)))], start)
    assert fitted == pytest.approx(pose(turn([1, 0, 0], 0.2), (0.0, 0.5, 0.0)), abs=1e-9)


EE_MOVED = (r'(<site name="end_effector" pos=")0.0 0.0 0.05', r"\g<1>0.0 0.0 0.06")


def test_the_refit_finds_the_world_over_the_frames_that_agree():
    a = aligner(ARM3[0], moved(P.sub_once(*EE_MOVED, ARM3[1])), samples=Q3)
    t, used = a.refit(np.eye(4), ONES, ZEROS)
    assert t == pytest.approx(MOVED, abs=1e-9)
    assert used == ["base", "link1", "link2", "link3"]


def test_the_simplest_explanation_drops_a_world_transform_and_offsets_nothing_needs(arm3):
    tiny = pose(xyz=(0.0, 0.0, 0.5 * TOL))
    assert arm3.simplest(tiny, ONES, ZEROS)[0] is not tiny and np.array_equal(arm3.simplest(tiny, ONES, ZEROS)[0], np.eye(4))
    assert arm3.simplest(tiny, ONES, ZEROS, keep_t=True)[0] is tiny
    shifted = pose(xyz=(0.0, 0.0, 0.1))
    t, offsets, bad, fits, errors = arm3.simplest(shifted, ONES, {**ZEROS, "joint1": 0.3, "joint3": 2 * math.pi})
    assert np.array_equal(t, np.eye(4)) and offsets == ZEROS and bad == 0
    assert [f.position for f in fits] == pytest.approx([0.0] * 5, abs=1e-12)
    t, offsets, bad, _, _ = arm3.simplest(shifted, ONES, ZEROS, keep_t=True)
    assert t is shifted and bad == 5 + 2 + 4  # every frame, every centre of mass, the lines but joint 1's (z)
    # the transform and the offset the MJCF needs stay
    a = aligner(ARM3[0], moved(remap_joint(ARM3[1], "joint2", 1, 0.7)), samples=Q3)
    t, offsets, bad, _, _ = a.simplest(MOVED, ONES, {**ZEROS, "joint2": 0.7})
    assert t is MOVED and offsets == {**ZEROS, "joint2": 0.7} and bad == 0


def test_a_turn_no_feature_sees_is_no_world_transform():
    # the lift's frames, centres of mass and axis all lie on z: a turn about z explains nothing
    urdf, mjcf = P.generated_pair("lift")
    a = aligner(urdf, mjcf, samples=np.array([[0.2]]))
    t, _, bad, _, _ = a.simplest(pose(turn([0, 0, 1], 0.5)), {"lift": 1}, {"lift": 0.0})
    assert np.array_equal(t, np.eye(4)) and bad == 0


def test_the_solved_alignment_is_the_world_transform_with_its_residual():
    al = aligner(ARM3[0], moved(P.sub_once(*EE_MOVED, ARM3[1])), samples=Q3).solve()
    assert al.T == pytest.approx(MOVED, abs=1e-9)
    assert joint_map(al) == {j: (1, 0.0) for j in ONES}
    assert [(j.urdf, j.mjcf, j.type) for j in al.joints] == [(j, j, "revolute") for j in ONES]
    assert al.unexplained == 1  # the end effector, left out of the fit and reported on its own
    assert [(f.urdf, f.in_fit) for f in al.frames] == [("base", True), ("link1", True), ("link2", True), ("link3", True), ("end_effector", False)]  # fmt: skip
    assert al.frames[-1].position == pytest.approx(0.01, abs=1e-9)
    assert al.residual[0] < 1e-9 and al.residual[1] < 1e-9  # the end effector's centimetre is not a residual
    assert list(al.axis_errors) == list(ONES) and al.couplings == {} and al.independent == list(ONES)


def test_a_tilted_axis_is_the_residual_of_the_fit():
    tilted = [0.0, math.cos(0.02), math.sin(0.02)]
    al = arm3_edited(r'(<joint name="joint3" [^>]*?axis=")0.0 1.0 0.0', r"\g<1>" + " ".join(map(repr, tilted))).solve()
    assert np.array_equal(al.T, np.eye(4)) and joint_map(al) == {j: (1, 0.0) for j in ONES}
    assert al.residual[1] == pytest.approx(0.02, abs=1e-12) and al.residual[0] == pytest.approx(0.0, abs=1e-12)
    assert al.axis_errors["joint3"] == pytest.approx((0.02, 0.0), abs=1e-12)


def test_a_first_joints_offset_is_that_offset_rather_than_a_turned_world():
    # joint 1 turns the arm about z, as a world turned about z would; the base frame, which
    # joint 1 does not move, agrees only without a world turn
    al = aligner(ARM3[0], remap_joint(ARM3[1], "joint1", 1, 0.3), samples=Q3).solve()
    assert np.array_equal(al.T, np.eye(4)) and joint_map(al) == {**{j: (1, 0.0) for j in ONES}, "joint1": (1, pytest.approx(0.3, abs=1e-12))}  # fmt: skip
    # the MJCF's base body turned with everything on it: the world turned, not the joint
    quat = f'quat="{math.cos(0.15)!r} 0 0 {math.sin(0.15)!r}"'
    al = aligner(ARM3[0], P.sub_once(r'(<body name="base" pos="0.0 0.0 0.42")', rf"\1 {quat}", ARM3[1]), samples=Q3).solve()
    assert al.T == pytest.approx(pose(turn([0, 0, 1], 0.3)), abs=1e-9) and joint_map(al) == {j: (1, 0.0) for j in ONES}
    assert al.unexplained == 0


def test_a_candidate_kept_as_given_is_only_its_joints_solved(arm3):
    al = arm3.solve(candidates=[("given", pose(xyz=(0.0, 0.0, 0.1)))], refit=False)
    assert al.candidate == "given" and al.T == pytest.approx(pose(xyz=(0.0, 0.0, 0.1)))
    assert al.unexplained == 11 and al.residual[0] == pytest.approx(0.1, abs=1e-12)


def test_floating_files_keep_their_base_frames_unless_a_world_transform_explains_everything():
    same = solved(*ARM3, samples=Q3, base_fixes_frame=True)
    assert same.candidate == "base frames" and np.array_equal(same.T, np.eye(4)) and same.unexplained == 0
    world = solved(ARM3[0], moved(ARM3[1]), samples=Q3, base_fixes_frame=True)
    assert world.candidate != "base frames" and world.T == pytest.approx(MOVED, abs=1e-9) and world.unexplained == 0
    both = solved(ARM3[0], moved(P.sub_once(*EE_MOVED, ARM3[1])), samples=Q3, base_fixes_frame=True)
    assert both.candidate == "base frames" and np.array_equal(both.T, np.eye(4)) and both.unexplained > 1


def tool_at(xyz) -> str:
    return P.sub_once(r'(<site name="tool" pos=")0.0 0.0 0.0|(<site name="tool" pos=")0.05 0.02 0.0', lambda m: (m[1] or m[2]) + " ".join(map(repr, xyz)), BENT[1])  # fmt: skip


def test_a_zero_offset_is_read_on_the_points_that_keep_their_distance_from_the_axis():
    # j4 carries its centre of mass and the tool; the MJCF's tool sits 1.5 times further out: only
    # the centre of mass says j4's offset, and it is whole
    mjcf = remap_joint(tool_at([0.075, 0.03, 0.0]), "j4", 1, 0.4)
    assert aligner(BENT[0], mjcf).solve_joints(np.eye(4))[1]["j4"] == pytest.approx(0.4, abs=1e-12)


def test_no_zero_offset_where_what_a_joint_carries_disagrees_on_one():
    # the MJCF's tool turned 0.2 rad about j4's axis, its centre of mass not: no one turn explains both
    c, s = math.cos(0.2), math.sin(0.2)
    mjcf = tool_at([0.05 * c - 0.02 * s, 0.05 * s + 0.02 * c, 0.0])
    assert aligner(BENT[0], mjcf).solve_joints(np.eye(4))[1]["j4"] == 0.0


def test_no_shift_where_what_a_slide_carries_disagrees_on_one():
    # the MJCF's lift slides 0.1 m further at the same q, its platform site 0.1 m lower on the
    # carriage: the carriage's frame and centre of mass say 0.1 m, the platform 0
    urdf, mjcf = P.generated_pair("lift")
    mjcf = P.sub_once(r'(<site name="platform" pos=")0.0 0.0 0.05', r"\g<1>0.0 0.0 -0.05", remap_joint(mjcf, "lift", 1, 0.1))
    assert aligner(urdf, mjcf).solve_joints(np.eye(4))[1] == {"lift": 0.0}


def test_a_next_axis_parallel_to_a_slide_says_nothing_of_its_shift():
    # j2 slides along x and carries j3, which turns about x: the MJCF's j2 slides 5 cm further at
    # the same q and its j3 axis sits 1 cm aside (a difference of its own); j2's frame and
    # centre of mass still say the shift
    def joint(name, kind, axis, xyz):
        limits = {"lower": -0.5, "upper": 0.5, "unit": "rad" if kind == "revolute" else "m"}
        return {"name": name, "type": kind, "xyz": xyz, "rpy": [0.0, 0.0, 0.0], "axis": axis, "limits": limits,
                "link": {"name": "l" + name[1:], "mass": 1.0}}  # fmt: skip

    spec = spec_from_dict(
        {
            "name": "slider",
            "joints": [
                joint("j1", "revolute", [0, 0, 1], [0.0, 0.0, 0.1]),
                joint("j2", "prismatic", [1, 0, 0], [0.1, 0.0, 0.1]),
                joint("j3", "revolute", [1, 0, 0], [0.1, 0.05, 0.0]),
            ],
            "tools": [{"name": "tool", "parent": "l3", "xyz": [0.05, 0.02, 0.03], "rpy": [0.0, 0.0, 0.0]}],
        }
    )
    mjcf = P.sub_once(r'(<joint name="j3" )', r'\1pos="0 0.01 0" ', remap_joint(generate_mjcf(spec), "j2", 1, 0.05))
    offsets = aligner(generate_urdf(spec), mjcf).solve_joints(np.eye(4))[1]
    assert offsets == {"j1": 0.0, "j2": pytest.approx(0.05, abs=1e-12), "j3": 0.0}


def test_gauss_newton_weighs_an_axis_direction_by_its_rotation_tolerance():
    # points on x fix all but a turn about x; two axes along y disagree on it (0.1 rad, or none),
    # the second with a 1000× tighter tolerance: the turn θ minimises w_a·|R(θ)y − R(0.1)y|² +
    # w_b·|R(θ)y − y|² (weights 1 and 1e6), where w_a·sin(θ − 0.1) + w_b·sin θ = 0
    on_x = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    y, at = np.array([[0.0, 1.0, 0.0]]), np.array([[0.0, 0.0, 0.0]])
    feats = [
        point_feature("x", on_x, np.eye(4), (1.0, 1.0)),
        line_feature("a", pose(turn([1, 0, 0], 0.1)), y, at, tol=(1.0, 1.0)),
        line_feature("b", np.eye(4), y, at, tol=(1.0, 1e-3)),
    ]
    t = _gauss_newton(feats, np.eye(4), iterations=20)
    angle = math.atan2(t[2, 1], t[1, 1])
    assert angle == pytest.approx(math.atan2(math.sin(0.1), 1e6 + math.cos(0.1)), rel=1e-9)
    assert t[:3, 3] == pytest.approx([0.0, 0.0, 0.0], abs=1e-12)


def test_identical_files_are_aligned_by_the_identity_candidate_with_nothing_to_explain(arm3):
    al = arm3.solve()
    assert al.candidate == "identity" and np.array_equal(al.T, np.eye(4)) and al.unexplained == 0
    assert joint_map(al) == {j: (1, 0.0) for j in ONES} and all(f.in_fit for f in al.frames)
    assert al.residual == pytest.approx((0.0, 0.0), abs=1e-12)


def test_identical_files_need_no_sign_and_no_zero_offset():
    # bent: every joint's offset is seen (points off its axis); one joint carrying nothing off its
    # axis: nothing says an offset
    for urdf, mjcf, joints in ((*BENT, ("j1", "j2", "j3", "j4")), (*one_joint(), ("j1",))):
        assert aligner(urdf, mjcf).solve_joints(np.eye(4)) == ({j: 1 for j in joints}, {j: 0.0 for j in joints})


def test_a_pair_sharing_no_joint_and_no_frame_is_left_as_it_is_with_no_residual():
    u, m = describe_urdf(ARM3[0]), describe_mjcf(ARM3[1])
    nothing = Matching([], [], [], [])
    al = align(PairPoses(u, m, nothing, *ARM3), nothing, Floors(), np.zeros((0, 0)))
    assert (al.candidate, al.unexplained, al.residual, al.joints, al.frames) == ("identity", 0, (0.0, 0.0), [], [])
    assert np.array_equal(al.T, np.eye(4))


def test_a_fit_far_from_its_start_is_seeded_by_the_weighted_kabsch_estimate():
    # 2.5 rad away: Gauss-Newton alone from the start would not get there in its few iterations
    t = pose(turn([1, 1, 1], 2.5), (0.3, -0.2, 0.1))
    a = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    ua, up = np.array([[0.0, 1.0, 0.0]]), np.array([[0.5, 0.0, 0.0]])
    feats = [point_feature("p", a, t, (1e-3, 2e-3)), line_feature("l", t, ua, up, 0.4, (3e-3, 4e-3))]
    assert Aligner._fit(feats, np.eye(4)) == pytest.approx(t, abs=1e-9)
    assert not np.allclose(_gauss_newton(feats, np.eye(4)), t, atol=1e-6)


def test_the_refit_keeps_a_frame_within_its_rounding():
    # the end effector 1 mm off, both files' rounding allowing 2 mm there: it agrees and is fitted
    mjcf = moved(P.sub_once(EE_MOVED[0], r"\g<1>0.0 0.0 0.051", ARM3[1]))
    a = aligner(ARM3[0], mjcf, samples=Q3, floors=Floors(frames={"end_effector": (1e-3, 0.0)}))
    t, used = a.refit(np.eye(4), ONES, ZEROS)
    assert used == ["base", "link1", "link2", "link3", "end_effector"]


def test_a_lines_residual_is_its_worst_configuration():
    # two configurations: the point 3 mm, then 4 mm off the other file's line (along x): 4 mm, not 5
    ua, up = np.array([[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]), np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]])
    line = ("l", "line", (ua, up), (ua, up + [[0.0, 3e-3, 0.0], [0.0, 0.0, 4e-3]]), (1e-3, 1.0))
    assert Aligner._residual(line, np.eye(4)) == pytest.approx(4.0, rel=1e-9)


def test_a_feature_one_and_a_half_tolerances_off_is_left_out(arm3):
    a = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    feats = [point_feature(f"f{i}", a + i, np.eye(4), (1e-6, 1e-6)) for i in range(3)]
    feats.append(("loose", "point", a[:1], a[:1] + [[1.5e-3, 0.0, 0.0]], (1e-3, 1e-3)))
    _, keep = arm3._eliminate(feats, [0, 1, 2, 3], np.eye(4))
    assert keep == [0, 1, 2]


def test_the_other_files_axis_line_is_read_in_its_own_frame_names():
    # the MJCF calls joint 2's body "forearm": its line is read there
    renamed = ARM3[1].replace('<body name="link2"', '<body name="forearm"')
    a = aligner(ARM3[0], renamed, samples=Q3)
    pm = a.mjcf_poses(ONES, ZEROS)
    assert a.line("m", "joint2", pm)[1] == pytest.approx(a.line("u", "joint2", a.pu)[1], abs=1e-12)
    assert a.line("m", "joint2", pm)[0] == pytest.approx(a.line("u", "joint2", a.pu)[0], abs=1e-12)


def test_one_world_turn_that_explains_a_first_joints_offset_too_is_preferred_to_two_explanations():
    # the MJCF's world turned 0.5 rad about z and joint 1's zero 0.05 rad back: a world turned by
    # 0.55 rad alone leaves nothing unexplained (the base frame's own orientation is a choice),
    # one explanation rather than a turn and an offset
    mjcf = remap_joint(move_world(ARM3[1], [0.0, 0.0, 0.0], [0.0, 0.0, 0.5]), "joint1", 1, -0.05)
    al = aligner(ARM3[0], mjcf, samples=Q3).solve()
    assert al.T == pytest.approx(pose(turn([0, 0, 1], 0.55)), abs=1e-9)
    assert joint_map(al) == {j: (1, 0.0) for j in ONES} and al.unexplained == 0
