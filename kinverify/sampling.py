"""Joint configurations to evaluate: uniform inside the limits plus edge configurations.

Everything is reproducible from ``seed`` (numpy ``default_rng``).
"""

from __future__ import annotations

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
    revolute = [j.type == "revolute" for j in spec.joints]
    return sample_configurations(spec.lower, spec.upper, revolute, n, seed, edges)
