"""The geometric helpers the alignment is built on, each checked on inputs whose answer is worked out by
hand: line distances and feet of common perpendiculars, composite inertials (parallel axis theorem),
the weighted Kabsch fit, chain reach, the weighted consensus of angles and the smallest rotation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kinverify.filemode.align.geometry import (
    angle_between,
    apply,
    composite_inertials,
    consensus,
    foot_on_line,
    frame_pose,
    kabsch,
    line_distance,
    planar,
    pose_difference,
    project_on_line,
    reach,
    rotation_between,
    rpy_string,
    to_frame,
    wrap,
)
from kinverify.filemode.read.model import BodyInertial, JointDesc, ModelDesc
from kinverify.model.transforms import axis_angle_to_matrix, make_transform, quat_to_matrix, rpy_to_matrix

X, Y, Z = np.eye(3)


def rot(axis, angle) -> np.ndarray:
    return axis_angle_to_matrix(np.asarray(axis, dtype=float), np.array([angle]))[0]


def joint(name, parent, anchor=(0.0, 0.0, 0.0)) -> JointDesc:
    return JointDesc(name, "revolute", parent, name + "_link", "p", Z.copy(), np.asarray(anchor, float), -1.0, 1.0)


def desc(joints, bodies=(), frames=None, owner=None) -> ModelDesc:
    return ModelDesc("urdf", "test", list(joints), frames or {}, owner or {}, {}, list(bodies))


def test_apply_rotates_then_translates():
    t = make_transform(rot(Z, math.pi / 2), [1.0, 2.0, 3.0])
    assert apply(t, np.array([1.0, 0.0, 0.0])) == pytest.approx([1.0, 3.0, 3.0], abs=1e-12)


@pytest.mark.parametrize(
    ("b", "angle"), [((0, 1, 0), math.pi / 2), ((-1, 0, 0), math.pi), ((1, 1, 0), math.pi / 4), ((1, 0, 0), 0.0)]
)
def test_angle_between(b, angle):
    assert angle_between(X, np.array(b, float)) == pytest.approx(angle, abs=1e-12)


def test_line_distance_skew_lines():
    # a line along x through (1, 2, 3) and one along (cos 30°, sin 30°, 0) 2 m above it: common normal z
    p1 = np.array([1.0, 2.0, 3.0])
    a2 = np.array([math.cos(math.pi / 6), math.sin(math.pi / 6), 0.0])
    assert line_distance(p1, X, p1 + [5.0, -1.0, 2.0], a2) == pytest.approx(2.0, rel=1e-12)
    assert line_distance(p1, X, p1 + [0.0, 0.0, -3.0], Y) == pytest.approx(3.0, rel=1e-12)


def test_line_distance_parallel_lines():
    p1 = np.array([1.0, 2.0, 3.0])
    assert line_distance(p1, X, p1 + [7.0, 3.0, 4.0], X) == pytest.approx(5.0, rel=1e-12)
    assert line_distance(p1, X, p1 + [7.0, 3.0, 4.0], -X) == pytest.approx(5.0, rel=1e-12)


def test_pose_difference():
    a = make_transform(np.eye(3), [1.0, 0.0, 0.0])
    b = make_transform(rot(X, 0.3), [1.0, 3.0, 4.0])
    dist, angle = pose_difference(a, b)
    assert dist == pytest.approx(5.0, rel=1e-12)
    assert angle == pytest.approx(0.3, rel=1e-9)


def test_frame_pose_falls_back_to_identity():
    pose = make_transform(np.eye(3), [1.0, 2.0, 3.0])
    d = desc([], frames={"tool": pose})
    assert frame_pose(d, "tool") is pose
    assert np.array_equal(frame_pose(d, "missing"), np.eye(4))


def test_composite_inertials_groups_by_nearest_mapped_ancestor():
    # j1 -> j2 -> j3; j2 is not in the map and its bodies go with j1's key, the base bodies with None
    joints = [joint("j1", None), joint("j2", "j1"), joint("j3", "j2")]
    ia, ib = np.diag([1.0, 2.0, 3.0]), np.diag([0.5, 0.5, 0.5])
    bodies = [
        BodyInertial("j1", 2.0, np.array([0.0, 0.0, 0.0]), ia),
        BodyInertial("j2", 1.0, np.array([3.0, 0.0, 0.0]), ib),
        BodyInertial("j3", 4.0, np.array([0.0, 1.0, 2.0]), ia),
        BodyInertial(None, 5.0, np.array([0.0, 0.0, -1.0]), ib),
    ]
    out = composite_inertials(desc(joints, bodies), {"j1": "A", "j3": "C"})
    assert set(out) == {"A", "C", None}
    mass, com, inertia = out["A"]
    assert mass == pytest.approx(3.0)
    assert com == pytest.approx([1.0, 0.0, 0.0])
    # parallel axis: body at x=0 (m=2) and x=3 (m=1), both 1 m / 2 m off the CoM along x
    shift = 2.0 * 1.0**2 + 1.0 * 2.0**2
    assert inertia == pytest.approx(ia + ib + np.diag([0.0, shift, shift]), abs=1e-12)
    mass, com, inertia = out["C"]
    assert (mass, list(com)) == (4.0, [0.0, 1.0, 2.0])
    assert inertia == pytest.approx(ia, abs=1e-12)
    assert out[None][0] == 5.0


def test_composite_inertials_off_axis_parallel_axis_terms():
    # two unit masses at (1, 1, 0) and (-1, -1, 0): products of inertia appear with the outer product
    bodies = [
        BodyInertial("j1", 1.0, np.array([1.0, 1.0, 0.0]), np.zeros((3, 3))),
        BodyInertial("j1", 1.0, np.array([-1.0, -1.0, 0.0]), np.zeros((3, 3))),
    ]
    _, com, inertia = composite_inertials(desc([joint("j1", None)], bodies), {"j1": "A"})["A"]
    assert com == pytest.approx([0.0, 0.0, 0.0])
    expected = 2.0 * (2.0 * np.eye(3) - np.outer([1.0, 1.0, 0.0], [1.0, 1.0, 0.0]))
    assert inertia == pytest.approx(expected, abs=1e-12)


def test_composite_inertials_unmapped_chain_goes_to_none():
    bodies = [BodyInertial("j2", 1.0, np.zeros(3), np.eye(3))]
    out = composite_inertials(desc([joint("j1", None), joint("j2", "j1")], bodies), {})
    assert list(out) == [None]


def test_to_frame_expresses_com_and_inertia_in_the_frame():
    t = make_transform(rot(Z, math.pi / 2), [1.0, 0.0, 0.0])
    com, inertia = to_frame(t, np.array([1.0, 2.0, 0.0]), np.diag([1.0, 2.0, 3.0]))
    # the frame's x axis is world y: the CoM 2 m along world y is 2 m along the frame's x
    assert com == pytest.approx([2.0, 0.0, 0.0], abs=1e-12)
    assert inertia == pytest.approx(np.diag([2.0, 1.0, 3.0]), abs=1e-12)


def test_rpy_string_gives_plain_floats():
    out = rpy_string(rpy_to_matrix([0.1, -0.2, 0.3]))
    assert out == pytest.approx([0.1, -0.2, 0.3], abs=1e-12)
    assert all(type(v) is float for v in out)


def test_kabsch_recovers_a_rigid_motion():
    r = rot(np.array([1.0, 2.0, 2.0]) / 3.0, 0.7)
    t = np.array([0.3, -1.0, 2.0])
    src = np.array([[0, 0, 0], [1, 0, 0], [0, 2, 0], [0, 0, 3], [1, 1, 1]], dtype=float)
    fit = kabsch(src, src @ r.T + t)
    assert fit[:3, :3] == pytest.approx(r, abs=1e-9)
    assert fit[:3, 3] == pytest.approx(t, abs=1e-9)
    assert fit[3] == pytest.approx([0, 0, 0, 1])


def test_kabsch_point_weights_ignore_a_zero_weight_outlier():
    src = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [5, 5, 5]], dtype=float)
    dst = src + [1.0, 2.0, 3.0]
    dst[4] = [-40.0, 7.0, 0.5]
    fit = kabsch(src, dst, w_p=[1, 1, 1, 1, 0])
    assert fit[:3, :3] == pytest.approx(np.eye(3), abs=1e-9)
    assert fit[:3, 3] == pytest.approx([1.0, 2.0, 3.0], abs=1e-9)
    # without the weights the outlier pulls the fit away
    assert not np.allclose(kabsch(src, dst)[:3, 3], [1.0, 2.0, 3.0], atol=1e-3)


def test_kabsch_uneven_weights_pull_the_translation():
    # translation-only data disagreeing between two points: the weighted mean wins
    src = np.zeros((2, 3))
    dst = np.array([[1.0, 0.0, 0.0], [4.0, 0.0, 0.0]])
    fit = kabsch(src, dst, w_p=[2.0, 1.0])
    assert fit[:3, 3] == pytest.approx([2.0, 0.0, 0.0], abs=1e-12)


def test_kabsch_directions_alone_fix_the_rotation():
    r = rot(Z, 0.4)
    d_src = np.array([X, Y])
    fit = kabsch(np.zeros((0, 3)), np.zeros((0, 3)), d_src=d_src, d_dst=d_src @ r.T)
    assert fit[:3, :3] == pytest.approx(r, abs=1e-9)
    assert fit[:3, 3] == pytest.approx([0, 0, 0], abs=1e-12)


def test_kabsch_direction_weights():
    # two directions pulling to different rotations about z; the zero-weight one is ignored
    d_src = np.array([X, Y, X])
    d_dst = np.array([X, Y, rot(Z, 1.0) @ X])
    fit = kabsch(np.zeros((0, 3)), np.zeros((0, 3)), d_src=d_src, d_dst=d_dst, w_d=[1, 1, 0])
    assert fit[:3, :3] == pytest.approx(np.eye(3), abs=1e-9)
    fit = kabsch(np.zeros((0, 3)), np.zeros((0, 3)), d_src=d_src, d_dst=d_dst, w_d=[0, 0, 1])
    assert fit[:3, :3] @ X == pytest.approx(rot(Z, 1.0) @ X, abs=1e-9)
    # directions and points together: the points fix the translation, both the rotation
    src = np.array([[0.0, 0.0, 0.0]])
    fit = kabsch(src, src + [0, 0, 1.0], d_src=d_src[:2], d_dst=d_dst[:2])
    assert fit[:3, :3] == pytest.approx(np.eye(3), abs=1e-9)
    assert fit[:3, 3] == pytest.approx([0, 0, 1.0], abs=1e-12)


def horn(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The rotation R minimising Σ |R a_i − b_i|² (centred points), by Horn's closed form: the
    unit quaternion is the top eigenvector of a symmetric 4x4 matrix."""
    s = a.T @ b
    (sxx, sxy, sxz), (syx, syy, syz), (szx, szy, szz) = s
    n = np.array(
        [
            [sxx + syy + szz, syz - szy, szx - sxz, sxy - syx],
            [syz - szy, sxx - syy - szz, sxy + syx, szx + sxz],
            [szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy],
            [sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz],
        ]
    )
    return quat_to_matrix(np.linalg.eigh(n)[1][:, -1])


