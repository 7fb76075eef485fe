"""Batched forward kinematics and geometric Jacobians straight from an ArmSpec (numpy only).

No per-configuration Python loop: each joint is one vectorised step over all N configurations.
Poses are ``T_world_from_frame`` ``(N, F, 4, 4)`` in ``spec.frame_names`` order; Jacobians are
world-aligned, taken at each frame's origin, rows ``[linear; angular]``: ``(N, F, 6, n)``.
"""

from __future__ import annotations

import numpy as np

from kinverify.model.spec import ArmSpec
from kinverify.model.floating import base_transforms, rate_matrices
from kinverify.model.transforms import axis_angle_to_matrix


def check_configurations(spec: ArmSpec, q) -> np.ndarray:
    """``q`` as a float array ``(N, nq)``; a single ``(nq,)`` vector becomes ``(1, nq)``. ``nq`` is
    the number of joints, plus the six base coordinates first for a floating base."""
    q = np.asarray(q, dtype=float)
    if q.ndim == 1:
        q = q[None, :]
    if q.ndim != 2 or q.shape[1] != spec.nq:
        raise ValueError(f"expected configurations of shape (N, {spec.nq}), got {q.shape}")
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


def joint_local_coefficients(joint) -> np.ndarray:
    """Constant matrix ``K`` with ``origin @ motion(v)`` = ``(basis(v) @ K).reshape(4, 4)``.

    Revolute: Rodrigues ``R(v) = I + sin v·S + (1 − cos v)·S²`` with ``S = skew(axis)``, so the
    local transform is linear in ``(1, sin v, cos v)``; prismatic: linear in ``(1, v)``.
    """
    o = joint.origin.transform
    axis = np.asarray(joint.axis, dtype=float)
    if joint.type == "revolute":
        k = np.zeros((3, 4, 4))
        sk = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        rot = o[:3, :3]
        k[0] = o
        k[0, :3, :3] = rot @ (np.eye(3) + sk @ sk)
        k[1, :3, :3] = rot @ sk
        k[2, :3, :3] = -(rot @ (sk @ sk))
    else:
        k = np.zeros((2, 4, 4))
        k[0] = o
        k[1, :3, 3] = o[:3, :3] @ axis
    return k.reshape(len(k), 16)


_COEFFICIENTS: dict[int, tuple[ArmSpec, list[np.ndarray]]] = {}  # id(spec) -> (spec, per joint)


def _coefficients(spec: ArmSpec) -> list[np.ndarray]:
    hit = _COEFFICIENTS.get(id(spec))
    if hit is None or hit[0] is not spec:
        if len(_COEFFICIENTS) >= 32:
            _COEFFICIENTS.clear()
        hit = _COEFFICIENTS[id(spec)] = (spec, [joint_local_coefficients(j) for j in spec.joints])
    return hit[1]


def link_poses(spec: ArmSpec, q, out: np.ndarray | None = None) -> np.ndarray:
    """World poses of the base link and every joint's link, ``(N, n + 1, 4, 4)`` (written into
    ``out[:, :n + 1]`` when given).

    Batched: each joint's local transform ``origin @ motion(q_i)`` for all N
    configurations is one small matrix product ``(N, 3) @ (3, 16)`` of ``(1, sin, cos)`` with
    constants (:func:`joint_local_coefficients`), then one stacked 4×4 product per joint, on
    contiguous buffers.
    """
    q = check_configurations(spec, q)
    n_cfg = q.shape[0]
    if out is None:
        out = np.empty((n_cfg, spec.dof + 1, 4, 4))
    if spec.floating:  # the base pose is the first six coordinates
        out[:, 0] = base_transforms(q[:, :6])
        q = q[:, 6:]
    else:
        out[:, 0] = spec.base_origin.transform
    basis = np.empty((n_cfg, 3))
    basis[:, 0] = 1.0
    for i, (joint, coef, parent) in enumerate(zip(spec.joints, _coefficients(spec), spec.parent_indices, strict=True)):
        if joint.type == "revolute":
            np.sin(q[:, i], out=basis[:, 1])
            np.cos(q[:, i], out=basis[:, 2])
            local = basis @ coef
        else:
            basis[:, 1] = q[:, i]
            local = basis[:, :2] @ coef
        np.matmul(out[:, parent], local.reshape(n_cfg, 4, 4), out=out[:, i + 1])  # the parent link: any earlier one
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
    q = check_configurations(spec, q)
    out = np.empty((q.shape[0], spec.dof + 1 + len(spec.tools), 4, 4))
    link_poses(spec, q, out)
    for k, tool in enumerate(spec.tools):
        np.matmul(out[:, spec.link_index(tool.parent)], tool.origin.transform, out=out[:, spec.dof + 1 + k])
    return out


def frame_link_indices(spec: ArmSpec) -> np.ndarray:
    """For each frame, the index of the link it rides on (0 = base)."""
    return np.array(list(range(spec.dof + 1)) + [spec.link_index(t.parent) for t in spec.tools])


def geometric_jacobians(spec: ArmSpec, poses: np.ndarray, q=None) -> np.ndarray:
    """Jacobians ``(N, F, 6, nq)`` of every frame from the frame poses of :func:`frame_poses`
    (``q``, the configurations, is needed with a floating base).

    Joint i moves link i+1 whose frame origin lies on the joint axis, so the axis in the world is
    ``R_link · axis`` through ``p_link``. Revolute column: ``[z × (p_frame − p_joint); z]``;
    prismatic: ``[z; 0]``. Columns of joints that are not on the path from the base to the
    frame (another branch of a tree, or further out) are zero. A floating base adds six columns
    in front, moving every frame: world translations ``[e_k; 0]`` and the roll, pitch and yaw
    axes ``a`` through the base origin ``[a × (p_frame − p_base); a]``.
    """
    joints = _joint_jacobians(spec, poses)
    if not spec.floating:
        return joints
    if q is None:
        raise ValueError("a floating base's Jacobian columns need the configurations q")
    q = check_configurations(spec, q)
    axes = rate_matrices(q[:, :6])  # (N, 3, 3): world roll, pitch, yaw axes as columns
    lever = poses[..., :3, 3] - poses[:, :1, :3, 3]  # (N, F, 3)
    base = np.zeros(poses.shape[:2] + (6, 6))
    base[..., :3, :3] = np.eye(3)
    a = np.broadcast_to(np.swapaxes(axes, -1, -2)[:, None], lever.shape[:2] + (3, 3))  # (N, F, axis, xyz)
    base[..., :3, 3:] = np.swapaxes(np.cross(a, lever[:, :, None, :]), -1, -2)
    base[..., 3:, 3:] = axes[:, None]
    return np.concatenate([base, joints], axis=-1)


def _joint_jacobians(spec: ArmSpec, poses: np.ndarray) -> np.ndarray:
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
    ancestor = spec.ancestors()[frame_link_indices(spec)]  # (F, n): does joint i move frame f?
    jac = np.concatenate([linear, angular], axis=-1) * ancestor[None, :, :, None]
    return np.swapaxes(jac, -1, -2)


def home_tool_position(spec: ArmSpec) -> np.ndarray:
    """World position [m] of the last frame (the last tool if any) at the home configuration."""
    return frame_poses(spec, spec.home())[0, -1, :3, 3]
