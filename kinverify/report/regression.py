"""Terminal and HTML output of ``baseline check`` and ``diff``.

Both commands first build a *document*, plain JSON data
``{"title", "passed", "verdict", "summary": [str], "tables": [{"title", "columns", "rows"}], "notes": [str]}``,
then print it with rich or render it with the autoescaped ``regression.html.j2`` template.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from jinja2 import Environment, PackageLoader, select_autoescape
from rich.console import Console
from kinverify.text import console as text_console, markup as escape
from rich.table import Table

from kinverify.regression.check import BaselineCheck
from kinverify.regression.modeldiff import ModelDiff
from kinverify.regression.specdiff import ParamChange
from kinverify.io.write import write_atomic


def _num(x: float) -> str:
    return f"{x:.9g}"


def _short(x: float) -> str:
    return f"{x:.6g}"


def show_values(old, new) -> tuple[str, str]:
    """Short text for two record values: vectors of up to 3 numbers in full, larger values as
    the entry that changed most, e.g. ``[1,2]=0.25``."""
    a, b = np.asarray(old, float), np.asarray(new, float)
    if a.shape != b.shape:
        return f"shape {a.shape}", f"shape {b.shape}"
    if a.size <= 3:
        return ("[" + ", ".join(_short(x) for x in a.ravel()) + "]", "[" + ", ".join(_short(x) for x in b.ravel()) + "]")
    idx = np.unravel_index(int(np.argmax(np.abs(a - b))), a.shape)
    label = "[" + ",".join(str(int(i)) for i in idx) + "]="
    return label + _num(a[idx]), label + _num(b[idx])


def _q(q) -> str:
    """Full precision, ready to paste."""
    return "[" + ", ".join(repr(float(v)) for v in q) + "]"


def _q_short(q) -> str:
    return "[" + ", ".join(_short(float(v)) for v in q) + "]"


def param_table(changes: list[ParamChange]) -> dict[str, Any]:
    rows = [
        [
            c.where,
            c.field if c.kind == "changed" else c.kind,
            "" if c.old is None else _fmt(c.old),
            "" if c.new is None else _fmt(c.new),
            "" if c.delta is None else f"{c.delta:.6g}",
        ]
        for c in changes
    ]
    return {"title": "parameter changes", "columns": ["where", "field", "old", "new", "|Δ|"], "rows": rows}


def _fmt(v) -> str:
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_fmt(x) for x in v) + "]"
    return _num(v) if isinstance(v, float) else str(v)


def check_document(result: BaselineCheck) -> dict[str, Any]:
    moved_rows = []
    for m in result.moved:
        old, new = show_values(m.old, m.new)
        moved_rows.append(
            [m.frame, m.property, old, new, f"{m.delta:.3e} {m.unit}", f"{m.tolerance:.0e}", f"{m.count}/{m.of}", _q_short(m.q)]
        )
    summary = [
        f"{result.compared} records compared at {result.samples} configurations: "
        + (f"{len(result.moved)} quantities moved beyond tolerance" if result.moved else "nothing moved beyond tolerance")
    ]
    if result.moved:
        first = result.moved[0]
        summary.append(
            f"first moved: {first.property} at frame {first.frame}, delta {first.delta:.3e} {first.unit}, at q = {_q(first.q)}"
        )
    if result.frames_removed:
        summary.append("frames removed since the baseline: " + ", ".join(result.frames_removed))
    if result.frames_added:
        summary.append("frames added since the baseline: " + ", ".join(result.frames_added))
    tables = [
        {
            "title": "moved quantities (worst configuration per frame and property)",
            "columns": ["frame / joint", "property", "old", "new", "delta", "tolerance", "samples moved", "q"],
            "rows": moved_rows,
        }
    ]
    if result.spec_changes:
        tables.append(param_table(result.spec_changes))
    return {
        "title": f"kinverify baseline check: {result.model} against {result.source}",
        "passed": result.passed,
        "verdict": "PASS" if result.passed else "FAIL",
        "summary": summary,
        "tables": tables,
        "notes": result.explanations,
    }


def diff_document(d: ModelDiff, old_path: str = "", new_path: str = "") -> dict[str, Any]:
    frames = [
        [
            f.frame,
            f"{f.position:.3e}",
            f"{f.rotation:.3e}",
            f"{f.jacobian_linear:.3e}",
            f"{f.jacobian_angular:.3e}",
            _q_short(f.q),
        ]
        for f in d.frames
    ]
    reach = [
        [
            r.frame,
            "-" if r.old is None else f"{r.old:.6f}",
            "-" if r.new is None else f"{r.new:.6f}",
            "-" if r.change is None else f"{r.change:+.6f}",
        ]
        for r in d.reach
    ]
    moved = [f for f in d.frames if max(f.position, f.rotation, f.jacobian_linear, f.jacobian_angular) > 0]
    summary = [
        f"{len(d.params)} parameter changes; {len(moved)} of {len(d.frames)} common frames move (over {d.samples} configurations)"
    ]
    return {
        "title": f"kinverify diff: {old_path or d.old_name} -> {new_path or d.new_name}",
        "passed": d.identical,
        "verdict": "IDENTICAL" if d.identical else "CHANGED",
        "summary": summary,
        "tables": [
            param_table(d.params),
            {
                "title": "behaviour: largest change per frame over the sample set",
                "columns": ["frame", "position [m]", "rotation [rad]", "J linear", "J angular", "q (largest position change)"],
                "rows": frames,
            },
            {"title": "workspace reach from the base link [m]", "columns": ["frame", "old", "new", "change"], "rows": reach},
        ],
        "notes": d.notes,
    }


def print_document(doc: dict[str, Any], console: Console | None = None) -> None:
    console = console or text_console()
    console.print(f"[bold]{escape(doc['title'])}[/]")
    for table in doc["tables"]:
        if not table["rows"]:
            continue
        t = Table(title=table["title"])
        for col in table["columns"]:
            t.add_column(col, overflow="fold")
        for row in table["rows"]:
            t.add_row(*(escape(str(c)) for c in row))
        console.print(t)
    for line in doc["summary"]:
        console.print(escape(line))
    for note in doc["notes"]:
        console.print(f"[yellow]note:[/] {escape(note)}")
    colour = "green" if doc["passed"] else "red"
    console.print(f"verdict: [bold {colour}]{doc['verdict']}[/]")


def render_document_html(doc: dict[str, Any]) -> str:
    env = Environment(loader=PackageLoader("kinverify", "report/templates"), autoescape=select_autoescape(["html", "j2"]))
    return env.get_template("regression.html.j2").render(doc=doc)


def write_document(doc: dict[str, Any], path) -> Path:
    """HTML, or JSON when ``path`` ends in ``.json``; written atomically."""
    if str(path).endswith(".json"):
        import json

        return write_atomic(path, json.dumps(doc, indent=1, sort_keys=True) + "\n")
    return write_atomic(path, render_document_html(doc))
