"""Number formatting and geometry helpers shared by the generators."""

from __future__ import annotations

from xml.sax.saxutils import quoteattr

import numpy as np

from kinverify.model.transforms import matrix_to_rpy

PALETTE = ("0.2 0.2 0.2 1", "0.8 0.2 0.2 1", "0.2 0.2 0.8 1", "0.2 0.6 0.2 1", "0.8 0.6 0.1 1", "0.5 0.2 0.6 1")


def num(x: float) -> str:
    """Shortest text that round-trips the float exactly (so generated files lose no precision)."""
    return repr(float(x) + 0.0)  # + 0.0 turns -0.0 into 0.0


def nums(values) -> str:
    return " ".join(num(v) for v in values)


def attr(value: str) -> str:
    """A quoted, escaped XML attribute value."""
    return quoteattr(str(value))


def segment_placement(fromto) -> tuple[np.ndarray, np.ndarray, float]:
    """Centre, rpy aligning local z with the segment, and length of a ``fromto`` segment."""
    a, b = np.asarray(fromto[:3]), np.asarray(fromto[3:])
    d = b - a
    length = float(np.linalg.norm(d))
    z = d / length
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    rot = np.column_stack([x, np.cross(z, x), z])
    return (a + b) / 2, matrix_to_rpy(rot), length


def colour(index: int) -> str:
    return PALETTE[index % len(PALETTE)]