def test_kabsch_never_returns_a_reflection():
    # a mirror image: the best proper rotation, as Horn's quaternion method (which cannot reflect) finds it
    src = np.array([[1, 0, 0], [0, 2, 0], [0, 0, 3], [0, 0, 0]], dtype=float)
    dst = src * [-1.0, 1.0, 1.0]
    fit = kabsch(src, dst)
    expected = horn(src - src.mean(axis=0), dst - dst.mean(axis=0))
    assert np.linalg.det(fit[:3, :3]) == pytest.approx(1.0)
    assert fit[:3, :3] == pytest.approx(expected, abs=1e-9)
    assert fit[:3, 3] == pytest.approx(dst.mean(axis=0) - fit[:3, :3] @ src.mean(axis=0), abs=1e-12)


def test_project_on_line_batched():
    # the line through (5, 0, 1) along (0.6, 0.8, 0): a point 2 along it and 3 off it along z projects onto it
    point, axis = np.array([5.0, 0.0, 1.0]), np.array([0.6, 0.8, 0.0])
    on = point + 2.0 * axis
    x = np.array([on + [0.0, 0.0, 3.0], on + 4.0 * np.array([0.8, -0.6, 0.0]), point - axis])
    assert project_on_line(x, point, axis) == pytest.approx(np.array([on, on, point - axis]), abs=1e-12)
    assert project_on_line(x[None], point, axis)[0] == pytest.approx(np.array([on, on, point - axis]), abs=1e-12)


