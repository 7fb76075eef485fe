"""Small geometric helpers for comparing two descriptions: axis lines, composite inertials."""

from __future__ import annotations

import math

import numpy as np

from kinverify.filemode.read.model import ModelDesc
from kinverify.model.transforms import axis_angle_to_matrix, geodesic_distance, invert_transform, matrix_to_rpy


def apply(t: np.ndarray, p: np.ndarray) -> np.ndarray:
    return t[:3, :3] @ p + t[:3, 3]


def angle_between(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), np.dot(a, b)))


def line_distance(p1, a1, p2, a2) -> float:
    """Shortest distance between the lines p1 + s·a1 and p2 + t·a2 (unit directions)."""
    d = np.asarray(p2) - np.asarray(p1)
    n = np.cross(a1, a2)
    if np.linalg.norm(n) < 1e-9:
        return float(np.linalg.norm(np.cross(d, a1)))
    return float(abs(np.dot(d, n)) / np.linalg.norm(n))


def pose_difference(t_a: np.ndarray, t_b: np.ndarray) -> tuple[float, float]:
    """(position distance [m], rotation angle [rad]) between two poses."""
    return (float(np.linalg.norm(t_a[:3, 3] - t_b[:3, 3])), float(geodesic_distance(t_a[:3, :3], t_b[:3, :3])))


def frame_pose(desc: ModelDesc, name: str) -> np.ndarray:
    return desc.frames.get(name, np.eye(4))


def composite_inertials(desc: ModelDesc, owner_map: dict) -> dict:
    """Mass, CoM and inertia about the CoM (world, q = 0) of everything moving with each key of
    ``owner_map`` (joint -> key; joints missing from it go to their parent's key)."""
    parent = {j.name: j.parent for j in desc.joints}

    def key_of(owner):
        while owner is not None and owner not in owner_map:
            owner = parent.get(owner)
        return owner_map.get(owner) if owner is not None else None

    groups: dict = {}
    for body in desc.bodies:
        groups.setdefault(key_of(body.owner), []).append(body)
    out = {}
    for key, bodies in groups.items():
        mass = sum(b.mass for b in bodies)
        com = sum(b.mass * b.com for b in bodies) / mass
        inertia = np.zeros((3, 3))
        for b in bodies:
            r = b.com - com
            inertia += b.inertia + b.mass * (np.dot(r, r) * np.eye(3) - np.outer(r, r))
        out[key] = (mass, com, inertia)
    return out


