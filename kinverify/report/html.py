"""HTML report rendered from Jinja2 templates shipped as package data (autoescaped).

The first screen answers: the verdict and what it means for the exit code, the model and what was
compared, what failed (with the worst configuration, both values and what to check) and the
heat map of every property against every backend. Then the pictures (skeleton, kinematic tree,
MuJoCo renderings), the file-mode findings, and the detail of each suite folded in ``<details>``.

Everything comes from the :class:`~kinverify.results.VerifyResult` (so a saved JSON re-renders
the same page). One self-contained file: CSS, SVG, images and the model texts are inline;
nothing is fetched from a network.
"""

from __future__ import annotations

import base64
import math
from pathlib import Path
from typing import Any

from jinja2 import Environment, PackageLoader
from markupsafe import Markup

from kinverify.report import failures as fail_view
from kinverify.report import matrix
from kinverify.report.plots import error_distributions_svg, workspace_svg
from kinverify.report.units import display_unit, revolute
from kinverify.io.write import write_atomic
from kinverify.results import VerifyResult
from kinverify.suites.base import Section, Table

IMAGE_MIMES = {"image/svg+xml", "image/png", "image/gif", "image/jpeg", "image/webp"}
SPECIAL_SECTIONS = {"diagnosis", "pictures", "filemode"}  # drawn in their own places, not as a generic section
# Page order of the other sections and of versions; anything else follows alphabetically. Fixed
# here (not taken from dict order) so a result re-read from its JSON (sorted keys) renders identically.
SECTION_ORDER = ("kinematics", "ik", "dynamics", "tracking", "workspace")
VERSION_ORDER = ("kinverify", "python")  # then the libraries, alphabetically
EXIT_MEANING = {
    "pass": "exit 0: the models agree",
    "fail": "exit 1: the models disagree",
    "error": "exit 3: kinverify itself failed; what was computed is shown",
}

configuration = fail_view.configuration  # re-exported: a configuration as rad and deg vectors


def _ordered(keys, first) -> list:
    return sorted(keys, key=lambda k: (first.index(k) if k in first else len(first), k))


def _environment() -> Environment:
    env = Environment(
        loader=PackageLoader("kinverify", "report/templates"), autoescape=True, trim_blocks=True, lstrip_blocks=True
    )
    env.filters["sci"] = lambda x: "nan" if x != x else f"{x:.2e}"
    env.filters["b64"] = lambda text: base64.b64encode(str(text).encode("utf-8")).decode("ascii")
    return env


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
    rows = [
        [
            {
                "text": cell(v),
                "num": isinstance(v, (int, float)) and not isinstance(v, bool),
                "long": isinstance(v, str) and len(v) > 60,
            }
            for v in (row if isinstance(row, (list, tuple)) else [row])
        ]
        for row in t.rows
    ]
    return {"title": t.title, "columns": list(t.columns), "rows": rows}


def _figures(section: Section) -> list[dict[str, Any]]:
    """Images of a section; plots (SVG) get a full row, pictures and animations share one."""
    return [
        {"title": f.title, "caption": f.caption, "wide": f.mime == "image/svg+xml", "src": f"data:{f.mime};base64,{f.data}"}
        for f in section.figures
        if f.mime in IMAGE_MIMES
    ]


def _is_alert(note: str) -> bool:
    """Notes that say something is missing from the page are shown up front; the others explain
    the numbers and follow the tables."""
    return "unavailable" in note or note.startswith(("skipped", "not run", "no MuJoCo rendering"))


def _section_view(name: str, sec: Section) -> dict[str, Any]:
    svg = workspace_svg(sec.data) if name == "workspace" else None
    notes = list(sec.notes)
    # the file-mode findings are drawn from the findings themselves, grouped (failures.finding_groups)
    tables = [t for t in sec.tables if not (name == "filemode" and t.title == "Findings")]
    return {
        "id": name,
        "title": sec.title or name,
        "summary": sec.summary,
        "svg": Markup(svg) if svg else None,
        "figures": _figures(sec),
        "tables": [_table(t) for t in tables],
        "alerts": [n for n in notes if _is_alert(n)],
        "notes": [n for n in notes if not _is_alert(n)],
    }


def run_notes(result: VerifyResult) -> list[str]:
    """The run's notes without those the page shows elsewhere (file-mode findings, which have
    their own table, and notes a section repeats)."""
    shown = {f"{f.kind}: {f.message}" for f in result.findings}
    for sec in result.sections.values():
        shown |= set(sec.notes)
    return [n for n in result.notes if n not in shown]


def detail_rows(result: VerifyResult, group: matrix.Group) -> list[dict[str, Any]]:
    """One row per matrix cell of a suite (the cell links here): checks, worst frame and pair,
    max and p99 error, tolerance or goal, first failing frame."""
    rank = {f: i for i, f in enumerate(result.frames)}
    rows = []
    for row in group.rows:
        for col in group.columns:
            if col not in row.cells:
                continue
            c = row.cells[col]
            failed = sorted((x for x in c.checks if not x.passed), key=lambda x: rank.get(x.frame, len(rank)))
            pairs = {x.backends for x in c.checks}
            rows.append(
                {
                    "anchor": c.anchor,
                    "property": row.property,
                    "column": col,
                    "against": ", ".join(a for a in c.against if a),
                    "pair": " vs ".join(c.worst.backends) if len(pairs) > 1 else "",
                    "n": len(c.checks),
                    "failed": len(failed),
                    "worst": c.worst,
                    "p99": max(x.p99_error for x in c.checks),
                    "first": failed[0].frame if failed else "",
                    "passed": c.passed,
                    "note": "; ".join(dict.fromkeys(x.note for x in c.checks if x.note)),
                }
            )
    return rows


