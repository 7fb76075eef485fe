"""Denavit-Hartenberg tables: conversion into a joint chain, and a DH-matrix FK of their own.

Standard DH (Spong): ``T_{i-1,i} = Rz(θ_i + q) · Tz(d_i) · Tx(a_i) · Rx(α_i)`` (prismatic: ``d_i + q``).
Modified DH (Craig): ``T_{i-1,i} = Rx(α_{i-1}) · Tx(a_{i-1}) · Rz(θ_i + q) · Tz(d_i)``; a modified
row stores ``α_{i-1}, a_{i-1}`` in its ``alpha, a`` fields, as published tables do.

Both become URDF-style joints (static origin, then motion about/along local z):
- modified: ``origin_i = Rx(α)·Tx(a)·Rz(θ)·Tz(d)``, so link i's frame is DH frame i;
- standard: ``origin_i = S_{i-1}`` with ``S = Rz(θ)·Tz(d)·Tx(a)·Rx(α)`` (identity for i = 0), so
  link i's frame is DH frame i-1 moved by q_i, and DH frame n is the ``flange`` tool ``S_n``.
"""

from __future__ import annotations

import numpy as np

from kinverify.model.spec import DHRow, Origin
from kinverify.model.transforms import matrix_to_rpy

CONVENTIONS = ("standard", "modified")


def rot_x(angle) -> np.ndarray:
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    t = np.zeros(angle.shape + (4, 4))
    t[..., 0, 0] = t[..., 3, 3] = 1.0
    t[..., 1, 1], t[..., 1, 2], t[..., 2, 1], t[..., 2, 2] = c, -s, s, c
    return t


def rot_z(angle) -> np.ndarray:
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    t = np.zeros(angle.shape + (4, 4))
    t[..., 2, 2] = t[..., 3, 3] = 1.0
    t[..., 0, 0], t[..., 0, 1], t[..., 1, 0], t[..., 1, 1] = c, -s, s, c
    return t


def trans(x=0.0, y=0.0, z=0.0) -> np.ndarray:
    x, y, z = np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in (x, y, z)))
    t = np.zeros(x.shape + (4, 4))
    t[..., 0, 0] = t[..., 1, 1] = t[..., 2, 2] = t[..., 3, 3] = 1.0
    t[..., 0, 3], t[..., 1, 3], t[..., 2, 3] = x, y, z
    return t


def dh_matrix(convention: str, row: DHRow, q=0.0, prismatic: bool = False) -> np.ndarray:
    """The DH link transform of ``row`` at joint value(s) ``q`` ``(N,)`` -> ``(N, 4, 4)``."""
    q = np.asarray(q, dtype=float)
    theta = row.theta + (0.0 if prismatic else q)
    d = row.d + (q if prismatic else 0.0)
    if convention == "standard":
        return rot_z(theta) @ trans(z=d) @ trans(x=row.a) @ rot_x(row.alpha)
    return rot_x(row.alpha) @ trans(x=row.a) @ rot_z(theta) @ trans(z=d)


def origin_from_transform(t: np.ndarray) -> Origin:
    """The ``Origin`` (xyz, rpy) of a 4×4 transform."""
    return Origin(tuple(t[:3, 3]), tuple(matrix_to_rpy(t[:3, :3])))


def static_part(convention: str, row: DHRow) -> np.ndarray:
    """The transform of ``row`` at q = 0 (revolute and prismatic alike)."""
    return dh_matrix(convention, row)


def joint_origins(convention: str, rows: tuple[DHRow, ...]) -> tuple[list[Origin], np.ndarray | None]:
    """Joint origins of the equivalent URDF-style chain, and the flange transform (standard only)."""
    if convention == "modified":
        return [origin_from_transform(static_part(convention, r)) for r in rows], None
    origins = [Origin()] + [origin_from_transform(static_part(convention, r)) for r in rows[:-1]]
    return origins, static_part(convention, rows[-1])


def dh_link_poses(convention: str, rows, prismatic, base: np.ndarray, q: np.ndarray) -> np.ndarray:
    """World poses ``(N, n, 4, 4)`` of the link frames computed by DH matrix products only.

    For modified DH, link i is DH frame i. For standard DH it is DH frame i-1 moved by joint i
    (``Rz(q)`` or ``Tz(q)``), matching :func:`joint_origins`.
    """
    q = np.atleast_2d(np.asarray(q, dtype=float))
    n_cfg, n = q.shape
    out = np.empty((n_cfg, n, 4, 4))
    frame = np.broadcast_to(base, (n_cfg, 4, 4))
    for i, row in enumerate(rows):
        if convention == "modified":
            frame = frame @ dh_matrix(convention, row, q[:, i], prismatic[i])
            out[:, i] = frame
        else:
            motion = trans(z=q[:, i]) if prismatic[i] else rot_z(q[:, i])
            out[:, i] = frame @ motion
            frame = frame @ dh_matrix(convention, row, q[:, i], prismatic[i])
    return out
