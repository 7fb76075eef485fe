"""IK targets: reachable ones (FK of random configurations inside the limits) and unreachable
ones (beyond a bound on the arm's reach, with the closest approach any configuration can make)."""

from __future__ import annotations

import numpy as np

from kinverify.pipeline.sampling import uniform_configurations


def reachable_targets(backend, frame: str, lower, upper, n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """``(q (n, dof), T (n, 4, 4))``: uniform configurations inside the limits and ``frame``'s pose."""
    q = uniform_configurations(lower, upper, n, seed)
    if n == 0:
        return q, np.empty((0, 4, 4))
    poses = backend.evaluate(q, with_jacobians=False).poses[:, backend.frames.index(frame)]
    return q, poses


def reach_bound(spec, frame: str) -> tuple[np.ndarray, float]:
    """``(centre, radius)``: no configuration puts ``frame`` farther than ``radius`` from ``centre``
    (the origin of the first joint on the path from the base to ``frame``). Radius = the sum of
    the offsets after that joint along the path (in a tree, the frame's own branch) plus each
    prismatic joint's largest travel on it."""
    from kinverify.model.kinematics import frame_link_indices

    link = int(frame_link_indices(spec)[spec.frame_names.index(frame)])  # frame rides on link `link`
    path = [spec.joints[i] for i in np.flatnonzero(spec.ancestors()[link])]
    tools = {t.name: t for t in spec.tools}
    tool_offset = float(np.linalg.norm(tools[frame].origin.transform[:3, 3])) if frame in tools else 0.0
    if not path:  # rides on the base: it never moves
        from kinverify.model.kinematics import frame_poses

        return frame_poses(spec, np.zeros(spec.dof))[0, spec.frame_names.index(frame), :3, 3], 0.0
    first = spec.base_origin.transform @ path[0].origin.transform
    radius = sum(float(np.linalg.norm(j.origin.transform[:3, 3])) for j in path[1:])
    radius += sum(max(abs(j.limits.lower), abs(j.limits.upper)) for j in path if j.type == "prismatic")
    return first[:3, 3], radius + tool_offset


def unreachable_targets(spec, frame: str, n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """``(T (n, 4, 4), lower_bound (n,))``: positions at 1.1 × reach + 0.1 m from the first joint in
    random directions (identity orientation), and for each a lower bound [m] on the distance any
    configuration can come to it."""
    centre, radius = reach_bound(spec, frame)
    rng = np.random.default_rng(seed)
    d = rng.normal(size=(n, 3))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    dist = 1.1 * radius + 0.1
    targets = np.tile(np.eye(4), (n, 1, 1))
    targets[:, :3, 3] = centre + dist * d
    return targets, np.full(n, dist - radius)
