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
  Memory: one int64 counter per bin between the smallest and the largest positive error seen,
  independent of the count: errors spanning 20 decades take ~17,000 bins (136 kB).
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
PERCENTILE_METHOD = (
    f"log-binned streaming histogram, {BINS_PER_OCTAVE} bins per factor 2; "
    f"relative error <= {PERCENTILE_RTOL:.2e} vs numpy's linear percentile"
)


class ErrorStats:
    """Accumulate non-negative errors ``(N,)`` with their configurations ``(N, n)``."""

    def __init__(self) -> None:
        self.count = 0
        self.max_error = 0.0
        self.worst_q: np.ndarray | None = None
        self.histogram = np.zeros(len(HIST_EDGES) - 1, dtype=np.int64)
        self._lo = 0  # fine log2 bin of self._bins[0]
        self._bins = np.zeros(0, dtype=np.int64)  # counts of positive finite errors per fine bin
        self._zeros = 0
        self._infs = 0

    def update(self, errors: np.ndarray, q: np.ndarray) -> None:
        errors = np.asarray(errors, dtype=float).ravel()
        n = errors.size
        if n == 0:
            return
        top = errors.max()  # NaN if any is NaN
        if not np.isfinite(top):
            errors = np.where(np.isnan(errors), np.inf, errors)  # NaN counts as the worst possible error
            top = np.inf
        if self.worst_q is None or top > self.max_error:
            self.max_error = float(top)
            self.worst_q = np.array(q[int(np.argmax(errors))], dtype=float)
        self.count += n
        finite = errors if top < np.inf else errors[np.isfinite(errors)]
        positive = finite[finite > 0]
        infs, zeros = n - finite.size, finite.size - positive.size
        self._infs += infs
        self._zeros += zeros
        self.histogram[0] += zeros
        self.histogram[-1] += infs
        if positive.size:
            # Coarse bin by index arithmetic (no sort): floor(4·(log10 x + 18)), clipped to the range.
            coarse = np.floor((np.log10(positive) + 18.0) * 4.0)
            np.clip(coarse, 0, len(self.histogram) - 1, out=coarse)
            self.histogram += np.bincount(coarse.astype(np.int64), minlength=len(self.histogram))
            idx = np.floor(np.log2(positive) * BINS_PER_OCTAVE).astype(np.int64)
            lo = int(idx.min())
            self._add_bins(lo, np.bincount(idx - lo))

    def _add_bins(self, lo: int, counts: np.ndarray) -> None:
        if self._bins.size == 0:
            self._lo, self._bins = lo, counts.astype(np.int64, copy=True)
            return
        new_lo = min(lo, self._lo)
        new_hi = max(lo + counts.size, self._lo + self._bins.size)
        if new_lo != self._lo or new_hi != self._lo + self._bins.size:
            grown = np.zeros(new_hi - new_lo, dtype=np.int64)
            grown[self._lo - new_lo : self._lo - new_lo + self._bins.size] = self._bins
            self._lo, self._bins = new_lo, grown
        self._bins[lo - self._lo : lo - self._lo + counts.size] += counts

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
        if other._bins.size:
            self._add_bins(other._lo, other._bins)
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
        cum = np.cumsum(self._bins)
        if cum.size == 0 or rank >= cum[-1]:
            return math.inf
        b = self._lo + int(np.searchsorted(cum, rank, side="right"))
        return 2.0 ** ((b + 0.5) / BINS_PER_OCTAVE)
