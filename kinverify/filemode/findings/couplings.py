"""Couplings (URDF ``<mimic>``, MJCF ``<equality joint>``) that differ between the files, or that
one file lacks. Each file's couplings are resolved first (a coupling stated the other way round,
or through a chain of them, ties the same joints), then compared joint by joint in the URDF's
joint coordinates: the MJCF's ``q_f = k·q_l + c`` carried through each joint's sign and zero
offset (``q_mjcf = s·q_urdf + o``) reads ``q_f = (k·s_l/s_f)·q_l + (k·o_l + c − o_f)/s_f``.

A coupling each file writes alike in its own coordinates (a leader's frame moved along or turned
about its axis, the ``<equality joint>`` left as written) differs in the URDF's coordinates only
by the zero offsets: that is said by the zero offset finding (:func:`written_alike`), not as a
coupling difference. A coupling that differs beyond that is a difference of the size the offsets
do not explain: how far apart the follower sits over the leader's range."""

from __future__ import annotations

import math

from kinverify.filemode.align.match import resolve_couplings
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.model import Coupling

# a coupling's offset carried through fitted zero offsets is known to the fit's precision only
FITTED_OFFSET_TOL = {"revolute": 1e-4, "prismatic": 1e-5}  # rad, m


def _compared(u, m, matching, alignment=None):
    """Each coupled joint's ``joint = k·root + c`` as the URDF states it, as the MJCF's reads in the
    URDF's coordinates (through each joint's sign and zero offset), and as it reads with the signs
    carried but not the offsets (each file's own zero); and the joint order."""
    to_u = {b: a for a, b, _ in matching.joints}
    order = [a for a, _, _ in matching.joints]
    maps = {j.urdf: (j.sign, j.offset) for j in (alignment.joints if alignment is not None else [])}

    def in_urdf(c: Coupling, offsets: bool) -> Coupling:
        f, lead = to_u[c.follower], to_u[c.leader]
        (sf, of), (sl, ol) = maps.get(f, (1, 0.0)), maps.get(lead, (1, 0.0))
        of, ol = (of, ol) if offsets else (0.0, 0.0)
        return Coupling(f, lead, c.multiplier * sl * sf, sf * (c.multiplier * ol + c.offset - of), c.source, c.nonlinear)

    stated = [c for c in u.couplings if c.follower in to_u.values() and c.leader in to_u.values()]
    followers = {c.follower for c in stated}
    own = [c for c in m.couplings if c.follower in to_u and c.leader in to_u]
    mine = resolve_couplings(stated, order, followers)
    theirs, written = (resolve_couplings([in_urdf(c, carry) for c in own], order, followers) for carry in (True, False))
    return mine, theirs, written, order, maps


def _apart(a: Coupling, b: Coupling, u) -> float:
    """How far apart the follower sits under two couplings to one leader, over the leader's range
    in the URDF (rad or m; a multiplier that differs on an unlimited leader: ``inf``)."""
    dk, dc = b.multiplier - a.multiplier, b.offset - a.offset
    if abs(dk) <= 1e-9:
        return abs(dc)
    lead = u.joint(a.leader)
    ends = [lead.lower, lead.upper]
    if not all(math.isfinite(x) for x in ends):
        return math.inf
    return max(abs(dk * x + dc) for x in ends)


def _alike(a: Coupling | None, b: Coupling | None, tol: float = 1e-9) -> bool:
    return (
        a is not None
        and b is not None
        and a.leader == b.leader
        and abs(a.multiplier - b.multiplier) <= 1e-9
        and abs(a.offset - b.offset) <= tol
    )


def written_alike(u, m, matching, alignment) -> dict[str, str]:
    """Coupled joints (URDF names) whose coupling each file writes alike in its own coordinates
    while the zero offsets of it or its leader set them apart in the URDF's: follower -> leader."""
    mine, theirs, written, _, maps = _compared(u, m, matching, alignment)
    fitted = {a for a, (_, o) in maps.items() if o}
    return {f: a.leader for f, a in mine.items() if _folded(u, f, a, theirs.get(f), written.get(f), fitted)}


