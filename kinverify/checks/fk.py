"""``fk.position`` [m] and ``fk.rotation`` (geodesic angle, rad) between two evaluations."""

from __future__ import annotations

import numpy as np

from ..backends.base import Evaluation
from ..transforms import geodesic_distance


def fk_errors(reference: Evaluation, other: Evaluation, with_rotation: bool = True) -> dict[tuple[str, str], np.ndarray]:
    """Errors ``(N,)`` keyed by ``(property, frame)`` for the frames both evaluations report."""
    ref_index = {f: i for i, f in enumerate(reference.frames)}
    pairs = [(j, ref_index[f]) for j, f in enumerate(other.frames) if f in ref_index]
    if not pairs:
        return {}
    # All matched frames at once (issue 8): one gather and one vectorised measure per property.
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
        if with_rotation:
            out[("fk.rotation", frame)] = rot[:, k]
    return out
