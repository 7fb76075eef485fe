"""Values each file writes in its own joint coordinates, and a zero offset (or reversed axis) between them.

A joint's zero offset (``q_mjcf = s·q_urdf + o``, fitted from the kinematics) moves everything a
file states in that joint's coordinates: a range, a coupling. When the MJCF writes the same
numbers as the URDF in its own coordinates (a frame turned about its joint's axis, or a slide's
frame moved along it, with the range left as written), those values sit ``o`` apart physically:
a consequence of the zero offset, said in its finding, not a second difference. A reversed axis
(``s = −1``) with an asymmetric range left as written mirrors it physically: said likewise by the
``axis_sign_flip`` finding. What differs beyond that is a difference of its own, of the size the
joint map does not explain.

:func:`bounds` compares a joint's range both ways; the limits suite reports the part the offset
does not explain, :func:`zero_offset_finding` the part it does.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.model import ModelDesc
from kinverify.suites.base import Finding


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
    as each file writes it (the offset not carried; the sign carried or, on a reversed axis, not:
    the closer), None when the joint map is the identity."""

    lower: float
    upper: float
    ends: tuple[float, float]
    written: tuple[float, float] | None

    @property
    def error(self) -> float:
        return max(self.ends)

    def offset_explains(self, tol: float) -> bool:
        """The ranges differ physically, and only by the joint map (a zero offset, a reversed axis):
        written alike in each file's own coordinates."""
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
    # each file's own coordinates: the offset not carried (the sign carried, or neither when the axis is reversed)
    own = [ends(mapped_bounds(lower, upper, s, 0.0)) for s in {sign, 1} if offset or s != sign]
    return Bounds(lo, up, ends((lo, up)), min(own, key=max) if own else None)


def zero_offset_finding(
    u: ModelDesc, m: ModelDesc, j, frames: list[str], names: dict, limit_tol: float, coupled: dict
) -> Finding:
    """Joint ``j``'s zero offset; and what each file writes alike in its own zero, which the offset
    therefore sets apart physically (:mod:`kinverify.filemode.findings.own_zero`): its range (the
    limits check it fails is this finding's), the couplings of it or on it (``coupled``: follower ->
    leader, :func:`~kinverify.filemode.findings.couplings.written_alike`)."""
    unit = "rad" if j.type == "revolute" else "m"
    deg = f" ({math.degrees(j.offset):.4g}°)" if j.type == "revolute" else ""
    uj, mj = u.joint(j.urdf), m.joint(j.mjcf)
    b = bounds(uj.lower, uj.upper, mj.lower, mj.upper, j.sign, j.offset, j.type == "revolute")
    values: dict[str, Any] = {"offset": j.offset, "unit": unit, "moves": frames}
    also = []
    if b.offset_explains(limit_tol):
        values |= {"range_written_alike": True, "checks": [["limits.position", "joints"]]}
        also.append(
            f"its range [{mj.lower:.6g}, {mj.upper:.6g}] is written alike in each file's own zero, so it too sits "
            f"{b.error:.6g} {unit} apart physically"
        )
    ties = sorted(f for f, lead in coupled.items() if j.urdf in (f, lead))
    if ties:
        values["couplings_written_alike"] = ties
        also.append(
            " and ".join(f"{f} follows {coupled[f]}" for f in ties)
            + " as each file writes it in its own coordinates, so the offset carries into the coupling too"
        )
    return finding(
        "zero_offset",
        f"joint {j.urdf}/{j.mjcf}: zero offset of {j.offset:.6g} {unit}{deg}: at the same q "
        f"the MJCF's joint sits {j.offset:.6g} {unit} further (q_mjcf = {'−' if j.sign < 0 else ''}q_urdf "
        f"{'+' if j.offset >= 0 else '−'} {abs(j.offset):.6g})" + "".join(f"; {x}" for x in also),
        values,
        magnitude=abs(j.offset),
        unit=unit,
        **names,
    )


def sign_flip_finding(u: ModelDesc, m: ModelDesc, j, frames: list[str], names: dict, limit_tol: float) -> Finding:
    """Joint ``j``'s reversed axis; without a zero offset beside it (whose finding says the range
    then), an asymmetric range written alike in each file's own coordinates is mirrored by it
    physically: said here (the limits check it fails is this finding's), not as a second difference."""
    values: dict[str, Any] = {"sign": -1, "moves": frames}
    also = ""
    if not j.offset:
        uj, mj = u.joint(j.urdf), m.joint(j.mjcf)
        b = bounds(uj.lower, uj.upper, mj.lower, mj.upper, j.sign, 0.0, j.type == "revolute")
        if b.offset_explains(limit_tol):
            unit = "rad" if j.type == "revolute" else "m"
            values |= {"range_written_alike": True, "checks": [["limits.position", "joints"]]}
            also = (
                f"; its range [{mj.lower:.6g}, {mj.upper:.6g}] is written alike in each file's own coordinates, so the "
                f"reversed axis mirrors it: its ends sit {b.error:.6g} {unit} apart physically"
            )
    return finding(
        "axis_sign_flip",
        f"joint {j.urdf}/{j.mjcf}: the axis is reversed (the same q turns the other "
        "way): q_mjcf = −q_urdf" + (f" + {j.offset:.6g}" if j.offset else "") + also,
        values,
        magnitude=1,
        unit="",
        **names,
    )