def test_foot_on_line_skew():
    # line 1: the x axis; line 2: through (2, 5, 3) along y. The foot on line 2 is (2, 0, 3)
    assert foot_on_line(np.array([-1.0, 0.0, 0.0]), X, np.array([2.0, 5.0, 3.0]), Y) == pytest.approx([2.0, 0.0, 3.0], abs=1e-12)
    # line 2 at 30° from line 1 (|n| < 1): foot where line 2 is nearest the x axis, the point above it
    a2 = np.array([math.cos(math.pi / 6), math.sin(math.pi / 6), 0.0])
    p2 = np.array([0.0, 0.0, 2.0]) + 3.0 * a2
    assert foot_on_line(np.array([4.0, 0.0, 0.0]), X, p2, a2) == pytest.approx([0.0, 0.0, 2.0], abs=1e-12)


def test_foot_on_line_parallel_crosses_the_normal_plane():
    p = foot_on_line(np.array([1.0, 0.0, 0.0]), X, np.array([5.0, 2.0, 0.0]), -X)
    assert p == pytest.approx([1.0, 2.0, 0.0], abs=1e-12)


def test_reach_sums_the_chain():
    joints = [joint("j1", None, (0.0, 0.0, 1.0)), joint("j2", "j1", (0.0, 3.0, 5.0)), joint("j3", "j1", (1.0, 0.0, 1.0))]
    frames = {
        "base": make_transform(np.eye(3), [0.0, 0.0, 0.5]),
        "tool": make_transform(np.eye(3), [0.0, 3.0, 7.0]),
        "side": make_transform(np.eye(3), [1.0, 0.0, 1.0]),
    }
    d = desc(joints, frames=frames, owner={"base": None, "tool": "j2", "side": "j3"})
    out = reach(d)
    assert out["base"] == pytest.approx(0.5)
    assert out["tool"] == pytest.approx(1.0 + 5.0 + 2.0)  # base -> j1 (1), j1 -> j2 (3-4-5), j2 -> tool (2)
    assert out["side"] == pytest.approx(1.0 + 1.0 + 0.0)


