"""The map for people: tables of the orders, the maps and the values side by side (rich on the
terminal; :class:`~kinverify.suites.base.Section` tables for file mode's JSON and HTML reports)."""

from __future__ import annotations

import math

from rich.console import Console
from rich.markup import escape
from rich.table import Table

from kinverify.map.contract import MapResult
from kinverify.map.side import VALUES, Value
from kinverify.suites.base import Section

COLOURS = {"error": "red", "warning": "yellow", "info": "dim"}


def short_labels(result: MapResult) -> list[str]:
    """Each side's label: its file name, or its path where two files share a name (:func:`map_files`)."""
    return [s.label for s in result.sides]


def _num(x) -> str:
    if x is None:
        return "—"
    if isinstance(x, float) and math.isinf(x):
        return "inf"
    return f"{x:.6g}"


def order_rows(result: MapResult) -> tuple[list[str], list[list[str]]]:
    """One row per joint: its place in each file's order (``#k``, its name there when it is
    another, ``qpos[a]`` for MuJoCo)."""
    labels, rows = short_labels(result), []
    columns = ["joint"] + [labels[s] for s, side in enumerate(result.sides) if side.ordered]
    for r, names in enumerate(result.rows.names):
        cells = [result.rows.label(r)]
        for s, side in enumerate(result.sides):
            if not side.ordered:
                continue
            n = names[s]
            if n is None:
                cells.append("—")
                continue
            j = side.joint(n)
            at = f" qpos[{j.qpos}]" if j is not None and j.qpos is not None and side.format == "mjcf" else ""
            named = f" {n}" if n != cells[0] else ""
            cells.append(f"#{side.names.index(n)}{named}{at}")
        rows.append(cells)
    return columns, rows


def actuator_rows(result: MapResult) -> tuple[list[str], list[list[str]]]:
    labels, rows = short_labels(result), []
    for s, side in enumerate(result.sides):
        for k, act in enumerate(side.actuators or []):
            rows.append([labels[s], f"#{k}", act.name, ", ".join(act.joints) or "—", act.kind])
    return ["file", "ctrl", "actuator", "joints", "kind"], rows


def value_rows(result: MapResult, v: Value) -> tuple[list[str], list[list[str]]] | None:
    """The value on every joint, per side (None when no side states it)."""
    labels, rows, any_stated = short_labels(result), [], False
    for r in range(len(result.rows.names)):
        cells = [result.rows.label(r)]
        for s, side in enumerate(result.sides):
            j = result.rows.joint(r, s)
            amount = None if j is None else getattr(j, v.name)
            any_stated |= amount is not None
            cells.append(
                ""
                if j is None
                else _num(amount)
                if amount is not None
                else "apart"
                if v.name in j.apart
                else "passive"
                if v.name in ("stiffness", "damping", "effort") and j.driven is False
                else side.state(v.name)
            )
        rows.append(cells)
    return (["joint"] + labels, rows) if any_stated else None


def drive_rows(result: MapResult) -> tuple[list[str], list[list[str]]]:
    labels, rows = short_labels(result), []
    for r in range(len(result.rows.names)):
        cells = [result.rows.label(r)]
        for s in range(len(result.sides)):
            j = result.rows.joint(r, s)
            if j is None:
                cells.append("")
                continue
            unstated = "the asset's drive" if result.sides[s].format == "table" else "not stated"
            drive = {True: j.mode or "driven", False: "passive", None: unstated}[j.driven]
            follows = f"; follows {j.follows.leader} ×{j.follows.multiplier:g}" if j.follows else ""
            cells.append(drive + follows)
        rows.append(cells)
    return ["joint"] + labels, rows


def _units(v: Value) -> str:
    return v.unit_revolute if v.unit_revolute == v.unit_prismatic else f"{v.unit_revolute}; prismatic {v.unit_prismatic}"


def tables(result: MapResult) -> list[tuple[str, list[str], list[list[str]]]]:
    """(title, columns, rows) of every table, in the report's order."""
    out = [("joint order (#index in each file's order)", *order_rows(result))]
    columns, rows = actuator_rows(result)
    if rows:
        out.append(("actuators (control order)", columns, rows))
    out.append(("drives and couplings", *drive_rows(result)))
    for v in VALUES:
        found = value_rows(result, v)
        if found is not None:
            out.append((f"{v.label} [{_units(v)}]", *found))
    return out


def print_map(result: MapResult, console: Console | None = None, json_path: str | None = None) -> None:
    console = console or Console()
    for side in result.sides:
        console.print(
            f"[bold]{escape(side.label)}[/]: {side.format}, {escape(side.order)}"
            + (f", {len(side.actuators)} actuators" if side.actuators is not None else "")
        )
        for note in side.notes:
            console.print(f"  [dim]{escape(note)}[/]")
    for title, columns, rows in tables(result):
        console.print(f"[bold]{escape(title)}[/]")
        table = Table(show_edge=False, pad_edge=False)
        for c in columns:
            table.add_column(escape(c), overflow="fold")
        for row in rows:
            table.add_row(*(escape(str(c)) for c in row))
        console.print(table)
    console.print("[bold]maps[/] " + escape("(to = from[index]; null: absent)"))
    for kind, entries in result.maps.items():
        for e in entries:
            console.print(
                f"  {kind}: {escape(e['from'])} -> {escape(e['to'])}: {[i for i in e['index']]}".replace("None", "null")
            )
    for f in result.findings:
        console.print(f"[{COLOURS[f.severity]}]{f.severity}[/] {f.kind}: {escape(f.message)}")
    errors = sum(f.fails for f in result.findings)
    verdict = f"[red]DIFFER[/]: {errors} error finding{'s' * (errors != 1)}" if errors else "[green]AGREE[/]"
    console.print(f"{verdict} ({result.duration_s:.2f} s)" + (f"; JSON: {escape(json_path)}" if json_path else ""))


def map_section(result: MapResult) -> Section:
    """The map as a report section (file mode): the tables and the maps, the findings as notes
    (file mode states its own findings; these are the contract's, shown, not counted)."""
    section = Section(
        "Sim-to-sim map",
        summary=f"joint and actuator orders of {', '.join(short_labels(result))}, "
        "the index maps between them and the values a policy depends on, per radian",
    )
    for title, columns, rows in tables(result):
        section.table(title, columns, rows)
    section.notes = [f"{f.severity} {f.kind}: {f.message}" for f in result.findings]
    section.data = {"maps": result.maps}
    return section
