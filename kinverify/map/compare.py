"""What differs between the sides, as findings (one cause, one finding, with its size).

- ``joint_missing`` (error): joints one file has and the first lacks, or the other way round;
- ``joint_order`` / ``actuator_order`` (error): the joints (actuators) both have, in another order
  than the first file's (the first side with actuators'): the size is how many change place; two
  control orders that are each their file's joint order (a USD's drives) differ only as the joints
  do, which ``joint_order`` names;
- ``<value>_difference`` (error) per value of :data:`kinverify.map.side.VALUES`: each side is
  compared with the first side that states the value; the joints a side gets wrong by one same
  ratio are one finding; a ratio of 180/π (or π/180) is ``<value>_units`` (per degree read as per
  radian); positions are compared by their difference, the other values relatively (``rtol``);
- ``<value>_unset`` (warning): a side whose format can state the value and leaves it unset where
  another states it (the simulator then uses its default, MuJoCo 0); ``<value>_inexpressible``
  (info): its format cannot state it;
- ``drive_difference`` (error): joints one side drives and another leaves passive;
  ``driven_follower`` (error): a side drives a joint that follows another (a ``<mimic>``, an
  active ``<equality joint>``, a USD mimic joint) through an actuator of its own: the drive fights the coupling;
  ``coupling_difference`` (error) / ``coupling_one_file`` (warning).
Gains and efforts are compared only on joints both sides drive."""

from __future__ import annotations

import math

from kinverify.map.rows import Rows
from kinverify.map.side import VALUES, Value
from kinverify.suites.base import Finding, Severity

POSITION_TOL = 1e-4  # rad or m: a default pose written to 4 decimals agrees
RTOL = 1e-3  # relative: gains, limits, inertias written to 3-4 significant digits agree
DEGREE = 180.0 / math.pi
DRIVE_VALUES = ("stiffness", "damping", "effort")


def map_finding(kind: str, severity: Severity, message: str, joints=(), values=None, magnitude=None, unit="", prop="") -> Finding:
    joints = list(joints)
    return Finding(
        kind,
        severity,
        message,
        ", ".join(joints),
        "joint" if joints else "model",
        "",
        prop,
        dict(values or {}),
        None if magnitude is None else float(magnitude),
        unit,
    )


def listed(names, limit: int = 6) -> str:
    names = list(names)
    return ", ".join(names[:limit]) + (f" and {len(names) - limit} more" if len(names) > limit else "")


def order_findings(rows: Rows) -> list[Finding]:
    out = []
    files = [s for s, side in enumerate(rows.sides) if side.ordered]
    ref = files[0]
    for s in files[1:]:
        a, b = rows.sides[ref], rows.sides[s]
        only_b = [rows.names[r][s] for r in range(len(rows.names)) if rows.names[r][ref] is None and rows.names[r][s]]
        only_a = [rows.names[r][ref] for r in range(len(rows.names)) if rows.names[r][s] is None and rows.names[r][ref]]
        if only_a or only_b:
            said = "; ".join(
                x
                for x in (
                    f"{b.label} lacks {listed(only_a)}" if only_a else "",
                    f"{a.label} lacks {listed(only_b)}" if only_b else "",
                )
                if x
            )
            out.append(
                map_finding(
                    "joint_missing",
                    "error",
                    f"joints in one file only: {said}",
                    only_a + only_b,
                    {"files": [a.label, b.label], "only_first": only_a, "only_second": only_b},
                    len(only_a) + len(only_b),
                    "joints",
                )
            )
        common = [r for r in range(len(rows.names)) if rows.names[r][ref] and rows.names[r][s]]
        by_a = sorted(common, key=lambda r: a.names.index(rows.name(r, ref)))
        by_b = sorted(common, key=lambda r: b.names.index(rows.name(r, s)))
        moved = [rows.names[r][ref] for r, q in zip(by_a, by_b, strict=True) if r != q]
        if moved:
            out.append(
                map_finding(
                    "joint_order",
                    "error",
                    f"{b.label} ({b.order}) orders {len(moved)} of the {len(common)} "
                    f"joints both have otherwise than {a.label} ({a.order}): {listed(moved)}; use the joint map",
                    moved,
                    {
                        "files": [a.label, b.label],
                        "first": [rows.names[r][ref] for r in by_a],
                        "second": [rows.names[r][s] for r in by_b],
                    },
                    len(moved),
                    "joints",
                    "order",
                )
            )
    out += _actuator_order(rows)
    return out


def actuator_rows(rows: Rows, s: int) -> list[tuple[int, ...]]:
    """Side ``s``'s actuators as the rows of the joints each drives, in its actuator order."""
    return [tuple(r for n in act.joints if (r := rows.row_of(s, n)) is not None) for act in rows.sides[s].actuators or []]


def _actuator_order(rows: Rows) -> list[Finding]:
    having = [s for s, side in enumerate(rows.sides) if side.actuators]
    out = []
    for s in having[1:]:
        a, b = rows.sides[having[0]], rows.sides[s]
        acts = a.actuators or []  # every side in having states actuators
        ka, kb = actuator_rows(rows, having[0]), actuator_rows(rows, s)
        common = [k for k in ka if k and k in kb]
        by_b = sorted(common, key=kb.index)
        moved = [acts[ka.index(k)].name for k, q in zip(common, by_b, strict=True) if k != q]
        if moved and _follow_joints(rows, having[0], common) and _follow_joints(rows, s, by_b):
            continue  # both control orders are their files' joint orders (a USD's drives): joint_order names the cause
        if moved:
            out.append(
                map_finding(
                    "actuator_order",
                    "error",
                    f"{b.label} orders {len(moved)} of the {len(common)} actuators "
                    f"both have (by the joints they drive) otherwise than {a.label}: {listed(moved)}; use the "
                    "actuator map",
                    [rows.label(k[0]) for k in common if acts[ka.index(k)].name in moved],
                    {"files": [a.label, b.label]},
                    len(moved),
                    "actuators",
                    "order",
                )
            )
    return out


