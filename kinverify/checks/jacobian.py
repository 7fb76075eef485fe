"""``jacobian.linear`` / ``jacobian.angular`` between backends (Frobenius norm of the 3×n
difference) and ``jacobian.fd``: a backend's Jacobian against finite differences of its own FK."""

from __future__ import annotations

import numpy as np

from ..backends.base import Backend, Evaluation, finite_difference_jacobians


def jacobian_errors(reference: Evaluation, other: Evaluation, rows: slice | None = None) -> dict[tuple[str, str], np.ndarray]:
    """Errors ``(N,)`` keyed by ``(property, frame)``; ``rows`` selects the configurations of the
    reference that ``other`` was evaluated on (default: all)."""
    if reference.jacobians is None or other.jacobians is None:
        return {}
    ref_jac = reference.jacobians if rows is None else reference.jacobians[rows]
    ref_index = {f: i for i, f in enumerate(reference.frames)}
    out = {}
    for j, frame in enumerate(other.frames):
        if frame not in ref_index:
            continue
        diff = ref_jac[:, ref_index[frame]] - other.jacobians[:, j]
        out[("jacobian.linear", frame)] = np.linalg.norm(diff[:, :3], axis=(-2, -1))
        out[("jacobian.angular", frame)] = np.linalg.norm(diff[:, 3:], axis=(-2, -1))
    return out


def finite_difference_errors(backend: Backend, q: np.ndarray, jacobians: np.ndarray) -> dict[tuple[str, str], np.ndarray]:
    """Errors ``(N,)`` of ``jacobians`` (the backend's own, at ``q``) against central differences
    of the same backend's FK."""
    fd = finite_difference_jacobians(backend.poses, q)
    diff = np.linalg.norm(jacobians - fd, axis=(-2, -1))  # (N, F)
    return {("jacobian.fd", frame): diff[:, f] for f, frame in enumerate(backend.frames)}
