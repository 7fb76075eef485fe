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
    pairs = [(j, ref_index[f]) for j, f in enumerate(other.frames) if f in ref_index]
    if not pairs:
        return {}
    # All matched frames at once (issue 8).
    mine, ref = [j for j, _ in pairs], [i for _, i in pairs]
    a = ref_jac if ref == list(range(ref_jac.shape[1])) else ref_jac[:, ref]
    b = other.jacobians if mine == list(range(other.jacobians.shape[1])) else other.jacobians[:, mine]
    diff = a - b  # (N, F, 6, n)
    rows = np.square(diff, out=diff).sum(axis=-1)  # (N, F, 6)
    lin = np.sqrt(rows[..., :3].sum(axis=-1))
    ang = np.sqrt(rows[..., 3:].sum(axis=-1))
    out = {}
    for k, j in enumerate(mine):
        frame = other.frames[j]
        out[("jacobian.linear", frame)] = lin[:, k]
        out[("jacobian.angular", frame)] = ang[:, k]
    return out


def finite_difference_errors(backend: Backend, q: np.ndarray, jacobians: np.ndarray) -> dict[tuple[str, str], np.ndarray]:
    """Errors ``(N,)`` of ``jacobians`` (the backend's own, at ``q``) against central differences
    of the same backend's FK."""
    fd = finite_difference_jacobians(backend.poses, q)
    diff = np.linalg.norm(jacobians - fd, axis=(-2, -1))  # (N, F)
    return {("jacobian.fd", frame): diff[:, f] for f, frame in enumerate(backend.frames)}