def test_planar_removes_the_axis_component():
    assert planar(np.array([1.0, 2.0, 3.0]), Z) == pytest.approx([1.0, 2.0, 0.0])


@pytest.mark.parametrize(
    ("angle", "wrapped"),
    [
        (0.5, 0.5),
        (math.pi, -math.pi),
        (-math.pi, -math.pi),
        (1.5 * math.pi, -0.5 * math.pi),
        (-1.5 * math.pi, 0.5 * math.pi),
        (7.0, 7.0 - 2 * math.pi),
    ],
)
def test_wrap(angle, wrapped):
    assert wrap(angle) == pytest.approx(wrapped, abs=1e-12)


def test_consensus_empty_is_zero():
    assert consensus([], []) == 0.0


def test_consensus_weighted_majority_within_spread():
    # 1.0 carries 2 of 3 and the others stay apart: the group around 1.0 wins alone
    assert consensus([1.0, 1.5], [2.0, 1.0], linear=True) == pytest.approx(1.0, abs=1e-12)
    assert consensus([1.5, 1.0], [1.0, 2.0], linear=True) == pytest.approx(1.0, abs=1e-12)
    # values within the spread are averaged by weight
    assert consensus([1.0, 1.5, 3.0], [1.0, 3.0, 1.0], linear=True, spread=0.6) == pytest.approx(1.375, rel=1e-12)


def test_consensus_without_a_half_is_zero():
    assert consensus([1.0, 2.0, 3.0], [1.0, 1.0, 1.0], linear=True) == 0.0
    assert consensus([1.0, 2.0, 3.0], [1.0, 1.0, 1.0]) == 0.0
    # exactly half the weight is enough, and the first of tied groups wins
    assert consensus([1.0, 2.0], [1.0, 1.0], linear=True) == pytest.approx(1.0)
    assert consensus([2.0, 1.0], [1.0, 1.0]) == pytest.approx(2.0)


def test_consensus_angles_wrap():
    # 3.14 and -3.14 are 0.0032 rad apart across the seam; their weighted mean sits by +pi
    a, b = 3.14, -3.14
    gap = 2 * math.pi - 6.28
    out = consensus([a, b], [1.0, 3.0], spread=0.01)
    assert out == pytest.approx(a + 0.75 * gap, abs=1e-12)
    # linear: far apart, no group; 3.14 carries exactly half (the first tied group)
    assert consensus([a, b], [1.0, 1.0], linear=True, spread=0.01) == pytest.approx(a)
    assert consensus([a, b], [1.0, 3.0], linear=True, spread=0.01) == pytest.approx(b)


@pytest.mark.parametrize(("a", "b"), [(X, Y), (X, np.array([math.cos(0.5), math.sin(0.5), 0.0])), (Z, np.array([0.6, 0.0, 0.8]))])
def test_rotation_between_general(a, b):
    r = rotation_between(a, b)
    assert r @ a == pytest.approx(b, abs=1e-12)
    assert np.linalg.det(r) == pytest.approx(1.0)
    # the smallest rotation leaves a x b alone
    n = np.cross(a, b)
    assert r @ n == pytest.approx(n, abs=1e-12)


def test_rotation_between_parallel_and_opposite():
    assert np.array_equal(rotation_between(X, X), np.eye(3))
    # opposite: a half turn about a perpendicular chosen from x (or y when a is along x)
    assert rotation_between(Z, -Z) == pytest.approx(np.diag([-1.0, 1.0, -1.0]), abs=1e-12)
    assert rotation_between(X, -X) == pytest.approx(np.diag([-1.0, -1.0, 1.0]), abs=1e-12)
    assert rotation_between(-X, X) == pytest.approx(np.diag([-1.0, -1.0, 1.0]), abs=1e-12)
    # a slanted a: a half turn about a × x, normalised (|a × x| = 0.877 here)
    a = np.array([0.48, 0.6, 0.64])
    n = np.cross(a, X) / np.linalg.norm(np.cross(a, X))
    assert rotation_between(a, -a) == pytest.approx(2 * np.outer(n, n) - np.eye(3), abs=1e-12)