def suites_view(result: VerifyResult, groups: list[matrix.Group]) -> list[dict[str, Any]]:
    """The folded detail of each suite: its matrix rows as a table and its section."""
    out, done = [], set()
    for g in groups:
        sec = result.sections.get(g.suite)
        n = sum(len(c.checks) for r in g.rows for c in r.cells.values())
        n_bad = sum(not c.passed for r in g.rows for cell_ in r.cells.values() for c in cell_.checks)
        out.append(
            {
                "id": g.suite,
                "title": g.title,
                "open": False,
                "n": n,
                "n_bad": n_bad,
                "performance": all(r.kind == "performance" for r in g.rows),
                "rows": detail_rows(result, g),
                "section": _section_view(g.suite, sec) if sec else None,
            }
        )
        done.add(g.suite)
    for name in _ordered(result.sections, SECTION_ORDER):
        if name not in done and name not in SPECIAL_SECTIONS:
            out.append(
                {
                    "id": name,
                    "title": result.sections[name].title or name,
                    "open": False,
                    "n": 0,
                    "n_bad": 0,
                    "performance": False,
                    "rows": [],
                    "section": _section_view(name, result.sections[name]),
                }
            )
    return out


def pictures_view(result: VerifyResult, marks: dict[str, str]) -> dict[str, Any] | None:
    """Skeleton (with the file-mode alignment when there is one), kinematic tree, MuJoCo images."""
    from kinverify.report.skeleton import skeleton_svg
    from kinverify.report.tree import tree_svg

    sec = result.sections.get("pictures")
    if sec is None:
        return None
    filemode = result.sections.get("filemode")
    alignment = (filemode.data.get("alignment") or {}).get("T_mjcf_from_urdf") if filemode is not None else None
    has_poses = bool(sec.data.get("poses"))
    skeleton = skeleton_svg(sec.data, alignment, marks) if has_poses else None
    failing = bool(result.failed or result.failing_findings)  # the worst configuration beside the failures
    worst = skeleton_svg(sec.data, alignment, marks, keys=("worst",), width=4.2) if has_poses and failing else None
    tree = tree_svg(sec.data["tree"], marks) if sec.data.get("tree") else None
    data = sec.data
    view = _section_view("pictures", sec)
    caption = data.get("worst_label", "")
    if data.get("other"):
        caption = f"{data.get('reference')} solid, {data['other']} ghosted over it. Worst configuration: {caption}"
    offset = fail_view.base_offset(result)
    base = (
        (
            f"The MJCF's base is the URDF's {fail_view.describe_offset(offset)}"
            + (' (panels "as written"; the others are drawn with the bases aligned).' if alignment is not None else ".")
        )
        if offset is not None
        else ""
    )
    return {
        **view,
        "skeleton": Markup(skeleton) if skeleton else None,
        "worst": Markup(worst) if worst else None,
        "tree": tree,
        "caption": caption,
        "base": base,
        "marked": sorted(marks.items()),
    }


def compared(result: VerifyResult) -> str:
    """One line: what was compared with what, on how much."""
    ref = matrix.reference(result)
    others = [b for b in result.backends if b != ref]
    return (
        f"{ref} (reference) against {', '.join(others) or 'nothing else'}; {len(result.joint_names)} joints, "
        f"{len(result.frames)} frames, {result.samples} configurations (seed {result.seed})"
    )


FORMAT_LABELS = {"urdf": "URDF", "mjcf": "MJCF", "sdf": "SDF", "usd": "USD"}


def side_labels(result: VerifyResult) -> tuple[str, str]:
    """The formats of file mode's two sides as the findings table heads them (a spec: URDF, MJCF)."""
    kinds = list((result.model_info or {}).get("files") or {})
    if len(kinds) == 2 and all(k in FORMAT_LABELS for k in kinds):
        return FORMAT_LABELS[kinds[0]], FORMAT_LABELS[kinds[1]]
    return "URDF", "MJCF"


def render_html(result: VerifyResult) -> str:
    groups = matrix.groups(result)
    marks = fail_view.marked_subjects(result)
    dist = error_distributions_svg(result)
    finding_groups = fail_view.finding_groups(result)
    top, others = fail_view.finding_groups(result, errors=True), fail_view.finding_groups(result, errors=False)
    return (
        _environment()
        .get_template("report.html.j2")
        .render(
            r=result,
            exit_meaning=EXIT_MEANING[result.verdict],
            compared=compared(result),
            failing=fail_view.failure_groups(result),
            findings=fail_view.findings_summary(result),
            finding_groups=finding_groups,
            top_findings=top,
            other_findings=others,
            side_labels=side_labels(result),
            groups=groups,
            legend=matrix.legend(bool(result.explained)),
            suites=suites_view(result, groups),
            pictures=pictures_view(result, marks),
            filemode=result.sections.get("filemode"),
            filemode_view=_section_view("filemode", result.sections["filemode"]) if "filemode" in result.sections else None,
            run_notes=run_notes(result),
            distributions=Markup(dist) if dist else None,
            rows=sorted(result.checks, key=lambda c: c.passed),
            versions=[(k, result.versions[k]) for k in _ordered(result.versions, VERSION_ORDER)],
            revolute=revolute(result),
            unit=lambda u: display_unit(u, revolute(result)),
            math=math,
            matrix=matrix,
        )
    )


def write_html(result: VerifyResult, path) -> Path:
    return write_atomic(path, render_html(result))
