"""Couplings (URDF ``<mimic>``, MJCF ``<equality joint>``) that differ between the files, or that
one file lacks. Each file's couplings are resolved first (a coupling stated the other way round,
or through a chain of them, ties the same joints), then compared joint by joint."""

from __future__ import annotations

from kinverify.filemode.align.match import resolve_couplings
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.model import Coupling


def coupling_findings(u, m, matching) -> list:
    """Couplings (URDF <mimic>, MJCF <equality joint>) that differ, or that one file lacks, each
    joint compared as ``joint = k·root + c`` of the first joint of its group (chains followed)."""
    out = []
    to_u = {b: a for a, b, _ in matching.joints}
    order = [a for a, _, _ in matching.joints]
    mine = resolve_couplings([c for c in u.couplings if c.follower in to_u.values() and c.leader in to_u.values()], order)
    theirs = resolve_couplings([Coupling(to_u[c.follower], to_u[c.leader], c.multiplier, c.offset, c.source, c.nonlinear)
                                for c in m.couplings if c.follower in to_u and c.leader in to_u], order)
    for f in sorted(set(mine) | set(theirs), key=order.index):
        a, b = mine.get(f), theirs.get(f)
        if a is None or b is None or a.leader != b.leader:
            if a is not None and b is not None:  # both couple it, to different joints
                out.append(finding("coupling_difference", f"joint {f}: {f} = {a.multiplier:g}·{a.leader} + {a.offset:g} in the "
                                   f"URDF, {b.multiplier:g}·{b.leader} + {b.offset:g} in the MJCF",
                                   {"urdf": [a.multiplier, a.offset], "mjcf": [b.multiplier, b.offset]}, joint=f))
                continue
            c, side = (a, "URDF") if a is not None else (b, "MJCF")
            out.append(finding("coupling_one_file", f"joint {f} follows {c.leader} in the {side} only ({c.source}); the "
                               "other file leaves it free: compared as coupled", {"file": side, "leader": c.leader}, joint=f))
        elif abs(a.multiplier - b.multiplier) > 1e-9 or abs(a.offset - b.offset) > 1e-9:
            out.append(finding("coupling_difference", f"joint {f}: {f} = {a.multiplier:g}·{a.leader} + {a.offset:g} in the URDF, "
                               f"{b.multiplier:g}·{b.leader} + {b.offset:g} in the MJCF", {"urdf": [a.multiplier, a.offset],
                                                                                          "mjcf": [b.multiplier, b.offset]},
                               joint=f))
    return out
