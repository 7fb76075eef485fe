"""A floating base as six configuration coordinates in front of the joints.

A floating-base model's configuration is ``q = [base:x, base:y, base:z, base:roll, base:pitch,
base:yaw, joints...]``: the world pose of the base link, ``T = Trans(x, y, z)·Rz(yaw)·Ry(pitch)·
Rx(roll)`` (URDF's fixed-axis roll-pitch-yaw), followed by the joint values. Jacobian and mass
matrix columns are the derivatives with respect to these coordinates, so every library's
native floating base is converted to them at its adapter (Pinocchio's free-flyer ``[xyz,
quat xyzw]`` with a body-frame twist; MuJoCo's free joint ``[xyz, quat wxyz]`` with a world
linear and body angular velocity) and FK, Jacobians, mass matrix and gravity are compared in
one set of coordinates.

The names carry a ``:``, which no joint name can (kinverify names are letters, digits, ``_ - .``).
"""

from __future__ import annotations

import math

import numpy as np

from kinverify.model.transforms import matrix_to_rpy

BASE_COORDINATES = ("base:x", "base:y", "base:z", "base:roll", "base:pitch", "base:yaw")
BASE_REVOLUTE = (False, False, False, True, True, True)
BASE_TRAVEL = 1.0  # m: sampled base positions lie within this of the home position, per axis
FLOATING_JOINT = "floating_base"  # the generated URDF's floating joint and MJCF's free joint


def has_base(names) -> bool:
    """Do these coordinate names start with the floating base's six?"""
    return tuple(names[:6]) == BASE_COORDINATES


def base_limits(home_xyz) -> tuple[np.ndarray, np.ndarray]:
    """Sampling ranges of the six base coordinates: the home position ± ``BASE_TRAVEL``, every
    roll and yaw, and pitch in [−π/2, π/2] (which covers every orientation)."""
    home = np.asarray(home_xyz, dtype=float)
    lower = np.concatenate([home - BASE_TRAVEL, [-math.pi, -math.pi / 2, -math.pi]])
    upper = np.concatenate([home + BASE_TRAVEL, [math.pi, math.pi / 2, math.pi]])
    return lower, upper


def _rotations(rpy: np.ndarray) -> np.ndarray:
    r, p, y = rpy[..., 0], rpy[..., 1], rpy[..., 2]
    cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    out = np.empty(rpy.shape[:-1] + (3, 3))
    out[..., 0, 0], out[..., 0, 1], out[..., 0, 2] = cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr
    out[..., 1, 0], out[..., 1, 1], out[..., 1, 2] = sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr
    out[..., 2, 0], out[..., 2, 1], out[..., 2, 2] = -sp, cp * sr, cp * cr
    return out


def base_transforms(b) -> np.ndarray:
    """World poses ``(N, 4, 4)`` of the base link for base coordinates ``b`` ``(N, 6)``."""
    b = np.asarray(b, dtype=float)
    out = np.zeros(b.shape[:-1] + (4, 4))
    out[..., :3, :3] = _rotations(b[..., 3:6])
    out[..., :3, 3] = b[..., :3]
    out[..., 3, 3] = 1.0
    return out


def rate_matrices(b) -> np.ndarray:
    """``E`` ``(N, 3, 3)``: world angular velocity of the base = ``E @ [roll, pitch, yaw] rates``.

    With ``R = Rz(yaw)·Ry(pitch)·Rx(roll)`` the columns are the world roll axis ``Rz·Ry·x``, the
    pitch axis ``Rz·y`` and the yaw axis ``z``."""
    b = np.asarray(b, dtype=float)
    p, y = b[..., 4], b[..., 5]
    cp, sp, cy, sy = np.cos(p), np.sin(p), np.cos(y), np.sin(y)
    out = np.zeros(b.shape[:-1] + (3, 3))
    out[..., 0, 0], out[..., 1, 0], out[..., 2, 0] = cy * cp, sy * cp, -sp
    out[..., 0, 1], out[..., 1, 1] = -sy, cy
    out[..., 2, 2] = 1.0
    return out


def velocity_map(b, linear_in_body: bool) -> np.ndarray:
    """``S`` ``(N, 6, 6)``: a library's native base velocity = ``S @`` our base coordinate rates.

    Angular: the body-frame angular velocity ``Rᵀ·E`` (Pinocchio's free-flyer and MuJoCo's free
    joint both use it). Linear: the body-frame velocity of the base origin ``Rᵀ`` (Pinocchio), or
    its world velocity ``I`` (MuJoCo, ``linear_in_body=False``)."""
    b = np.asarray(b, dtype=float)
    rt = np.swapaxes(_rotations(b[..., 3:6]), -1, -2)
    out = np.zeros(b.shape[:-1] + (6, 6))
    out[..., :3, :3] = rt if linear_in_body else np.eye(3)
    out[..., 3:, 3:] = rt @ rate_matrices(b)
    return out


def base_coordinates(transforms) -> np.ndarray:
    """The base coordinates ``(N, 6)`` of world poses ``(N, 4, 4)`` (pitch in [−π/2, π/2])."""
    t = np.asarray(transforms, dtype=float)
    return np.concatenate([t[..., :3, 3], matrix_to_rpy(t[..., :3, :3])], axis=-1)
