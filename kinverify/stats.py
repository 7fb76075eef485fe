"""Error statistics streamed chunk by chunk, in memory that does not grow with the sample count.

- ``count``, ``max_error`` and ``worst_q`` (the configuration of the largest error) are exact.
- Percentiles come from a sparse log-binned histogram: a positive error ``x`` goes into bin
  ``floor(log2(x) * BINS_PER_OCTAVE)``; exact zeros and non-finite errors (NaN counts as ``inf``,
  the worst possible error) are counted apart and returned exactly. A percentile is computed as
  numpy's default ("linear") method does, interpolating between the two order statistics around
  rank ``p/100 · (count − 1)``, but with each order statistic replaced by the geometric middle of
  its bin. Each replacement is within a factor ``2**(1/(2·BINS_PER_OCTAVE))`` of the true order
  statistic, so (errors being non-negative) the result satisfies

      |percentile(p) − numpy.percentile(errors, p)| ≤ PERCENTILE_RTOL · numpy.percentile(errors, p)

  with ``PERCENTILE_RTOL = 2**(1/512) − 1 ≈ 1.36e-3`` (plus float rounding of ``log2``, ~1e-15;
  subnormal errors, below 2.2e-308, only to within that absolute amount).
  Memory: one counter per occupied bin; errors spanning 40 decades occupy at most ~34,000 bins
  (~1 MB), typically a few hundred.
- ``histogram``: the coarse log histogram (decades 1e-18 ... 1e2, four bins per decade) that the
  report's distribution plots use.

Merging (:meth:`ErrorStats.merge`) adds counts and bins, so ``count``, ``max_error``, the
histograms and every percentile are independent of merge order; ``worst_q`` is too, except on
an exact tie of the maximum, where the stats merged first win (the pipeline merges in chunk
order, which reproduces a single sequential pass exactly).
"""

from __future__ import annotations

import math

import numpy as np

HIST_EDGES = np.logspace(-18, 2, 81)  # errors below 1e-18 (incl. exact 0) go in the first bin
BINS_PER_OCTAVE = 256
PERCENTILE_RTOL = 2.0 ** (1.0 / (2 * BINS_PER_OCTAVE)) - 1.0
PERCENTILE_METHOD = (f"log-binned streaming histogram, {BINS_PER_OCTAVE} bins per factor 2; "
                     f"relative error <= {PERCENTILE_RTOL:.2e} vs numpy's linear percentile")


class ErrorStats:
    """Accumulate non-negative errors ``(N,)`` with their configurations ``(N, n)``."""

    def __init__(self) -> None:
        self.count = 0
        self.max_error = 0.0
        self.worst_q: np.ndarray | None = None
        self.histogram = np.zeros(len(HIST_EDGES) - 1, dtype=np.int64)
        self._bins: dict[int, int] = {}  # fine log2 bin -> count (positive finite errors)
        self._zeros = 0
        self._infs = 0

    def update(self, errors: np.ndarray, q: np.ndarray) -> None:
        errors = np.asarray(errors, dtype=float).ravel()
        if errors.size == 0:
            return
        errors = np.where(np.isnan(errors), np.inf, errors)  # NaN counts as the worst possible error
        k = int(np.argmax(errors))
        if self.worst_q is None or errors[k] > self.max_error:
            self.max_error = float(errors[k])
            self.worst_q = np.array(q[k], dtype=float)
        self.count += errors.size
        # Coarse bin by index arithmetic (no sort): floor(4·(log10 x + 18)), clipped to the range.
        with np.errstate(divide="ignore"):
            coarse = np.floor((np.log10(errors) + 18.0) * 4.0)
        coarse = np.clip(np.nan_to_num(coarse, nan=0.0, neginf=0.0), 0, len(self.histogram) - 1).astype(np.int64)
        self.histogram += np.bincount(coarse, minlength=len(self.histogram))
        finite = np.isfinite(errors)
        positive = errors[finite & (errors > 0)]
        self._zeros += int(np.count_nonzero(errors[finite] <= 0))
        self._infs += int(errors.size - np.count_nonzero(finite))
        if positive.size:
            idx = np.floor(np.log2(positive) * BINS_PER_OCTAVE).astype(np.int64)
            lo = int(idx.min())
            counts = np.bincount(idx - lo)
            bins = self._bins
            for i in np.flatnonzero(counts).tolist():
                bins[lo + i] = bins.get(lo + i, 0) + int(counts[i])

    def merge(self, other: "ErrorStats") -> "ErrorStats":
        """Add ``other``'s errors to these (in place); returns ``self``."""
        if other.count == 0:
            return self
        if self.worst_q is None or other.max_error > self.max_error:
            self.max_error, self.worst_q = other.max_error, other.worst_q
        self.count += other.count
        self.histogram = self.histogram + other.histogram
        self._zeros += other._zeros
        self._infs += other._infs
        for b, c in other._bins.items():
            self._bins[b] = self._bins.get(b, 0) + c
        return self

    def percentile(self, p: float) -> float:
        """The ``p``-th percentile (0..100) to within ``PERCENTILE_RTOL`` (see module doc)."""
        if self.count == 0:
            return 0.0
        h = (self.count - 1) * p / 100.0
        lo, hi = math.floor(h), math.ceil(h)
        # Clamping to the exact max keeps the bound (every order statistic is <= the max).
        a = min(self._order_statistic(lo), self.max_error)
        b = min(self._order_statistic(hi), self.max_error)
        if a == b:
            return a
        return a + (b - a) * (h - lo)

    def _order_statistic(self, rank: int) -> float:
        """Estimate of the ``rank``-th smallest error (0-based)."""
        if rank < self._zeros:
            return 0.0
        rank -= self._zeros
        for b in sorted(self._bins):
            rank -= self._bins[b]
            if rank < 0:
                return 2.0 ** ((b + 0.5) / BINS_PER_OCTAVE)
        return math.inf