def _follow_joints(rows: Rows, s: int, keys: list[tuple[int, ...]]) -> bool:
    """Whether side ``s``'s actuators ``keys`` (single joints) come in its joint order."""
    if any(len(k) != 1 for k in keys):
        return False
    names = rows.sides[s].names
    at = [names.index(rows.name(k[0], s)) for k in keys]
    return at == sorted(at)


def _ratio_name(ratio: float) -> str | None:
    for factor, name in ((DEGREE, "per degree read as per radian?"), (1 / DEGREE, "per radian read as per degree?")):
        if abs(ratio / factor - 1) < 1e-3:
            return name
    return None


def _agree(v: Value, a: float, b: float, rtol: float) -> bool:
    if v.absolute:
        return abs(a - b) <= POSITION_TOL
    return abs(a - b) <= 1e-12 + rtol * max(abs(a), abs(b))


def _compared(rows: Rows, r: int, s: int, v: Value):
    """(value, reason): side ``s``'s value of ``v`` on row ``r``, or None and why it is absent:
    "absent" (no such joint), "apart", "passive", "unset" or "inexpressible"."""
    j = rows.joint(r, s)
    if j is None:
        return None, "absent"
    if v.name in DRIVE_VALUES and j.driven is False:
        return None, "passive"
    amount = getattr(j, v.name)
    if amount is not None:
        return amount, ""
    if v.name in j.apart:
        return None, "apart"
    return None, rows.sides[s].state(v.name)


def value_findings(rows: Rows, rtol: float = RTOL) -> list[Finding]:
    out = []
    for v in VALUES:
        groups: dict[tuple, list] = {}
        for r in range(len(rows.names)):
            stated = [(s, x) for s in range(len(rows.sides)) if (x := _compared(rows, r, s, v)[0]) is not None]
            if not stated:
                continue
            ref, ref_value = stated[0]
            for s, x in stated[1:]:
                if not _agree(v, ref_value, x, rtol):
                    ratio = x / ref_value if ref_value else math.inf
                    finite = math.isfinite(ratio) and ratio != 0
                    named = _ratio_name(ratio) if finite else None
                    bucket = None if v.absolute or named or not finite else round(math.log(abs(ratio)), 3)
                    groups.setdefault(("difference", ref, s, named, bucket), []).append((r, ref_value, x))
            for s in range(len(rows.sides)):
                _, why = _compared(rows, r, s, v)
                if why in ("unset", "inexpressible") and ref_value != 0:  # 0: every format's default
                    groups.setdefault((why, ref, s), []).append((r, ref_value, None))
        for key, hits in groups.items():
            out.append(_value_finding(rows, v, key, hits))
    return out


def _value_finding(rows: Rows, v: Value, key: tuple, hits: list) -> Finding:
    what, ref, s = key[:3]
    a, b = rows.sides[ref], rows.sides[s]
    joints = [rows.label(r) for r, _, _ in hits]
    types = {j.type for r, _, _ in hits if (j := rows.joint(r, ref)) is not None}  # every hit: a row side ref has
    unit = v.unit(types.pop()) if len(types) == 1 else f"{v.unit_revolute} or {v.unit_prismatic}"
    if what != "difference":
        size = max(abs(x) for _, x, _ in hits)
        severity: Severity
        kind, severity = f"{v.name}_{what}", "warning" if what == "unset" else "info"
        why = "leaves it unset (its simulator's default applies)" if what == "unset" else f"cannot state it ({b.format})"
        message = (
            f"{v.label}: {b.label} {why} on {len(joints)} joints where {a.label} states up to {size:.6g} {unit}: {listed(joints)}"
        )
        return map_finding(
            kind,
            severity,
            message,
            joints,
            {"files": [a.label, b.label], "stated": {rows.label(r): x for r, x, _ in hits}},
            size,
            unit,
            v.name,
        )
    named = key[3]
    size = max(abs(y - x) for _, x, y in hits)
    pairs = {rows.label(r): [x, y] for r, x, y in hits}
    ratio = hits[0][2] / hits[0][1] if hits[0][1] else math.inf
    scale = f"×{ratio:.6g}" if math.isfinite(ratio) and not v.absolute else ""
    detail = "; ".join(f"{n} {x:.6g} vs {y:.6g}" for n, (x, y) in list(pairs.items())[:4])
    kind = f"{v.name}_units" if named else f"{v.name}_difference"
    message = (
        f"{v.label}: {b.label}'s is {scale + ' ' if scale else 'not '}{a.label}'s on {len(joints)} joints"
        f"{f' ({named})' if named else ''}, up to {size:.6g} {unit} apart: {detail}"
    )
    return map_finding(
        kind,
        "error",
        message,
        joints,
        {"files": [a.label, b.label], "values": pairs, "ratio": ratio if math.isfinite(ratio) else None},
        size,
        unit,
        v.name,
    )
