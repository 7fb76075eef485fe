"""What the report shows first when a run fails: per backend under test, the properties that fail,
where along the chain the disagreement starts, the worst configuration, both values there and
what to check; and the file-mode findings grouped by joint and link, errors first.

Everything is computed from the :class:`~kinverify.results.VerifyResult` (checks, findings, the
diagnosis and pictures sections' data), so a saved JSON re-renders the same page.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from kinverify.report.matrix import column_of, ratio, reference
from kinverify.report.units import display_unit, revolute
from kinverify.results import VerifyResult
from kinverify.suites.base import SEVERITIES, Check, Finding

# What to look at when a property fails and no diagnosis pattern names the cause.
ADVICE = {
    "fk": "joint origins (xyz, rpy) and axes between the base and frame {frame}, where the disagreement starts",
    "jacobian": "joint axes and types up to frame {frame}; if FK agrees, the Jacobian convention (world-aligned, [linear; angular])",
    "jacobian.fd": "this backend's Jacobian against its own FK: a wrong Jacobian or frame convention in the adapter",
    "ik": "the IK solutions on this backend; when FK disagrees too, fix FK first",
    "dynamics": "masses, centres of mass, inertia tensors (and their frames), armature and joint damping/friction",
    "tracking": "the controller gains and the model terms (mass matrix, gravity) the controller uses",
}


def advice(c: Check) -> str:
    key = c.property if c.property in ADVICE else c.property.split(".")[0]
    return ADVICE.get(key, "the model parameters this property depends on").format(frame=c.frame)


def _vector(values, fmt: str) -> str:
    """``[a, b, c]``; components below 1e-9 of the largest are written 0 (round-off, not a value)."""
    values = [float(v) for v in values]
    big = max((abs(v) for v in values if math.isfinite(v)), default=0.0)
    values = [0.0 if math.isfinite(v) and abs(v) < 1e-9 * big else v for v in values]
    return "[" + ", ".join(format(v + 0.0, fmt) if math.isfinite(v) else str(v) for v in values) + "]"


def configuration(q, revolute: list[bool]) -> dict[str, str]:
    """A configuration as copyable vectors: radians (metres for prismatic joints) and degrees."""
    deg = [math.degrees(v) if r else v for v, r in zip(q, revolute, strict=False)]
    return {"rad": _vector([v + 0.0 for v in q], ".10g"), "deg": _vector([round(v, 6) + 0.0 for v in deg], ".10g")}


def _section_data(result: VerifyResult, name: str) -> dict:
    sec = result.sections.get(name)
    return sec.data if sec is not None else {}


def failure_groups(result: VerifyResult) -> list[dict[str, Any]]:
    """One block per backend under test with a failing check that counts (failures in chain
    order): its properties, where each starts, the worst configurations, both values at the worst
    configuration of FK (from the pictures suite) and the diagnosis hint or what to check."""
    ref, rev = reference(result), revolute(result)
    rank = {f: i for i, f in enumerate(result.frames)}
    diagnosis = {tuple(p["backends"])[1]: p for p in _section_data(result, "diagnosis").get("pairs", [])}
    values = {d["backend"]: d for d in _section_data(result, "pictures").get("disagreements", [])}
    by_column: dict[str, list[Check]] = {}
    for c in result.failed:
        by_column.setdefault(blamed(c, result, ref), []).append(c)
    out = []
    for col, failed in by_column.items():
        props = list(dict.fromkeys(c.property for c in failed))
        rows: list[dict[str, Any]] = []
        for prop in props:
            mine = [c for c in failed if c.property == prop]
            first = min(mine, key=lambda c: rank.get(c.frame, len(rank)))
            worst_check = max(mine, key=lambda c: ratio(c) if ratio(c) == ratio(c) else math.inf)
            against = list(dict.fromkeys(x for c in mine for x in c.backends if x != col)) or [col]
            rows.append(
                {
                    "property": prop,
                    "first": first,
                    "worst": worst_check,
                    "n": len(mine),
                    "against": ", ".join(against),
                    "of": sum(1 for c in result.checks if c.property == prop and col in c.backends),
                }
            )
        start = min((r["first"] for r in rows), key=lambda c: rank.get(c.frame, len(rank)))
        diag = diagnosis.get(col) or {}
        worst: list[dict[str, Any]] = []
        for w in diag.get("worst", []):
            worst.append(
                {
                    **configuration(w["q"], rev),
                    "where": w["frame"],
                    "error": f"{w['position_error']:.3e} m, {w['rotation_error']:.3e} rad",
                }
            )
        for c in sorted(failed, key=lambda c: -(ratio(c) if ratio(c) == ratio(c) else math.inf)):
            vec = configuration(c.worst_q, rev)
            if c.worst_q and vec["rad"] not in [w["rad"] for w in worst]:
                worst.append(
                    {**vec, "where": f"{c.property} at {c.frame}", "error": f"{c.max_error:.3e} {display_unit(c.unit, rev)}"}
                )
        v = values.get(col)
        both = None
        if v:
            both = {
                **configuration(v["q"], rev),
                "frame": v["frame"],
                "reference": ref,
                "backend": col,
                "a": _vector(v["reference"], ".6g"),
                "b": _vector(v["value"], ".6g"),
                "error": f"{v['position_error']:.3g} m, {v['rotation_error']:.3g} rad",
            }
        hint = (diag.get("hint") or {}).get("text", "")
        out.append(
            {
                "column": col,
                "rows": rows,
                "start": start,
                "worst": worst[:8],
                "both": both,
                "hint": hint,
                "advice": advice(start),
                "n_failed": len(failed),
                "chain": _chain(result, col, ref, rank),
            }
        )
    return out


def blamed(c: Check, result: VerifyResult, ref: str) -> str:
    """The side of a failing check to show it under: the side in more failing checks (a backend
    whose FK is wrong fails every comparison it is in), else the matrix column."""
    count = {b: sum(b in x.backends for x in result.failed) for b in c.backends}
    a, b = c.backends
    if a != b and count[a] != count[b] and a != ref and b != ref:
        return a if count[a] > count[b] else b
    return column_of(c.backends, result.backends, ref)[0]


def _chain(result: VerifyResult, col: str, ref: str, rank) -> dict[str, Any]:
    """Max error per frame (base to tool) of the properties compared per frame for one column."""
    checks = [c for c in result.checks if column_of(c.backends, result.backends, ref)[0] == col and c.frame in rank]
    props = list(dict.fromkeys(c.property for c in checks))
    cells: dict[tuple[str, str], Check] = {}
    for c in checks:
        key = (c.property, c.frame)
        if key not in cells or ratio(c) > ratio(cells[key]):
            cells[key] = c
    frames = sorted({c.frame for c in checks}, key=lambda f: rank[f])
    first = next((f for f in frames if any(not cells[(p, f)].passed for p in props if (p, f) in cells)), None)
    return {
        "properties": props,
        "rows": [{"frame": f, "starts": f == first, "cells": [cells.get((p, f)) for p in props]} for f in frames],
    }


def _numbers(v):
    if isinstance(v, (list, tuple)):
        for x in v:
            yield from _numbers(x)
    elif isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v):
        yield abs(v)


def fmt_value(v, floor: float = 0.0) -> str:
    """A finding's value for a table cell; in a vector or matrix, entries below 1e-12 of its
    largest are round-off and written 0."""
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        return "0" if abs(v) < floor else f"{v:.6g}"
    if isinstance(v, (list, tuple)):
        floor = max(floor, 1e-12 * max(_numbers(v), default=0.0))
        return "[" + ", ".join(fmt_value(x, floor) for x in v) + "]"
    if isinstance(v, dict):  # e.g. a rigid body's inertial: "mass 5.76; com [0, -0.03, 0.2775]; ..."
        return "; ".join(f"{k} {fmt_value(x)}" for k, x in v.items())
    return "" if v is None else str(v)


def side_by_side(f: Finding) -> tuple[list[tuple[str, str, str]], list[tuple[str, str]]]:
    """A finding's values as (label, URDF value, MJCF value) rows for keys ``urdf``/``mjcf`` and
    ``urdf_X``/``mjcf_X``, and the other values as (key, value)."""
    values = f.values or {}
    pairs, rest = [], []
    for key, value in values.items():
        if key == "urdf" or key.startswith("urdf_"):
            twin = "mjcf" + key[4:]
            if twin in values:
                a, b = value, values[twin]
                if isinstance(a, dict) and isinstance(b, dict):  # only what differs, side by side
                    keys = [k for k in a if k in b and k != "links" and fmt_value(a[k]) != fmt_value(b[k])] or list(a)
                    a, b = {k: a[k] for k in keys if k in a}, {k: b[k] for k in keys if k in b}
                pairs.append((key[5:].replace("_", " ") or f.property or "value", fmt_value(a), fmt_value(b)))
                continue
        elif (key == "mjcf" or key.startswith("mjcf_")) and ("urdf" + key[4:]) in values:
            continue
        rest.append((key.replace("_", " "), fmt_value(value)))
    return pairs, rest


def finding_groups(result: VerifyResult, errors: bool | None = None) -> list[dict[str, Any]]:
    """Findings grouped by what they concern (joint, link, frame, model, file), the groups with
    an error first; accepted findings count as their own kind, after infos. ``errors``: only the
    findings that fail the verdict (True), only the others (False), or all (None)."""
    order = {s: i for i, s in enumerate(SEVERITIES)}

    def level(f):
        return len(SEVERITIES) if f.accepted else order[f.severity]

    groups: dict[tuple[str, str], dict[str, Any]] = {}
    for f in result.findings:
        if errors is not None and f.fails != errors:
            continue
        key = (f.subject_type, f.subject)
        g = groups.setdefault(key, {"label": f.label, "type": f.subject_type, "subject": f.subject, "items": []})
        pairs, rest = side_by_side(f)
        g["items"].append(
            {"f": f, "pairs": pairs, "rest": rest, "level": level(f), "severity": "accepted" if f.accepted else f.severity}
        )
    out = sorted(groups.values(), key=lambda g: min(i["level"] for i in g["items"]))
    for g in out:
        g["items"].sort(key=lambda i: i["level"])
        g["severity"] = g["items"][0]["severity"]
    return out


def findings_summary(result: VerifyResult) -> list[tuple[str, int]]:
    """Findings counted per severity (errors first), accepted ones apart."""
    counts = {s: sum(f.severity == s and not f.accepted for f in result.findings) for s in SEVERITIES}
    accepted = sum(f.accepted for f in result.findings)
    return [(s, n) for s, n in counts.items() if n] + ([("accepted", accepted)] if accepted else [])


def base_offset(result: VerifyResult) -> np.ndarray | None:
    """File mode: the transform between the two files' world frames, from the file-mode section's
    alignment (``T_mjcf_from_urdf``) or a ``base_transform`` finding (xyz, rpy); None when the
    bases agree or it is unknown."""
    from kinverify.model.transforms import make_transform, rpy_to_matrix

    sec = result.sections.get("filemode")
    t = (sec.data.get("alignment") or {}).get("T_mjcf_from_urdf") if sec is not None else None
    if t is None:
        f = next((f for f in result.findings if f.kind == "base_transform" and {"xyz", "rpy"} <= set(f.values)), None)
        t = None if f is None else make_transform(rpy_to_matrix(f.values["rpy"]), f.values["xyz"])
    t = None if t is None else np.asarray(t, float)
    if t is None or t.shape != (4, 4) or np.allclose(t, np.eye(4), atol=1e-9):
        return None
    return t


def describe_offset(t: np.ndarray) -> str:
    """``turned by 180° about [0, 0, 1] and moved by [0, 0, 0.1] m`` (either part when it is zero)."""
    from kinverify.model.transforms import rotation_log

    w = rotation_log(t[:3, :3])
    angle = float(np.linalg.norm(w))
    parts = []
    if angle > 1e-9:
        parts.append(f"turned by {math.degrees(angle):.4g}° about {_vector(w / angle + 0.0, '.3g')}")
    if np.linalg.norm(t[:3, 3]) > 1e-9:
        parts.append(f"moved by {_vector(t[:3, 3] + 0.0, '.4g')} m")
    return " and ".join(parts)


def marked_subjects(result: VerifyResult) -> dict[str, str]:
    """Link and joint names to mark in the kinematic tree: ``error`` (an error finding, the
    frame where a failure starts, the joint a diagnosis names), ``warning``, or ``downstream``
    (a failing frame after the start)."""
    marks: dict[str, str] = {}
    rank = {"error": 0, "warning": 1, "downstream": 2}

    def mark(name: str, level: str) -> None:
        if name and (name not in marks or rank[level] < rank[marks[name]]):
            marks[name] = level

    for f in result.findings:
        if not f.accepted and f.severity in ("error", "warning") and f.subject_type in ("joint", "link", "frame"):
            mark(f.subject, f.severity)
    for g in failure_groups(result):
        mark(g["start"].frame, "error")
    for c in result.failed:
        mark(c.frame, "downstream")
    for p in _section_data(result, "diagnosis").get("pairs", []):
        hint = p.get("hint") or {}
        if hint.get("joint"):
            mark(hint["joint"], "error")
    return marks
