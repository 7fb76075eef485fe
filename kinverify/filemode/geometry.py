"""Small geometric helpers for comparing two descriptions: axis lines, composite inertials."""

from __future__ import annotations

import numpy as np

from kinverify.model.transforms import geodesic_distance, invert_transform
from kinverify.filemode.describe import ModelDesc


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
    return (float(np.linalg.norm(t_a[:3, 3] - t_b[:3, 3])),
            float(geodesic_distance(t_a[:3, :3], t_b[:3, :3])))


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
    from kinverify.model.transforms import matrix_to_rpy

    return [float(v) for v in matrix_to_rpy(rot)]
