"""Batched rigid-transform helpers (numpy-first, pytransform3d style).

Conventions: rotation matrices act on column vectors and map child to parent
(``R_world_from_link``); roll-pitch-yaw is URDF's fixed-axis X-Y-Z, R = Rz(yaw) Ry(pitch) Rx(roll);
quaternions are ``wxyz``. Batched functions accept ``(..., 3)`` / ``(..., 3, 3)`` arrays.
"""

from __future__ import annotations

import numpy as np


def rpy_to_matrix(rpy) -> np.ndarray:
    """Rotation matrix ``(..., 3, 3)`` from roll, pitch, yaw [rad] ``(..., 3)``."""
    rpy = np.asarray(rpy, dtype=float)
    r, p, y = rpy[..., 0], rpy[..., 1], rpy[..., 2]
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    m = np.empty(rpy.shape[:-1] + (3, 3))
    m[..., 0, 0] = cy * cp
    m[..., 0, 1] = cy * sp * sr - sy * cr
    m[..., 0, 2] = cy * sp * cr + sy * sr
    m[..., 1, 0] = sy * cp
    m[..., 1, 1] = sy * sp * sr + cy * cr
    m[..., 1, 2] = sy * sp * cr - cy * sr
    m[..., 2, 0] = -sp
    m[..., 2, 1] = cp * sr
    m[..., 2, 2] = cp * cr
    return m


def matrix_to_rpy(m) -> np.ndarray:
    """Roll, pitch, yaw [rad] of a rotation matrix (inverse of :func:`rpy_to_matrix`; pitch in
    [−π/2, π/2]). At pitch ±π/2 (gimbal lock) only roll ∓ yaw is defined: yaw is taken 0 there, and
    in every case roll is read off ``Rx(roll) = Ry(pitch)ᵀ·Rz(yaw)ᵀ·R``, so the three always make
    the matrix back."""
    m = np.asarray(m, dtype=float)
    cp = np.hypot(m[..., 0, 0], m[..., 1, 0])  # |cos(pitch)|
    pitch = np.arctan2(-m[..., 2, 0], cp)
    yaw = np.where(cp < 1e-12, 0.0, np.arctan2(m[..., 1, 0], m[..., 0, 0]))
    undone = rpy_to_matrix(np.stack([np.zeros_like(yaw), pitch, yaw], axis=-1))
    rx = np.swapaxes(undone, -1, -2) @ m
    roll = np.arctan2(rx[..., 2, 1], rx[..., 1, 1])
    return np.stack([roll, pitch, yaw], axis=-1)


def axis_angle_to_matrix(axis, angle) -> np.ndarray:
    """Rodrigues rotation about unit ``axis`` (3,) by ``angle`` [rad] ``(N,)`` -> ``(N, 3, 3)``."""
    axis = np.asarray(axis, dtype=float)
    angle = np.asarray(angle, dtype=float)
    k = skew(axis)
    s, c = np.sin(angle)[..., None, None], np.cos(angle)[..., None, None]
    return np.eye(3) + s * k + (1.0 - c) * (k @ k)


def skew(v) -> np.ndarray:
    """Cross-product matrix of ``(..., 3)`` vectors."""
    v = np.asarray(v, dtype=float)
    z = np.zeros(v.shape[:-1])
    return np.stack(
        [
            np.stack([z, -v[..., 2], v[..., 1]], -1),
            np.stack([v[..., 2], z, -v[..., 0]], -1),
            np.stack([-v[..., 1], v[..., 0], z], -1),
        ],
        -2,
    )


def make_transform(rotation, translation) -> np.ndarray:
    """Homogeneous transform ``(..., 4, 4)`` from ``(..., 3, 3)`` and ``(..., 3)``."""
    rotation = np.asarray(rotation, dtype=float)
    translation = np.asarray(translation, dtype=float)
    shape = np.broadcast_shapes(rotation.shape[:-2], translation.shape[:-1])
    t = np.zeros(shape + (4, 4))
    t[..., :3, :3] = rotation
    t[..., :3, 3] = translation
    t[..., 3, 3] = 1.0
    return t


def xyz_rpy_to_transform(xyz, rpy) -> np.ndarray:
    return make_transform(rpy_to_matrix(rpy), xyz)


