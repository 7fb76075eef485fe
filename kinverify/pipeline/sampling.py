"""Joint configurations to evaluate: uniform inside the limits plus edge configurations.

Everything is reproducible from ``seed`` (numpy ``default_rng``).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import cast

import numpy as np

HALF_PI = np.pi / 2


def _home(lower: np.ndarray, upper: np.ndarray) -> np.ndarray:
    """Zero where zero lies inside the limits, else the middle of the range."""
    inside = (lower <= 0) & (0 <= upper)
    return np.where(inside, 0.0, (lower + upper) / 2)


def edge_configurations(lower, upper, revolute) -> np.ndarray:
    """Edge cases ``(M, n)``: the home pose; each joint at each limit, at zero and at ±π/2
    (where inside its limits) with the others at home; and all joints together at each limit,
    at zero and at ±π/2 (clipped into the limits). Duplicates removed, order kept."""
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    revolute = np.asarray(revolute, bool)
    home = _home(lower, upper)
    rows = [home]
    for j in range(len(lower)):
        values = [lower[j], upper[j], 0.0] + ([HALF_PI, -HALF_PI] if revolute[j] else [])
        for v in values:
            if lower[j] <= v <= upper[j]:
                q = home.copy()
                q[j] = v
                rows.append(q)
    rows += [lower, upper]
    for v in (0.0, HALF_PI, -HALF_PI):
        rows.append(np.clip(np.where(revolute, v, home), lower, upper))
    out, seen = [], set()
    for q in rows:
        key = tuple(np.round(q, 15))
        if key not in seen:
            seen.add(key)
            out.append(q)
    return np.array(out)


def uniform_configurations(lower, upper, n: int, seed: int = 0) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return rng.uniform(lower, upper, size=(n, len(lower)))


def sample_configurations(lower, upper, revolute, n: int, seed: int = 0, edges: bool = True) -> np.ndarray:
    """``n`` uniform configurations, preceded by the edge configurations when ``edges``."""
    uniform = uniform_configurations(lower, upper, n, seed)
    if not edges:
        return uniform
    return np.concatenate([edge_configurations(lower, upper, revolute), uniform])


def spec_samples(spec, n: int, seed: int = 0, edges: bool = True) -> np.ndarray:
    """Configurations of every coordinate of ``spec`` (a floating base's six first)."""
    lower, upper = spec.coordinate_limits
    return sample_configurations(lower, upper, spec.coordinate_revolute, n, seed, edges)


class Samples:
    """The configurations of :func:`sample_configurations` without holding them: edge rows, then
    ``n`` uniform rows, any row range generated on demand (the uniform stream is skipped ahead with
    ``PCG64.advance``, one 64-bit draw per value), identical to slicing the full array.

    Array-like for suites that want an array: ``len``, ``shape``, ``samples[a:b]``, ``samples[i]``
    and ``np.asarray(samples)`` (which materialises all rows). Picklable, so worker processes
    generate their own chunks.
    """

    def __init__(self, lower, upper, revolute, n: int, seed: int = 0, edges: bool = True) -> None:
        self.lower, self.upper = np.asarray(lower, float), np.asarray(upper, float)
        self.n_uniform, self.seed = int(n), seed
        self.edges = edge_configurations(lower, upper, revolute) if edges else np.empty((0, len(self.lower)))
        self.shape = (len(self.edges) + self.n_uniform, len(self.lower))
        self.ndim, self.dtype = 2, np.dtype(float)

    def __len__(self) -> int:
        return self.shape[0]

    def rows(self, start: int, stop: int) -> np.ndarray:
        """Rows ``start:stop`` ``(stop - start, n)``."""
        start, stop = max(0, start), min(stop, len(self))
        if stop <= start:
            return np.empty((0, self.shape[1]))
        n_edge = len(self.edges)
        parts = [self.edges[start:stop]] if start < n_edge else []
        u0, u1 = max(start - n_edge, 0), stop - n_edge
        if u1 > u0:
            rng = np.random.default_rng(self.seed)
            cast(np.random.PCG64, rng.bit_generator).advance(u0 * self.shape[1])  # default_rng's generator
            parts.append(rng.uniform(self.lower, self.upper, size=(u1 - u0, self.shape[1])))
        return parts[0] if len(parts) == 1 else np.concatenate(parts)

    def chunks(self, size: int) -> "ChunkRanges":
        """``(start, stop)`` of consecutive chunks of at most ``size`` rows (a lazy sequence)."""
        return ChunkRanges(len(self), size)

    def __getitem__(self, key):
        if isinstance(key, slice):
            start, stop, step = key.indices(len(self))
            return self.rows(start, stop)[::step] if step > 0 else np.asarray(self)[key]
        if isinstance(key, (int, np.integer)):
            k = int(key) + (len(self) if key < 0 else 0)
            if not 0 <= k < len(self):
                raise IndexError(key)
            return self.rows(k, k + 1)[0]
        return np.asarray(self)[key]

    def __array__(self, dtype=None, copy=None):
        out = self.rows(0, len(self))
        return out if dtype is None else out.astype(dtype)


class ChunkRanges(Sequence):
    """``(start, stop)`` of the consecutive chunks of at most ``size`` rows out of ``n``: a sequence
    computed on demand, so its memory does not grow with ``n`` (10⁹ samples are 5·10⁵ chunks)."""

    def __init__(self, n: int, size: int) -> None:
        self.n, self.size = max(0, int(n)), max(1, int(size))

    def __len__(self) -> int:
        return -(-self.n // self.size)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(len(self)))]
        k = i + len(self) if i < 0 else i
        if not 0 <= k < len(self):
            raise IndexError(i)
        start = k * self.size
        return start, min(start + self.size, self.n)