def _folded(u, f: str, a: Coupling, b: Coupling | None, w: Coupling | None, fitted: set) -> bool:
    """Follower ``f``'s coupling ``a`` (the URDF's) differs from ``b`` (the MJCF's in the URDF's
    coordinates) only through a zero offset of it or its leader: written alike (``w``) in each file's own."""
    return bool({f, a.leader} & fitted) and not _alike(a, b, FITTED_OFFSET_TOL[u.joint(f).type]) and _alike(a, w)


def coupling_findings(u, m, matching, alignment=None) -> list:
    """Couplings (URDF <mimic>, MJCF <equality joint>) that differ, or that one file lacks, each
    joint compared as ``joint = k·root + c`` of the first joint of its group (chains followed), in
    the URDF's coordinates (``alignment``: the joint map; None: every sign +1, offset 0); those the
    zero offsets alone set apart (:func:`written_alike`) are the zero offset finding's to say."""
    out = []
    mine, theirs, written, order, maps = _compared(u, m, matching, alignment)
    fitted = {a for a, (_, o) in maps.items() if o}
    folded = {f for f, a in mine.items() if _folded(u, f, a, theirs.get(f), written.get(f), fitted)}
    same = {a for a, (sg, o) in maps.items() if sg == 1 and not o}
    for f in sorted(set(mine) | set(theirs), key=order.index):
        a, b = mine.get(f), theirs.get(f)
        if a is None or b is None or a.leader != b.leader:
            if a is not None and b is not None:  # both couple it, to different joints
                out.append(
                    finding(
                        "coupling_difference",
                        f"joint {f}: {f} = {a.multiplier:g}·{a.leader} + {a.offset:g} in the "
                        f"URDF, {b.multiplier:g}·{b.leader} + {b.offset:g} in the MJCF",
                        {"urdf": [a.multiplier, a.offset], "mjcf": [b.multiplier, b.offset]},
                        joint=f,
                    )
                )
                continue
            c, side = (a, "URDF") if a is not None else (b, "MJCF")
            assert c is not None  # one of the two couples it
            out.append(
                finding(
                    "coupling_one_file",
                    f"joint {f} follows {c.leader} in the {side} only ({c.source}); the "
                    "other file leaves it free: compared as coupled",
                    {"file": side, "leader": c.leader},
                    joint=f,
                )
            )
        elif f not in folded and not _alike(a, b, FITTED_OFFSET_TOL[u.joint(f).type] if {f, a.leader} & fitted else 1e-9):
            mapped = " (its coupling carried into the URDF's joint coordinates)" if {f, a.leader} & set(maps) - same else ""
            size, w = _apart(a, b, u), written.get(f)
            if w is not None and w.leader == a.leader and {f, a.leader} & fitted and _apart(a, w, u) < size:
                size = _apart(a, w, u)  # each file's coupling read in its own zero: what the offsets do not explain
                mapped = (
                    f"; {size:.4g} {_unit(u, f)} apart beyond the zero offsets (read in each file's own zero: "
                    f"{w.multiplier:g}·{w.leader} + {w.offset:.6g})"
                )
            out.append(
                finding(
                    "coupling_difference",
                    f"joint {f}: {f} = {a.multiplier:g}·{a.leader} + {a.offset:g} in the URDF, "
                    f"{b.multiplier:g}·{b.leader} + {b.offset:.6g} in the MJCF{mapped}",
                    {"urdf": [a.multiplier, a.offset], "mjcf": [b.multiplier, b.offset]},
                    magnitude=size,
                    unit=_unit(u, f),
                    joint=f,
                )
            )
    return out


def _unit(u, joint: str) -> str:
    return "m" if u.joint(joint).type == "prismatic" else "rad"