def matrix_to_quat(m) -> np.ndarray:
    """Unit quaternion ``wxyz`` (w >= 0) of rotation matrices ``(..., 3, 3)``."""
    m = np.asarray(m, dtype=float)
    flat = m.reshape(-1, 3, 3)
    out = np.empty((flat.shape[0], 4))
    for i, r in enumerate(flat):
        # Shepperd's method: pick the largest diagonal term for numerical stability.
        tr = np.trace(r)
        cand = np.array([tr, r[0, 0], r[1, 1], r[2, 2]])
        k = int(np.argmax(cand))
        if k == 0:
            s = np.sqrt(1.0 + tr) * 2
            q = [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
        elif k == 1:
            s = np.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2]) * 2
            q = [(r[2, 1] - r[1, 2]) / s, 0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s]
        elif k == 2:
            s = np.sqrt(1.0 + r[1, 1] - r[0, 0] - r[2, 2]) * 2
            q = [(r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s]
        else:
            s = np.sqrt(1.0 + r[2, 2] - r[0, 0] - r[1, 1]) * 2
            q = [(r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s]
        quat = np.asarray(q)
        quat /= np.linalg.norm(quat)
        out[i] = quat if quat[0] >= 0 else -quat
    return out.reshape(m.shape[:-2] + (4,))


def quat_to_matrix(q) -> np.ndarray:
    """Rotation matrices ``(..., 3, 3)`` from quaternions ``wxyz`` ``(..., 4)``."""
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    m = np.empty(q.shape[:-1] + (3, 3))
    m[..., 0, 0] = 1 - 2 * (y * y + z * z)
    m[..., 0, 1] = 2 * (x * y - z * w)
    m[..., 0, 2] = 2 * (x * z + y * w)
    m[..., 1, 0] = 2 * (x * y + z * w)
    m[..., 1, 1] = 1 - 2 * (x * x + z * z)
    m[..., 1, 2] = 2 * (y * z - x * w)
    m[..., 2, 0] = 2 * (x * z - y * w)
    m[..., 2, 1] = 2 * (y * z + x * w)
    m[..., 2, 2] = 1 - 2 * (x * x + y * y)
    return m


def rotation_vee(m) -> np.ndarray:
    """The vector of the skew part of ``(..., 3, 3)``: (m - m^T)^vee / 2."""
    return 0.5 * np.stack([m[..., 2, 1] - m[..., 1, 2], m[..., 0, 2] - m[..., 2, 0], m[..., 1, 0] - m[..., 0, 1]], -1)


def rotation_angle(m) -> np.ndarray:
    """Geodesic angle [rad] of rotation matrices, accurate near 0 (atan2, not arccos)."""
    s = np.linalg.norm(rotation_vee(m), axis=-1)
    c = 0.5 * (np.trace(m, axis1=-2, axis2=-1) - 1.0)
    return np.arctan2(s, c)


def rotation_log(m) -> np.ndarray:
    """Rotation vector (axis * angle, angle in [0, pi]) ``(..., 3)`` of rotation matrices.

    Near pi the skew part vanishes, so the axis is taken there from the symmetric part
    ``(R + Rᵀ)/2 − cos θ·I = (1 − cos θ)·a aᵀ``, its sign from the skew part.
    """
    m = np.asarray(m, dtype=float)
    v = rotation_vee(m)
    s = np.linalg.norm(v, axis=-1)
    angle = rotation_angle(m)
    scale = np.where(s > 1e-12, angle / np.where(s > 1e-12, s, 1.0), 1.0)
    out = v * scale[..., None]
    near_pi = angle > np.pi - 1e-3
    if np.any(near_pi):
        mp = m[near_pi]
        cos = np.cos(angle[near_pi])[..., None, None]
        b = 0.5 * (mp + np.swapaxes(mp, -1, -2)) - cos * np.eye(3)
        col = np.argmax(np.diagonal(b, axis1=-2, axis2=-1), axis=-1)
        axis = np.take_along_axis(b, col[..., None, None].repeat(3, -1), axis=-1)[..., 0]
        axis /= np.linalg.norm(axis, axis=-1, keepdims=True)
        sign = np.where(np.sum(axis * v[near_pi], axis=-1) < 0, -1.0, 1.0)
        out[near_pi] = axis * (sign * angle[near_pi])[..., None]
    return out


def geodesic_distance(r_a, r_b) -> np.ndarray:
    """Angle [rad] of the rotation taking ``r_a`` to ``r_b`` (both ``(..., 3, 3)``)."""
    return rotation_angle(np.swapaxes(r_a, -1, -2) @ r_b)


def invert_transform(t) -> np.ndarray:
    t = np.asarray(t, dtype=float)
    rt = np.swapaxes(t[..., :3, :3], -1, -2)
    return make_transform(rt, -(rt @ t[..., :3, 3, None])[..., 0])
