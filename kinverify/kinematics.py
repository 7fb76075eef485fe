"""Batched forward kinematics and geometric Jacobians straight from an ArmSpec (numpy only).

No per-configuration Python loop: each joint is one vectorised step over all N configurations.
Poses are ``T_world_from_frame`` ``(N, F, 4, 4)`` in ``spec.frame_names`` order; Jacobians are
world-aligned, taken at each frame's origin, rows ``[linear; angular]``: ``(N, F, 6, n)``.
"""

from __future__ import annotations

import numpy as np

from .spec import ArmSpec
from .transforms import axis_angle_to_matrix


def check_configurations(spec: ArmSpec, q) -> np.ndarray:
    """``q`` as a float array ``(N, n)``; a single ``(n,)`` vector becomes ``(1, n)``."""
    q = np.asarray(q, dtype=float)
    if q.ndim == 1:
        q = q[None, :]
    if q.ndim != 2 or q.shape[1] != spec.dof:
        raise ValueError(f"expected configurations of shape (N, {spec.dof}), got {q.shape}")
    return q


def joint_motion(joint, values: np.ndarray) -> np.ndarray:
    """``(N, 4, 4)`` motion of ``joint`` at ``values``: rotation about or translation along its axis."""
    t = np.zeros(values.shape + (4, 4))
    t[..., 3, 3] = 1.0
    if joint.type == "revolute":
        t[..., :3, :3] = axis_angle_to_matrix(joint.axis, values)
    else:
        t[..., :3, :3] = np.eye(3)
        t[..., :3, 3] = np.multiply.outer(values, joint.axis)
    return t


def link_poses(spec: ArmSpec, q) -> np.ndarray:
    """World poses of the base link and every joint's link, ``(N, n + 1, 4, 4)``."""
    q = check_configurations(spec, q)
    out = np.empty((q.shape[0], spec.dof + 1, 4, 4))
    out[:, 0] = spec.base_origin.transform
    for i, joint in enumerate(spec.joints):
        out[:, i + 1] = (out[:, i] @ joint.origin.transform) @ joint_motion(joint, q[:, i])
    return out


def tool_poses(spec: ArmSpec, links: np.ndarray) -> np.ndarray:
    """World poses ``(N, n_tools, 4, 4)`` of the tools, given the link poses."""
    if not spec.tools:
        return np.empty(links.shape[:1] + (0, 4, 4))
    parents = [spec.link_index(t.parent) for t in spec.tools]
    offsets = np.stack([t.origin.transform for t in spec.tools])
    return links[:, parents] @ offsets


def frame_poses(spec: ArmSpec, q) -> np.ndarray:
    """World poses of every frame in ``spec.frame_names`` order, ``(N, F, 4, 4)``."""
    links = link_poses(spec, q)
    return np.concatenate([links, tool_poses(spec, links)], axis=1)


def frame_link_indices(spec: ArmSpec) -> np.ndarray:
    """For each frame, the index of the link it rides on (0 = base)."""
    return np.array(list(range(spec.dof + 1)) + [spec.link_index(t.parent) for t in spec.tools])


def geometric_jacobians(spec: ArmSpec, poses: np.ndarray) -> np.ndarray:
    """Jacobians ``(N, F, 6, n)`` of every frame from the frame poses of :func:`frame_poses`.

    Joint i moves link i+1 whose frame origin lies on the joint axis, so the axis in the world is
    ``R_link · axis`` through ``p_link``. Revolute column: ``[z × (p_frame − p_joint); z]``;
    prismatic: ``[z; 0]``. Columns of joints that are not ancestors of the frame are zero.
    """
    n = spec.dof
    joint_links = poses[:, 1 : n + 1]
    axes = np.stack([j.axis for j in spec.joints])
    z = np.einsum("nkij,kj->nki", joint_links[..., :3, :3], axes)  # (N, n, 3)
    o = joint_links[..., :3, 3]  # (N, n, 3)
    p = poses[..., :3, 3]  # (N, F, 3)
    lever = p[:, :, None, :] - o[:, None, :, :]  # (N, F, n, 3)
    zb = np.broadcast_to(z[:, None], lever.shape)
    revolute = np.array([j.type == "revolute" for j in spec.joints])
    linear = np.where(revolute[None, None, :, None], np.cross(zb, lever), zb)
    angular = np.where(revolute[None, None, :, None], zb, 0.0)
    ancestor = np.arange(n)[None, :] < frame_link_indices(spec)[:, None]  # (F, n)
    jac = np.concatenate([linear, angular], axis=-1) * ancestor[None, :, :, None]
    return np.swapaxes(jac, -1, -2)


def home_tool_position(spec: ArmSpec) -> np.ndarray:
    """World position [m] of the last frame (the last tool if any) at q = 0."""
    return frame_poses(spec, np.zeros(spec.dof))[0, -1, :3, 3]
