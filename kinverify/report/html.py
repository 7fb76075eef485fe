"""HTML report rendered from Jinja2 templates shipped as package data (autoescaped).

Everything comes from the :class:`~kinverify.results.VerifyResult` (so a saved JSON re-renders
the same page): this module turns it into a small view model (groups, failing pairs, vectors in
rad and deg, plots as inline SVG) and the template lays it out. One self-contained file: CSS,
SVG, images and the model texts are inline; nothing is fetched from a network.
"""

from __future__ import annotations

import base64
import math
from pathlib import Path
from typing import Any

from jinja2 import Environment, PackageLoader
from markupsafe import Markup

from kinverify.results import VerifyResult
from kinverify.suites.base import SEVERITIES, Check, Section, Table
from kinverify.report.plots import error_distributions_svg, workspace_svg
from kinverify.report.writer import write_atomic

IMAGE_MIMES = {"image/svg+xml", "image/png", "image/gif", "image/jpeg", "image/webp"}
SPECIAL_SECTIONS = {"diagnosis"}  # rendered inside the failing-check blocks, not as a section
# Page order of sections and versions; anything else follows alphabetically. Fixed here (not
# taken from dict order) so a result re-read from its JSON (sorted keys) renders identically.
SECTION_ORDER = ("filemode", "pictures", "workspace", "ik", "tracking", "dynamics")
VERSION_ORDER = ("kinverify", "python")  # then the libraries, alphabetically


def _ordered(keys, first) -> list:
    return sorted(keys, key=lambda k: (first.index(k) if k in first else len(first), k))


def _environment() -> Environment:
    env = Environment(loader=PackageLoader("kinverify", "report/templates"), autoescape=True,
                      trim_blocks=True, lstrip_blocks=True)
    env.filters["sci"] = lambda x: "nan" if x != x else f"{x:.2e}"
    env.filters["b64"] = lambda text: base64.b64encode(str(text).encode("utf-8")).decode("ascii")
    return env


def _vector(values, fmt: str) -> str:
    return "[" + ", ".join(format(v, fmt) if math.isfinite(v) else str(v) for v in values) + "]"


def configuration(q, revolute: list[bool]) -> dict[str, str]:
    """A configuration as copyable vectors: radians (metres for prismatic joints) and degrees."""
    deg = [math.degrees(v) if r else v for v, r in zip(q, revolute)]
    return {"rad": _vector([v + 0.0 for v in q], ".10g"), "deg": _vector([round(v, 6) + 0.0 for v in deg], ".10g")}


def _revolute(result: VerifyResult) -> list[bool]:
    joints = result.model_info.get("joints") or []
    if len(joints) == len(result.joint_names):
        return [j.get("type", "revolute") == "revolute" for j in joints]
    return [True] * len(result.joint_names)


def failing_pairs(result: VerifyResult) -> list[dict[str, Any]]:
    """One block per backend pair with a failing check: properties along the chain, where the
    disagreement starts, worst configurations and the diagnosis hint."""
    revolute = _revolute(result)
    rank = {f: i for i, f in enumerate(result.frames)}
    diag_section = result.sections.get("diagnosis")
    diagnosis = {tuple(p["backends"]): p for p in (diag_section.data.get("pairs", []) if diag_section else [])}
    pairs: dict[tuple, list[Check]] = {}
    for c in result.checks:
        pairs.setdefault(c.backends, []).append(c)
    out = []
    for pair, checks in pairs.items():
        failed = [c for c in checks if not c.passed]
        if not failed:
            continue
        props = list(dict.fromkeys(c.property for c in checks))
        frames = sorted({c.frame for c in checks}, key=lambda f: rank.get(f, len(rank)))
        cell = {(c.property, c.frame): c for c in checks}
        first = min(failed, key=lambda c: rank.get(c.frame, len(rank)))
        chain = [{"frame": f, "starts": f == first.frame, "cells": [cell.get((p, f)) for p in props]} for f in frames]
        diag = diagnosis.get(pair) or {}
        worst = []
        for w in diag.get("worst", []):
            worst.append({**configuration(w["q"], revolute), "where": w["frame"],
                          "error": f"{w['position_error']:.3e} m, {w['rotation_error']:.3e} rad"})
        for c in sorted(failed, key=lambda c: -c.max_error / c.tolerance if c.tolerance else 0):
            vec = configuration(c.worst_q, revolute)
            if c.worst_q and vec["rad"] not in [w["rad"] for w in worst]:
                worst.append({**vec, "where": f"{c.property} at {c.frame}", "error": f"{c.max_error:.3e} {c.unit}"})
        out.append({"backends": pair, "properties": props, "failed_properties": list(dict.fromkeys(c.property for c in failed)),
                    "first": first, "chain": chain, "worst": worst[:8], "hint": (diag.get("hint") or {}).get("text", ""),
                    "diagnosed": bool(diag), "n_failed": len(failed), "n_checks": len(checks)})
    return out


