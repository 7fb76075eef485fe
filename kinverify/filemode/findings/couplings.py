"""Couplings (URDF ``<mimic>``, MJCF ``<equality joint>``) that differ between the files, or
that one file lacks; an MJCF stating the coupling the other way round (leader from follower) is
turned round before comparing."""

from __future__ import annotations

from kinverify.filemode.findings.table import finding


def coupling_findings(u, m, matching) -> list:
    """Couplings (URDF <mimic>, MJCF <equality joint>) that differ, or that one file lacks."""
    out = []
    to_u = {b: a for a, b, _ in matching.joints}
    matched = set(to_u.values())  # a joint in one file only is said once, as an extra part
    mine = {c.follower: c for c in u.couplings if c.follower in matched and c.leader in matched}
    theirs = {}
    for c in m.couplings:
        f, lead = to_u.get(c.follower), to_u.get(c.leader)
        if f is None or lead is None:
            continue
        if f in mine and mine[f].leader == lead or lead not in mine:
            theirs[f] = (lead, c.multiplier, c.offset, c)
        else:  # the MJCF states it the other way round: leader = (follower − offset) / multiplier
            theirs[lead] = (f, 1 / c.multiplier, -c.offset / c.multiplier, c) if c.multiplier else (f, 0.0, 0.0, c)
    for f in sorted(set(mine) | set(theirs)):
        a, b = mine.get(f), theirs.get(f)
        if a is None or b is None:
            side = "URDF" if a is not None else "MJCF"
            lead = a.leader if a is not None else b[0]
            out.append(finding("coupling_one_file", f"joint {f} follows {lead} in the {side} only ({(a or b[3]).source}); the "
                               "other file leaves it free: compared as coupled", {"file": side, "leader": lead}, joint=f))
        elif a.leader != b[0] or abs(a.multiplier - b[1]) > 1e-9 or abs(a.offset - b[2]) > 1e-9:
            out.append(finding("coupling_difference", f"joint {f}: {f} = {a.multiplier:g}·{a.leader} + {a.offset:g} in the URDF, "
                               f"{b[1]:g}·{b[0]} + {b[2]:g} in the MJCF", {"urdf": [a.multiplier, a.offset],
                                                                          "mjcf": [b[1], b[2]]}, joint=f))
    return out
