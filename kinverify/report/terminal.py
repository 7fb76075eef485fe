"""Terminal summary with rich, at the console's width: one line per suite, then the agreement
table (one row per property; one per property and backend where something fails) and the
performance table (goals, not counted unless gated), then what failed and the verdict.

At 80 columns, the width of a CI log (rich falls back to 80 when no stream is a terminal), no
row wraps and no value is split or cut: backends have short labels (``pin-urdf``, ``analytic vs
5``), numbers a compact form (``4.45e-16``, ``1e-9``), the unit follows the tolerance, and the
columns that do not fit are dropped, least useful first (:func:`fit_table`). A passing run
takes about 40 lines. A wider terminal shows the dropped columns and the backends by name.
"""

from __future__ import annotations

from typing import Sequence

from rich.cells import cell_len
from rich.console import Console
from kinverify.text import console as text_console, markup as escape
from rich.table import Table
from rich.text import Text

from kinverify.report.matrix import reference
from kinverify.report.units import display_unit, revolute as revolute_of
from kinverify.results import VerifyResult
from kinverify.suites.base import EXPLAINED, PERFORMANCE, Check, joint_unit

Column = tuple[str, dict]  # (plain-text header, rich column options)
NUMBER = {"justify": "right", "overflow": "fold"}  # one word, as wide as its column: never broken (fit_table)
NAME = {"overflow": "fold"}  # identifiers (property names, results): one word, never broken either
TEXT = {"overflow": "fold", "vertical": "top"}  # wraps between words, only when dropping columns leaves no room
GAP = 2  # spaces between columns
# backend and reference labels as the terminal prints them (the report and the JSON keep the full names)
SHORT = {"pinocchio-urdf": "pin-urdf", "pinocchio-mjcf": "pin-mjcf", "finite-difference": "finite-diff"}
UNITS = {"fraction of the move": "× move"}  # a goal relative to the move: 0.15 × move


def compact(x: float) -> str:
    """A number in at most 3 significant digits, exponent without padding: ``4.45e-16``, ``1e-9``,
    ``0.0422``, ``0``, ``inf``."""
    text = f"{x:.3g}"
    if "e" in text:
        mantissa, exponent = text.split("e")
        text = f"{mantissa}e{int(exponent)}"
    return text


def short(name: str) -> str:
    return SHORT.get(name, name)


