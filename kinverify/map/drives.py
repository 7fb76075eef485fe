"""Which joints are driven and which follow another, compared between the sides (see
:mod:`kinverify.map.compare` for the findings' meaning).

A side drives a joint *directly* when one of its actuators acts on that joint alone (an MJCF
joint transmission, a URDF ``<transmission>`` naming one joint, a Drake joint actuator, a USD
joint's drive, an actuator table's group). A tendon through a leader and its follower drives the pair together and
fights nothing; a direct drive on a follower fights the coupling (Isaac Lab's mimic-joint
reports). A side without couplings of its own (an actuator table, an SDFormat file) is checked
against the couplings the files state."""

from __future__ import annotations

from kinverify.map.compare import listed, map_finding
from kinverify.map.rows import Rows
from kinverify.map.side import Follows, value

COUPLED_FORMATS = ("urdf", "mjcf", "usd")
RTOL = 1e-6


def direct(rows: Rows, s: int) -> set[int]:
    """Rows side ``s`` drives directly."""
    side = rows.sides[s]
    if side.format in ("table", "usd"):  # a group's joints; a USD drive (or MjcActuator) acts on its joint alone
        return {r for r in range(len(rows.names)) if (j := rows.joint(r, s)) is not None and j.driven}
    return {r for act in side.actuators or [] if act.direct for n in act.joints if (r := rows.row_of(s, n)) is not None}


def couplings(rows: Rows, s: int) -> dict[int, tuple[int | None, Follows]]:
    """Row of each follower side ``s`` states -> (row of its leader, the coupling)."""
    out = {}
    for r in range(len(rows.names)):
        j = rows.joint(r, s)
        if j is not None and j.follows is not None:
            out[r] = (rows.row_of(s, j.follows.leader), j.follows)
    return out


def drive_findings(rows: Rows) -> list:
    out, followers_driven = [], set()
    stated = {s: couplings(rows, s) for s, side in enumerate(rows.sides) if side.format in COUPLED_FORMATS}
    every: dict[int, tuple[int | None, Follows]] = {}
    stater: dict[int, int] = {}
    # each coupling as the first file that states it says it, and that file
    for s, found in stated.items():
        for r, c in found.items():
            every.setdefault(r, c)
            stater.setdefault(r, s)
    for s, side in enumerate(rows.sides):
        own = stated.get(s, every if side.format not in COUPLED_FORMATS else {})
        driven = sorted(r for r in direct(rows, s) if r in own)
        if driven:
            followers_driven |= set(driven)
            names = [rows.label(r) for r in driven]
            leaders = {rows.label(r): (own[r][1].leader, own[r][1].source) for r in driven}
            whose = "" if s in stated else f" ({', '.join(sorted({rows.sides[stater[r]].label for r in driven}))} couples them)"
            stiff = [
                (j.stiffness, value("stiffness").unit(j.type))
                for r in driven
                if (j := rows.joint(r, s)) is not None and j.stiffness
            ]
            size, unit = max(stiff) if stiff else (len(driven), "joints")
            out.append(
                map_finding(
                    "driven_follower",
                    "error",
                    f"{side.label} drives {len(driven)} joint(s) that follow another "
                    f"through an actuator of their own{whose}: "
                    + "; ".join(f"{n} follows {lead} ({src})" for n, (lead, src) in leaders.items())
                    + "; the drive fights the coupling",
                    names,
                    {"file": side.label, "leaders": leaders},
                    size,
                    unit,
                    "driven",
                )
            )
    out += _drive_differences(rows, followers_driven)
    out += _coupling_differences(rows, stated)
    return out


def _drive_differences(rows: Rows, skip: set[int]) -> list:
    out: list = []
    groups: dict[tuple, list] = {}
    for r in range(len(rows.names)):
        if r in skip:
            continue
        says = [(s, j.driven) for s in range(len(rows.sides)) if (j := rows.joint(r, s)) is not None and j.driven is not None]
        if not says:
            continue
        ref, value = says[0]
        for s, other in says[1:]:
            if other != value:
                groups.setdefault((ref, s, value), []).append(rows.label(r))
    for (ref, s, value), names in groups.items():
        a, b = rows.sides[ref].label, rows.sides[s].label
        driver, passive = (a, b) if value else (b, a)
        out.append(
            map_finding(
                "drive_difference",
                "error",
                f"{driver} drives {len(names)} joint(s) {passive} leaves passive: {listed(names)}",
                names,
                {"driven_in": driver, "passive_in": passive},
                len(names),
                "joints",
                "driven",
            )
        )
    return out


def _relations(rows: Rows, found: dict) -> dict[frozenset, tuple[int, float, float, Follows]]:
    """Each coupling as a relation between two rows: {rows} -> (follower row, multiplier, offset, coupling)."""
    return {frozenset((r, lead)): (r, c.multiplier, c.offset, c) for r, (lead, c) in found.items() if lead is not None}


def _coupling_differences(rows: Rows, stated: dict) -> list:
    sides = sorted(stated)
    out = []
    for s in sides[1:]:
        ref = sides[0]
        a, b = rows.sides[ref], rows.sides[s]
        ra, rb = _relations(rows, stated[ref]), _relations(rows, stated[s])
        for key in sorted(set(ra) | set(rb), key=sorted):
            if any(rows.joint(r, ref) is None or rows.joint(r, s) is None for r in key):
                continue
            x, y = ra.get(key), rb.get(key)
            if x is None or y is None:
                holder, other = (a, b) if x is not None else (b, a)
                f, _, _, c = ra[key] if x is not None else rb[key]
                out.append(
                    map_finding(
                        "coupling_one_file",
                        "warning",
                        f"{rows.label(f)} follows {c.leader} ({c.source}) in {holder.label} only; {other.label} leaves it free",
                        [rows.label(f)],
                        {"in": holder.label},
                        None,
                        "",
                        "follows",
                    )
                )
                continue
            m, o = y[1], y[2]
            if y[0] != x[0]:  # stated the other way round: l = m·f + o  =>  f = l/m − o/m
                m, o = (1 / m, -o / m) if m else (float("inf"), 0.0)
            if abs(x[1] - m) > RTOL * max(1, abs(x[1])) or abs(x[2] - o) > 1e-6:
                out.append(
                    map_finding(
                        "coupling_difference",
                        "error",
                        f"{rows.label(x[0])}: {a.label} has it follow "
                        f"{x[3].leader} ×{x[1]:g} {x[2]:+g}, {b.label} ×{m:g} {o:+g} (in {a.label}'s "
                        "direction)",
                        [rows.label(x[0])],
                        {"files": [a.label, b.label]},
                        abs(x[1] - m),
                        "ratio",
                        "follows",
                    )
                )
    return out
