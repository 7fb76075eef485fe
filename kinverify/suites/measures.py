"""Error measures between two backend evaluations, per (property, frame), shape ``(N,)``:

- ``fk.position`` [m] and ``fk.rotation`` (geodesic angle, rad);
- ``jacobian.linear`` / ``jacobian.angular`` (Frobenius norm of the 3×n difference);
- ``jacobian.fd``: a backend's Jacobian against finite differences of its own FK.
"""

from __future__ import annotations

import numpy as np

from kinverify.backends.base import FD_STEP, Backend, Evaluation, finite_difference_jacobians
from kinverify.model.transforms import geodesic_distance


def fk_errors(reference: Evaluation, other: Evaluation, with_rotation: bool = True) -> dict[tuple[str, str], np.ndarray]:
    """Errors ``(N,)`` keyed by ``(property, frame)`` for the frames both evaluations report."""
    ref_index = {f: i for i, f in enumerate(reference.frames)}
    pairs = [(j, ref_index[f]) for j, f in enumerate(other.frames) if f in ref_index]
    if not pairs:
        return {}
    # All matched frames at once: one gather and one vectorised measure per property.
    mine, ref = [j for j, _ in pairs], [i for _, i in pairs]
    a = reference.poses[:, ref] if ref != list(range(reference.poses.shape[1])) else reference.poses
    b = other.poses[:, mine] if mine != list(range(other.poses.shape[1])) else other.poses
    d = a[..., :3, 3] - b[..., :3, 3]
    pos = np.sqrt(np.einsum("nfi,nfi->nf", d, d))
    rot = geodesic_distance(a[..., :3, :3], b[..., :3, :3]) if with_rotation else None
    out = {}
    for k, j in enumerate(mine):
        frame = other.frames[j]
        out[("fk.position", frame)] = pos[:, k]
        if rot is not None:  # with_rotation
            out[("fk.rotation", frame)] = rot[:, k]
    return out


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
    # All matched frames at once.
    mine, ref = [j for j, _ in pairs], [i for _, i in pairs]
    a = ref_jac if ref == list(range(ref_jac.shape[1])) else ref_jac[:, ref]
    b = other.jacobians if mine == list(range(other.jacobians.shape[1])) else other.jacobians[:, mine]
    diff = a - b  # (N, F, 6, n)
    squares = np.square(diff, out=diff).sum(axis=-1)  # (N, F, 6)
    lin = np.sqrt(squares[..., :3].sum(axis=-1))
    ang = np.sqrt(squares[..., 3:].sum(axis=-1))
    out = {}
    for k, j in enumerate(mine):
        frame = other.frames[j]
        out[("jacobian.linear", frame)] = lin[:, k]
        out[("jacobian.angular", frame)] = ang[:, k]
    return out


def finite_difference_errors(backend: Backend, q: np.ndarray, jacobians: np.ndarray) -> dict[tuple[str, str], np.ndarray]:
    """Errors ``(N,)`` of ``jacobians`` (the backend's own, at ``q``) against central differences
    of the same backend's FK."""
    fd = finite_difference_jacobians(backend.poses, q, getattr(backend, "fd_step", FD_STEP))
    diff = np.linalg.norm(jacobians - fd, axis=(-2, -1))  # (N, F)
    return {("jacobian.fd", frame): diff[:, f] for f, frame in enumerate(backend.frames)}