def overview_rows(result: VerifyResult) -> list[dict[str, Any]]:
    """One row per (property, backend pair): frames, worst frame, max and p99 over frames;
    failing groups first, then the order the checks were computed in."""
    groups: dict[tuple, list[Check]] = {}
    for c in result.checks:
        groups.setdefault((c.property, c.backends), []).append(c)
    rows = []
    for (prop, pair), checks in groups.items():
        worst = max(checks, key=lambda c: (c.max_error / c.tolerance) if c.tolerance else c.max_error)
        failed = [c for c in checks if not c.passed]
        rows.append({"property": prop, "backends": pair, "frames": len(checks), "failed": len(failed),
                     "passed": not failed, "worst": worst, "p99": max(c.p99_error for c in checks),
                     "first": failed[0].frame if failed else "", "note": worst.note})
    return sorted(rows, key=lambda row: row["passed"])


def summary_rows(result: VerifyResult) -> list[Check]:
    """Every check, failures first; within each, property, pair and chain order as computed."""
    return sorted(result.checks, key=lambda c: c.passed)


def _figures(section: Section) -> list[dict[str, Any]]:
    """Images of a section; plots (SVG) get a full row, pictures and animations share one."""
    return [{"title": f.title, "caption": f.caption, "wide": f.mime == "image/svg+xml", "src": f"data:{f.mime};base64,{f.data}"}
            for f in section.figures if f.mime in IMAGE_MIMES]


def cell(value) -> str:
    """A section table cell as text: floats to 4 significant digits, booleans as yes/no, lists
    comma-separated; strings as they are."""
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float):
        return f"{value:.4g}"
    if isinstance(value, (list, tuple)):
        return ", ".join(cell(v) for v in value)
    return "" if value is None else str(value)


def _table(t: Table) -> dict[str, Any]:
    rows = [[{"text": cell(v), "num": isinstance(v, (int, float)) and not isinstance(v, bool),
              "long": isinstance(v, str) and len(v) > 60} for v in (row if isinstance(row, (list, tuple)) else [row])]
            for row in t.rows]
    return {"title": t.title, "columns": list(t.columns), "rows": rows}


def _is_alert(note: str) -> bool:
    """Notes that say something is missing from the page are shown up front; the others explain
    the numbers and follow the tables."""
    return "unavailable" in note or note.startswith(("skipped", "not run"))


def run_notes(result: VerifyResult) -> list[str]:
    """The run's notes without those the page shows elsewhere (file-mode findings, which have
    their own table, and notes a section repeats)."""
    shown = {f"{f.kind}: {f.message}" for f in result.findings}
    for sec in result.sections.values():
        shown |= set(sec.notes)
    return [n for n in result.notes if n not in shown]


def findings_summary(result: VerifyResult) -> list[tuple[str, int]]:
    """Findings counted per severity (errors first)."""
    counts = {s: sum(f.severity == s and not f.accepted for f in result.findings) for s in SEVERITIES}
    accepted = sum(f.accepted for f in result.findings)
    return [(s, n) for s, n in counts.items() if n] + ([("accepted", accepted)] if accepted else [])


def sections(result: VerifyResult) -> list[dict[str, Any]]:
    """Generic sections (schema in results.py); the workspace cloud is drawn from its points."""
    out = []
    for name in _ordered(result.sections, SECTION_ORDER):
        sec = result.sections[name]
        if name in SPECIAL_SECTIONS:
            continue
        svg = workspace_svg(sec.data) if name == "workspace" else None
        tables = [_table(t) for t in sec.tables]
        notes = list(sec.notes)
        out.append({"id": name, "title": sec.title or name, "summary": sec.summary,
                    "svg": Markup(svg) if svg else None, "figures": _figures(sec), "tables": tables,
                    "alerts": [n for n in notes if _is_alert(n)], "notes": [n for n in notes if not _is_alert(n)]})
    return out


def render_html(result: VerifyResult) -> str:
    dist = error_distributions_svg(result)
    return _environment().get_template("report.html.j2").render(
        r=result, run_notes=run_notes(result), findings=findings_summary(result), failing=failing_pairs(result), rows=summary_rows(result), overview=overview_rows(result), sections=sections(result),
        distributions=Markup(dist) if dist else None,
        versions=[(k, result.versions[k]) for k in _ordered(result.versions, VERSION_ORDER)], revolute=_revolute(result), math=math,
        failed_groups=sorted({(c.property, " vs ".join(c.backends)) for c in result.failed}),
    )


def write_html(result: VerifyResult, path) -> Path:
    return write_atomic(path, render_html(result))
