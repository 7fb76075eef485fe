"""Error statistics accumulated chunk by chunk.

Max and the worst configuration are exact. The 99th percentile is exact (numpy's "linear"
method over every error seen), and a log-spaced histogram (decades 1e-18 ... 1e2, four bins per
decade) is kept for the report's distribution plots.
"""

from __future__ import annotations

import numpy as np

HIST_EDGES = np.logspace(-18, 2, 81)  # errors below 1e-18 (incl. exact 0) go in the first bin


class ErrorStats:
    """Accumulate non-negative errors ``(N,)`` with their configurations ``(N, n)``."""

    def __init__(self) -> None:
        self.count = 0
        self.max_error = 0.0
        self.worst_q: np.ndarray | None = None
        self._chunks: list[np.ndarray] = []
        self.histogram = np.zeros(len(HIST_EDGES) - 1, dtype=np.int64)

    def update(self, errors: np.ndarray, q: np.ndarray) -> None:
        errors = np.asarray(errors, dtype=float)
        if errors.size == 0:
            return
        bad = ~np.isfinite(errors)
        errors = np.where(bad, np.inf, errors)  # NaN counts as the worst possible error
        k = int(np.argmax(errors))
        if self.worst_q is None or errors[k] > self.max_error:
            self.max_error = float(errors[k])
            self.worst_q = np.array(q[k], dtype=float)
        self.count += errors.size
        self._chunks.append(errors)
        clipped = np.clip(errors, HIST_EDGES[0], HIST_EDGES[-1] * 0.999)
        self.histogram += np.histogram(clipped, bins=HIST_EDGES)[0]

    def percentile(self, p: float) -> float:
        if not self._chunks:
            return 0.0
        return float(np.percentile(np.concatenate(self._chunks), p))
