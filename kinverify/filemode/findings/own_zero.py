"""Values each file writes in its own joint coordinates, and a zero offset between them.

A joint's zero offset (``q_mjcf = s·q_urdf + o``, fitted from the kinematics) moves everything a
file states in that joint's coordinates: a range, a coupling. When the MJCF writes the same
numbers as the URDF in its own coordinates (a frame turned about its joint's axis, or a slide's
frame moved along it, with the range left as written), those values sit ``o`` apart physically:
a consequence of the zero offset, said in its finding, not a second difference. What differs
beyond that is a difference of its own, of the size the offset does not explain.

:func:`bounds` compares a joint's range both ways; the limits suite reports the part the offset
does not explain, the zero offset finding the part it does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


def mapped_bounds(lower: float, upper: float, sign: int, offset: float) -> tuple[float, float]:
    """URDF bounds in the MJCF's coordinates (q_mjcf = sign · q + offset)."""
    lo, up = (lower, upper) if sign > 0 else (-upper, -lower)
    return lo + offset, up + offset


def bound_error(x: float | None, y: float | None) -> float | None:
    """How far apart two bounds are (``inf`` where one is unbounded and the other not)."""
    if x is None or y is None:
        return None
    if x == y:
        return 0.0
    return math.inf if not (math.isfinite(x) and math.isfinite(y)) else abs(x - y)


@dataclass(frozen=True)
class Bounds:
    """A joint's range compared: ``lower``/``upper`` the URDF's in the MJCF's coordinates (through
    the sign and the zero offset, up to the whole turn that fits), ``ends`` each bound's difference
    from the MJCF's and ``error`` the larger; ``written``: the two differences with the range read
    in each file's own zero (the sign carried, the offset not), None without an offset."""

    lower: float
    upper: float
    ends: tuple[float, float]
    written: tuple[float, float] | None

    @property
    def error(self) -> float:
        return max(self.ends)

    def offset_explains(self, tol: float) -> bool:
        """The ranges differ physically, and only by the zero offset: written alike in each file's own zero."""
        return self.error > tol and self.written is not None and max(self.written) <= tol

    def beyond_offset(self, tol: float) -> float:
        """The size of the difference the zero offset does not explain: of the two readings (the
        offset carried, or each file's own zero), the one where fewer ends differ (an end changed
        besides the offset: the other end agrees as written), else the smaller."""
        if self.written is None:
            return self.error
        return min((sum(e > tol for e in r), max(r)) for r in (self.ends, self.written))[1]


def bounds(lower: float, upper: float, m_lower: float, m_upper: float, sign: int, offset: float, revolute: bool) -> Bounds:
    """The URDF's range ``[lower, upper]`` against the MJCF's ``[m_lower, m_upper]`` through the
    joint's ``sign`` and zero ``offset`` (a revolute offset known up to whole turns: the one that fits)."""

    def ends(b: tuple[float, float]) -> tuple[float, float]:
        return bound_error(b[0], m_lower) or 0.0, bound_error(b[1], m_upper) or 0.0

    lo, up = mapped_bounds(lower, upper, sign, offset)
    if revolute and offset:
        lo, up = min(((lo + k, up + k) for k in (0.0, -2 * math.pi, 2 * math.pi)), key=lambda b: max(ends(b)))
    return Bounds(lo, up, ends((lo, up)), ends(mapped_bounds(lower, upper, sign, 0.0)) if offset else None)
