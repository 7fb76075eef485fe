"""The reference tables of ``docs/`` generated from the code, so they cannot drift from it.

``python -m kinverify.report.docs`` prints the property table (from the suite registry: name,
suite, kind, unit, default tolerance or goal, what it compares); ``--write FILE`` puts it into
FILE between the markers ``<!-- properties:start -->`` and ``<!-- properties:end -->``;
``--check FILE`` exits 1 when the table in FILE is not the current one.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

START, END = "<!-- properties:start -->", "<!-- properties:end -->"


def _unit(unit: str) -> str:
    return {"joint": "rad or m (per joint type)", "rad|m": "rad or m (per joint type)"}.get(unit, unit)


def property_table() -> str:
    """Markdown: one row per registered property, in report order."""
    from kinverify.suites.registry import SUITES

    lines = ["| property | suite | kind | unit | default tolerance / goal | compares |", "| --- | --- | --- | --- | --- | --- |"]
    for suite in SUITES:
        for p in suite.properties:
            limit = f"{p.tolerance:g}" + (" (goal)" if p.kind == "performance" else "")
            compares = p.compares.replace("|", "\\|")
            unit = _unit(p.unit).replace("|", "\\|")
            lines.append(f"| `{p.name}` | `{suite.name}` | {p.kind} | {unit} | {limit} | {compares} |")
    return "\n".join(lines) + "\n"


def replace_table(text: str, table: str) -> str:
    """``text`` with the part between the markers replaced by ``table``."""
    if START not in text or END not in text:
        raise ValueError(f"no {START} ... {END} markers")
    head, rest = text.split(START, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{START}\n{table}{END}{tail}"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m kinverify.report.docs", description=__doc__.split("\n\n")[0])
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--write", metavar="FILE", help="replace the property table in FILE")
    group.add_argument("--check", metavar="FILE", help="exit 1 when the property table in FILE is out of date")
    args = parser.parse_args(argv)
    table = property_table()
    if args.write:
        path = Path(args.write)
        path.write_text(replace_table(path.read_text(encoding="utf-8"), table), encoding="utf-8")
        print(f"{path}: property table written")
    elif args.check:
        path = Path(args.check)
        text = path.read_text(encoding="utf-8")
        if replace_table(text, table) != text:
            print(f"{path}: the property table is out of date; run python -m kinverify.report.docs --write {path}")
            return 1
        print(f"{path}: the property table is current")
    else:
        sys.stdout.write(table)
    return 0


if __name__ == "__main__":
    sys.exit(main())
