"""Couplings (URDF ``<mimic>``, MJCF ``<equality joint>``) that differ between the files, or that
one file lacks. Each file's couplings are resolved first (a coupling stated the other way round,
or through a chain of them, ties the same joints), then compared joint by joint in the URDF's
joint coordinates: the MJCF's ``q_f = k·q_l + c`` carried through each joint's sign and zero
offset (``q_mjcf = s·q_urdf + o``) reads ``q_f = (k·s_l/s_f)·q_l + (k·o_l + c − o_f)/s_f``."""

from __future__ import annotations

from kinverify.filemode.align.match import resolve_couplings
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.model import Coupling


# a coupling's offset carried through fitted zero offsets is known to the fit's precision only
FITTED_OFFSET_TOL = {"revolute": 1e-4, "prismatic": 1e-5}  # rad, m


def coupling_findings(u, m, matching, alignment=None) -> list:
    """Couplings (URDF <mimic>, MJCF <equality joint>) that differ, or that one file lacks, each
    joint compared as ``joint = k·root + c`` of the first joint of its group (chains followed), in
    the URDF's coordinates (``alignment``: the joint map; None: every sign +1, offset 0)."""
    out = []
    to_u = {b: a for a, b, _ in matching.joints}
    order = [a for a, _, _ in matching.joints]
    maps = {j.urdf: (j.sign, j.offset) for j in (alignment.joints if alignment is not None else [])}

    def in_urdf(c: Coupling) -> Coupling:
        f, lead = to_u[c.follower], to_u[c.leader]
        (sf, of), (sl, ol) = maps.get(f, (1, 0.0)), maps.get(lead, (1, 0.0))
        return Coupling(f, lead, c.multiplier * sl * sf, sf * (c.multiplier * ol + c.offset - of), c.source, c.nonlinear)

    stated = [c for c in u.couplings if c.follower in to_u.values() and c.leader in to_u.values()]
    followers = {c.follower for c in stated}
    mine = resolve_couplings(stated, order, followers)
    theirs = resolve_couplings([in_urdf(c) for c in m.couplings if c.follower in to_u and c.leader in to_u], order, followers)
    fitted = {a for a, (_, o) in maps.items() if o}
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
        elif abs(a.multiplier - b.multiplier) > 1e-9 or abs(a.offset - b.offset) > (
            FITTED_OFFSET_TOL[u.joint(f).type] if {f, a.leader} & fitted else 1e-9
        ):
            mapped = " (its coupling carried into the URDF's joint coordinates)" if {f, a.leader} & set(maps) - same else ""
            out.append(
                finding(
                    "coupling_difference",
                    f"joint {f}: {f} = {a.multiplier:g}·{a.leader} + {a.offset:g} in the URDF, "
                    f"{b.multiplier:g}·{b.leader} + {b.offset:.6g} in the MJCF{mapped}",
                    {"urdf": [a.multiplier, a.offset], "mjcf": [b.multiplier, b.offset]},
                    joint=f,
                )
            )
    return out
