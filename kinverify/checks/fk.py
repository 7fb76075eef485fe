"""``fk.position`` [m] and ``fk.rotation`` (geodesic angle, rad) between two evaluations."""

from __future__ import annotations

import numpy as np

from ..backends.base import Evaluation
from ..transforms import geodesic_distance


def fk_errors(reference: Evaluation, other: Evaluation, with_rotation: bool = True) -> dict[tuple[str, str], np.ndarray]:
    """Errors ``(N,)`` keyed by ``(property, frame)`` for the frames both evaluations report."""
    ref_index = {f: i for i, f in enumerate(reference.frames)}
    out = {}
    for j, frame in enumerate(other.frames):
        if frame not in ref_index:
            continue
        a, b = reference.poses[:, ref_index[frame]], other.poses[:, j]
        out[("fk.position", frame)] = np.linalg.norm(a[:, :3, 3] - b[:, :3, 3], axis=-1)
        if with_rotation:
            out[("fk.rotation", frame)] = geodesic_distance(a[:, :3, :3], b[:, :3, :3])
    return out