def to_frame(t_world_frame: np.ndarray, com: np.ndarray, inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """CoM and inertia tensor expressed in a frame given by its world pose."""
    inv = invert_transform(t_world_frame)
    rot = t_world_frame[:3, :3]
    return apply(inv, com), rot.T @ inertia @ rot


def rpy_string(rot: np.ndarray) -> list[float]:

    return [float(v) for v in matrix_to_rpy(rot)]


def kabsch(
    p_src: np.ndarray,
    p_dst: np.ndarray,
    w_p: np.ndarray | None = None,
    d_src: np.ndarray | None = None,
    d_dst: np.ndarray | None = None,
    w_d: np.ndarray | None = None,
) -> np.ndarray:
    """The rigid transform T (4x4) minimising Σ w_p |T p_src − p_dst|² + Σ w_d |R d_src − d_dst|²
    over points ``(N, 3)`` and unit directions ``(M, 3)`` (directions constrain the rotation only)."""
    w_p = np.ones(len(p_src)) if w_p is None else np.asarray(w_p, dtype=float)
    if len(p_src):
        cs = (w_p[:, None] * p_src).sum(axis=0) / w_p.sum()
        cd = (w_p[:, None] * p_dst).sum(axis=0) / w_p.sum()
        h = (w_p[:, None] * (p_src - cs)).T @ (p_dst - cd)
    else:
        cs = cd = np.zeros(3)
        h = np.zeros((3, 3))
    if d_src is not None and len(d_src):
        w_d = np.ones(len(d_src)) if w_d is None else np.asarray(w_d, dtype=float)
        h = h + (w_d[:, None] * d_src).T @ d_dst
    u, _, vt = np.linalg.svd(h)
    d = np.diag([1.0, 1.0, np.sign(np.linalg.det(vt.T @ u.T)) or 1.0])
    rot = vt.T @ d @ u.T
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = rot, cd - rot @ cs
    return t


def project_on_line(x: np.ndarray, point: np.ndarray, axis: np.ndarray) -> np.ndarray:
    """Closest points on the line ``point + s·axis`` to ``x`` (batched over leading axes)."""
    d = x - point
    return point + np.sum(d * axis, axis=-1, keepdims=True) * axis


def foot_on_line(p1, a1, p2, a2) -> np.ndarray:
    """The point of line 2 closest to line 1 (the foot of their common perpendicular); for
    parallel lines, where line 2 crosses the plane through ``p1`` normal to ``a1``."""
    n = np.cross(a1, a2)
    d = np.asarray(p2) - np.asarray(p1)
    nn = float(np.dot(n, n))
    if nn < 1e-12:
        return np.asarray(p2) - np.dot(d, a1) / np.dot(a2, a1) * np.asarray(a2)
    t = np.dot(np.cross(d, a1), n) / nn  # p2 + t·a2 is the foot on line 2
    return np.asarray(p2) + t * np.asarray(a2)


def reach(desc: ModelDesc) -> dict[str, float]:
    """Per frame, the length of its chain from the base at q = 0 (joint anchor to joint anchor,
    then to the frame): the largest distance a rotation error upstream can move it by."""
    anchors: dict[str | None, np.ndarray] = {j.name: j.anchor for j in desc.joints}
    parent: dict[str | None, str | None] = {j.name: j.parent for j in desc.joints}
    length: dict[str | None, float] = {None: 0.0}

    def chain(joint: str | None) -> float:
        if joint not in length:
            up = parent.get(joint)
            start = anchors[up] if up is not None else np.zeros(3)
            length[joint] = chain(up) + float(np.linalg.norm(anchors[joint] - start))
        return length[joint]

    out = {}
    for name, pose in desc.frames.items():
        owner = desc.frame_owner.get(name)
        start = anchors[owner] if owner is not None else np.zeros(3)
        out[name] = chain(owner) + float(np.linalg.norm(pose[:3, 3] - start))
    return out


def planar(v: np.ndarray, axis: np.ndarray) -> np.ndarray:
    return v - (v @ axis) * axis


def wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def consensus(values: list[float], weights: list[float], linear: bool = False, spread: float = 1e-6) -> float:
    """The value most features agree on (within spread), weighted; 0 when they do not
    agree on one value carrying at least half the weight."""
    if not values:
        return 0.0
    diff = (lambda x, y: abs(x - y)) if linear else (lambda x, y: abs(wrap(x - y)))
    total = sum(weights)
    best, support = 0.0, 0.0
    for v in values:
        group = [(x, w) for x, w in zip(values, weights, strict=True) if diff(x, v) <= spread]
        s = sum(w for _, w in group)
        if s > support:
            support = s
            ref = v
            if linear:
                best = sum(x * w for x, w in group) / s
            else:
                best = ref + sum(wrap(x - ref) * w for x, w in group) / s
    return best if support >= total / 2 else 0.0


def rotation_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The smallest rotation taking unit vector a onto b."""
    v = np.cross(a, b)
    c = float(a @ b)
    if np.linalg.norm(v) < 1e-12:
        if c > 0:
            return np.eye(3)
        perp = np.cross(a, [1.0, 0, 0] if abs(a[0]) < 0.9 else [0, 1.0, 0])
        return axis_angle_to_matrix(perp / np.linalg.norm(perp), np.array([math.pi]))[0]
    return axis_angle_to_matrix(v / np.linalg.norm(v), np.array([math.atan2(np.linalg.norm(v), c)]))[0]