def fit_table(
    console: Console,
    columns: Sequence[Column],
    rows: Sequence[Sequence[str]],
    optional: Sequence[str] = (),
    wrap_headers: bool = False,
    **table_options,
) -> Table:
    """A table of ``columns`` (plain headers) and ``rows`` (rich markup) as wide as the console
    allows. The ``optional`` headers are dropped in that order until every row fits on one line;
    only if none does even then, :data:`TEXT` cells wrap between words. No word (a number, a
    name) is ever broken; headers wrap (between words) only with ``wrap_headers``."""
    plain = [[h for h, _ in columns]] + [[Text.from_markup(c, emoji=False).plain for c in row] for row in rows]

    def header(i: int) -> int:
        words = columns[i][0].split() if wrap_headers else [columns[i][0]]
        return max((cell_len(w) for w in words), default=0)

    def whole(i: int) -> int:
        return max([header(i)] + [cell_len(r[i]) for r in plain[1:]])

    def least(i: int) -> int:  # the longest word of a text column; the whole cell of the others
        if columns[i][1] is not TEXT:
            return whole(i)
        return max([header(i)] + [cell_len(w) for r in plain[1:] for w in r[i].split()])

    def span(widths: dict[int, int]) -> int:
        return sum(widths.values()) + GAP * (len(widths) - 1)

    keep = list(range(len(columns)))
    for drop in [None, *optional]:
        keep = [i for i in keep if columns[i][0] != drop]
        widths = {i: whole(i) for i in keep}
        if span(widths) <= console.width:
            break
    else:  # too narrow even so: wrap the text columns that wrap the least
        widths = {i: least(i) for i in keep}
        spare = console.width - span(widths)
        while spare > 0 and any(widths[i] < whole(i) for i in keep):
            i = min((i for i in keep if widths[i] < whole(i)), key=lambda i: whole(i) - widths[i])
            widths[i] += 1
            spare -= 1
    table = Table(box=None, show_edge=False, pad_edge=False, padding=(0, GAP // 2), header_style="bold", **table_options)
    for i in keep:
        table.add_column(escape(columns[i][0]), width=widths[i], **columns[i][1])
    for row in rows:
        table.add_row(*(row[i] for i in keep))
    return table


def suite_lines(result: VerifyResult) -> list[tuple[str, str, str, str]]:
    """(mark, suite, what, time) per suite that ran checks or was skipped, then one line for the
    suites that only add a section to the report."""
    from kinverify.suites.registry import SUITES

    suite_of = {p.name: s.name for s in SUITES for p in s.properties}
    lines, report_only = [], []
    for s in SUITES:
        if s.name not in result.timings:
            continue
        checks = [c for c in result.checks if suite_of.get(c.property) == s.name]
        failed = [c for c in checks if c.decisive_failure]
        missed = [c for c in checks if not c.passed and not c.counts and c.kind == PERFORMANCE]
        explained = [c for c in checks if not c.passed and c.kind == EXPLAINED]
        sec = result.sections.get(s.name)
        summary = sec.summary if sec is not None else ""
        if failed:
            mark, what = "[bold red]✗[/]", f"[red]{len(failed)} of {len(checks)} checks fail[/]"
        elif explained:
            mark, what = "[yellow]![/]", f"{len(checks) - len(explained)} of {len(checks)} checks pass"
        elif checks:
            mark, what = "[green]✓[/]", f"{len(checks)} checks pass"
        elif summary.startswith("skipped"):
            mark, what = "·", escape(_first_clause(summary))
        else:
            report_only.append(s.name)
            continue
        if missed:
            what += f", [yellow]{len(missed)} below goal[/]"
        if explained:
            what += f", {len(explained)} differ as findings say"
        lines.append((mark, s.name, what, f"[dim]{result.timings[s.name]:.1f} s[/]"))
    if report_only:
        seconds = sum(result.timings[n] for n in report_only)
        lines.append(("·", "report", f"{', '.join(report_only)}: sections of the report", f"[dim]{seconds:.1f} s[/]"))
    return lines


def suites_grid(result: VerifyResult) -> Table:
    grid = Table.grid(padding=(0, 1))
    for opts in ({"no_wrap": True}, {"no_wrap": True}, {"overflow": "fold", "ratio": 1}, {"no_wrap": True, "justify": "right"}):
        grid.add_column(**opts)
    for line in suite_lines(result):
        grid.add_row(*line)
    return grid


def _first_clause(text: str) -> str:
    """``skipped: tracking needs a fixed base`` of a summary that goes on to explain why."""
    return text.split("; ")[0].split(". ")[0].split(" (")[0]


def _rows(result: VerifyResult, kind: str) -> list[tuple[str, str, list[Check]]]:
    """(property, backends, checks): one row per property; where checks do not pass, one row per
    backend they are blamed on (:func:`~kinverify.report.failures.blamed`) and one for the rest."""
    from kinverify.report.failures import blamed

    ref = reference(result)
    out: list[tuple[str, str, list[Check]]] = []
    by_prop: dict[str, list[Check]] = {}
    for c in result.checks:
        if (c.kind == PERFORMANCE) == (kind == PERFORMANCE):
            by_prop.setdefault(c.property, []).append(c)
    for prop, checks in by_prop.items():
        bad: dict[str, list[Check]] = {}
        for c in checks:
            if not c.passed:
                bad.setdefault(blamed(c, result, ref), []).append(c)
        out += [(prop, _who(cs, col), cs) for col, cs in bad.items()]
        rest = [c for c in checks if c.passed]
        if rest:
            out.append((prop, _who(rest), rest))
    return out


def _who(checks: list[Check], col: str = "") -> str:
    """The backends of a row, short: ``a vs b`` for one pair, ``flipped vs 6`` (every pair has
    ``col``), ``analytic vs 5`` (one against five others), ``5 vs finite-diff``, ``5 backends``
    (each against its goal) or ``25 pairs``."""
    pairs = list(dict.fromkeys(c.backends for c in checks))
    firsts, seconds = list(dict.fromkeys(p[0] for p in pairs)), list(dict.fromkeys(p[1] for p in pairs))
    if len(pairs) == 1:
        a, b = pairs[0]
        return short(a) if a == b else f"{short(a)} vs {short(b)}"
    if col and all(col in p for p in pairs):
        return f"{short(col)} vs {len({x for p in pairs for x in p if x != col})}"
    if len(firsts) == 1:
        return f"{short(firsts[0])} vs {len(seconds)}"
    if len(seconds) == 1:
        return f"{len(firsts)} vs {short(seconds[0])}"
    if all(a == b for a, b in pairs):
        return f"{len(pairs)} backends"
    return f"{len(pairs)} pairs"


def _mark(checks: list[Check]) -> str:
    """``ok``; ``FAIL`` (counts); ``finding`` (differs as a finding says, which counts); ``missed`` (a goal)."""
    if all(c.passed for c in checks):
        return "[green]ok[/]"
    if any(c.decisive_failure for c in checks):
        return "[bold red]FAIL[/]"
    return "[yellow]finding[/]" if any(c.kind == EXPLAINED and not c.passed for c in checks) else "[yellow]missed[/]"


def _worst(checks: list[Check]) -> Check:
    return max(checks, key=lambda c: (not c.passed, c.max_error / c.tolerance if c.tolerance else c.max_error))


def _unit(unit: str, revolute) -> str:
    """The unit as the terminal prints it: joint-space units in the model's terms (rad, m, rad|m),
    ``X or X/s`` as ``X(/s)``, a fraction of the move as ``× move``."""
    unit = display_unit(unit, revolute)
    first, _, second = unit.partition(" or ")
    if second == f"{first}/s":
        unit = f"{first}(/s)"
    return UNITS.get(unit, unit)


def _limit(value: float, unit: str) -> str:
    """``1e-9 m``: a tolerance or goal and its unit, one cell (a column each would take two more)."""
    return escape(f"{compact(value)} {unit}".rstrip())


def results_tables(result: VerifyResult, console: Console) -> list[tuple[str, Table]]:
    """``(title, table)``: the agreement table (its title says what was sampled) and the
    performance table (its first header says what it is)."""
    revolute = revolute_of(result)
    out = []
    rows = [(prop, who, checks, _worst(checks)) for prop, who, checks in _rows(result, "agreement")]
    if rows:
        cells = [
            [
                escape(prop),
                escape(who),
                str(len(checks)),
                escape(w.frame),
                compact(w.max_error),
                compact(max(c.p99_error for c in checks)),
                _limit(w.tolerance, _unit(w.unit, revolute)),
                _mark(checks),
            ]
            for prop, who, checks, w in rows
        ]
        cols = [
            ("property", NAME),
            ("backends", TEXT),
            ("checks", NUMBER),
            ("worst at", TEXT),
            ("max error", NUMBER),
            ("p99 error", NUMBER),
            ("tolerance", TEXT),
            ("", NAME),
        ]
        title = f"{result.model}: {result.samples} configurations, seed {result.seed}, reference {short(reference(result))}"
        out.append((escape(title), fit_table(console, cols, cells, optional=("p99 error", "checks", "worst at"))))
    from kinverify.suites.registry import properties

    props = properties()
    perf = [(prop, who, checks, _worst(checks)) for prop, who, checks in _rows(result, PERFORMANCE)]
    if perf:
        cells = [
            [
                escape(prop),
                escape(who),
                compact(w.max_error),
                _limit(w.tolerance, _unit(w.unit, revolute)),
                escape(props[prop].compares if prop in props else ""),
                _mark(checks),
            ]
            for prop, who, checks, w in perf
        ]
        cols = [
            ("performance", NAME),
            ("backends", TEXT),
            ("measured", NUMBER),
            ("goal", TEXT),
            ("what is measured", TEXT),
            ("result", NAME),
        ]
        out.append(("", fit_table(console, cols, cells, optional=("what is measured",))))
    return out


def print_result(result: VerifyResult, console: Console | None = None) -> None:
    console = console or text_console()
    console.print(suites_grid(result))
    for title, table in results_tables(result, console):
        if title:
            console.print(title, highlight=False)
        console.print(table)
    revolute = revolute_of(result)
    notes = Table.grid(padding=(0, 1))  # a tag, then the text with a hanging indent
    notes.add_column(no_wrap=True)
    notes.add_column(overflow="fold", ratio=1)
    for c in result.first_failures():
        q = ", ".join(f"{v:.6g}" for v in c.worst_q)
        notes.add_row(
            "[bold red]✗[/]",
            f"{c.property} ({escape(' vs '.join(c.backends))}): first disagreeing frame "
            f"[bold]{escape(c.frame)}[/], max error {c.max_error:.3e} {display_unit(c.unit, revolute)} at q = [{q}]",
        )
    style = {"error": "bold red", "warning": "yellow", "info": "cyan"}
    for f in result.findings:
        tag = "accepted" if f.accepted else f.severity
        notes.add_row(
            f"[{style[f.severity] if not f.accepted else 'dim'}]{tag}[/]", f"{f.kind} ({escape(f.label)}): {escape(f.message)}"
        )
    for note in result.notes:
        notes.add_row("[yellow]note[/]", escape(note))
    if notes.row_count:
        console.print(notes)
    console.print(f"verdict: {verdict_line(result, console.width - len('verdict: '))}", highlight=False)


def verdict_line(result: VerifyResult, width: int | None = None) -> str:
    """``PASS: ...`` / ``FAIL (...)`` / ``ERROR``: one line with what decided it; the backends by
    name when that fits in ``width`` columns (None: always), else how many."""
    n_fail, n_err, n_missed = len(result.failed), len(result.failing_findings), len(result.missed_goals)
    checks, findings, seconds = len(result.checks), len(result.findings), f"{result.duration_s:.1f} s"

    def line(what: str, missed: str) -> str:
        missed = missed if n_missed else ""
        if result.verdict == "pass":
            return f"[bold green]PASS[/]: {what}{missed}"
        if result.verdict == "error":
            return f"[bold red]ERROR[/] (internal error in {len(result.internal_errors)} suite(s)): {what}"
        parts = [f"{n_fail} of {checks} checks" if n_fail else "", f"{n_err} error findings" if n_err else ""]
        return f"[bold red]FAIL[/] ({', '.join(p for p in parts if p)}): {what}{missed}"

    goals = f"{n_missed} performance goal{'s' if n_missed != 1 else ''} missed"
    forms = [
        line(
            f"{checks} checks and {findings} findings across {', '.join(result.backends)} in {seconds}",
            f"; {goals} (not counted)",
        ),
        line(
            f"{checks} checks and {findings} findings across {len(result.backends)} backends in {seconds}",
            f"; {goals} (not counted)",
        ),
        line(
            f"{checks} checks, {findings} findings, {len(result.backends)} backends, {seconds}",
            f"; {goals.replace('performance ', '')}",
        ),
    ]
    return next((f for f in forms if width is None or cell_len(Text.from_markup(f, emoji=False).plain) <= width), forms[-1])


def track_table(spec, result, console: Console) -> Table:
    """``kinverify track``'s metrics per controller, units after the joint types (rad, m)."""
    u = joint_unit(j.type == "revolute" for j in spec.joints)
    t = result.trajectory
    cols = [
        ("controller", NAME),
        (f"RMS error (motion) [{u}]", NUMBER),
        (f"max error (whole run) [{u}]", NUMBER),
        (f"error at end of motion [{u}]", NUMBER),
        ("tool path deviation [m]", NUMBER),
        (f"overshoot [{u}]", NUMBER),
        ("settling time [s]", NUMBER),
        (f"residual speed [{u}/s]", NUMBER),
        (f"speed at end of hold [{u}/s]", NUMBER),
        ("result", TEXT),
    ]
    rows = [
        [
            escape(m.controller),
            f"{m.rms_error:.3e}",
            f"{m.max_error:.3e}",
            f"{m.final_error:.3e}",
            f"{m.ee_path_deviation:.3e}",
            f"{m.overshoot:.3e}",
            "-" if m.settling_time is None else f"{m.settling_time:.3f}",
            f"{m.residual_speed:.3e}",
            f"{m.final_speed:.3e}",
            "[green]ok[/]" if m.passed else "[bold red]FAIL[/]",
        ]
        for m in result.metrics
    ]
    return fit_table(
        console,
        cols,
        rows,
        optional=(
            f"speed at end of hold [{u}/s]",
            f"overshoot [{u}]",
            "settling time [s]",
            "tool path deviation [m]",
            f"error at end of motion [{u}]",
        ),
        wrap_headers=True,
        title=f"kinverify track: {spec.name}, {t.duration:g} s motion + {t.hold:g} s hold",
    )
