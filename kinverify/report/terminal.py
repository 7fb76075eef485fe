"""Terminal summary with rich, at the console's width: one line per suite, then the agreement
table (one row per property; one per property and backend where something fails) and the
performance table (goals, not counted unless gated), then what failed and the verdict.

Tables fit the terminal: text columns wrap, numbers never break, and when even that is too wide
the least useful columns are dropped (:func:`fit_table`).
"""

from __future__ import annotations

from typing import Sequence

from rich import box
from rich.console import Console
from rich.markup import escape
from rich.table import Table
from rich.text import Text

from kinverify.report.matrix import column_of, reference
from kinverify.suites.base import EXPLAINED, PERFORMANCE
from kinverify.results import VerifyResult
from kinverify.report.units import display_unit, revolute as revolute_of
from kinverify.suites.base import PERFORMANCE, Check, joint_unit

Column = tuple[str, dict]  # (plain-text header, rich column options)
NUMBER = {"justify": "right", "overflow": "fold"}  # one word each: never wider than its column (fit_table)
NAME = {"overflow": "fold"}  # identifiers (property names): one word, never broken either
TEXT = {"overflow": "fold"}  # wraps between words; folds only a word longer than the column


def fit_table(console: Console, columns: Sequence[Column], rows: Sequence[Sequence[str]], optional: Sequence[str] = (),
              **table_options) -> Table:
    """A table of ``columns`` (plain headers) and ``rows`` (rich markup) as wide as the console
    allows: cells and headers wrap between words, no word (a number, a name) is ever broken, and
    the ``optional`` headers are dropped in that order until the table fits."""
    plain = [[h for h, _ in columns]] + [[Text.from_markup(c).plain for c in row] for row in rows]

    def least(i: int) -> int:  # the longest word of the column
        return max(max((len(w) for w in r[i].split()), default=0) for r in plain)

    keep = list(range(len(columns)))
    for drop in [None, *optional]:
        keep = [i for i in keep if columns[i][0] != drop]
        if sum(least(i) for i in keep) + 3 * len(keep) + 1 <= console.width:
            break
    widths = {i: least(i) for i in keep}
    most = {i: max(len(r[i]) for r in plain) for i in keep}
    spare = console.width - 3 * len(keep) - 1 - sum(widths.values())
    while spare > 0 and any(widths[i] < most[i] for i in keep):  # widen the column that wraps most
        i = min((i for i in keep if widths[i] < most[i]), key=lambda i: most[i] - widths[i])  # unwrap what is nearly whole
        widths[i] += 1
        spare -= 1
    table = Table(box=box.SIMPLE_HEAD, **table_options)
    for i in keep:
        table.add_column(escape(columns[i][0]), width=widths[i], **columns[i][1])
    for row in rows:
        table.add_row(*(row[i] for i in keep))
    return table


def suite_lines(result: VerifyResult) -> list[tuple[str, str, str, str]]:
    """(mark, suite, what, time) per suite that ran: its checks and how they did."""
    from kinverify.suites.registry import SUITES

    suite_of = {p.name: s.name for s in SUITES for p in s.properties}
    lines = []
    for s in SUITES:
        if s.name not in result.timings:
            continue
        checks = [c for c in result.checks if suite_of.get(c.property) == s.name]
        failed = [c for c in checks if c.decisive_failure]
        missed = [c for c in checks if not c.passed and not c.counts and c.kind == PERFORMANCE]
        explained = [c for c in checks if not c.passed and c.kind == EXPLAINED]
        if failed:
            mark, what = "[bold red]✗[/]", f"[red]{len(failed)} of {len(checks)} checks fail[/]"
        elif explained:
            mark, what = "[yellow]![/]", f"{len(checks) - len(explained)} of {len(checks)} checks pass"
        elif checks:
            mark, what = "[green]✓[/]", f"{len(checks)} checks pass"
        else:
            sec = result.sections.get(s.name)
            mark, what = "·", escape(_first_sentence(sec.summary)) if sec is not None and sec.summary else "report only"
        if missed:
            what += f", [yellow]{len(missed)} below goal[/]"
        if explained:
            what += f", {len(explained)} differ as a finding says (the finding counts)"
        lines.append((mark, s.name, what, f"[dim]{result.timings[s.name]:.1f} s[/]"))
    return lines


def suites_grid(result: VerifyResult) -> Table:
    grid = Table.grid(padding=(0, 1))
    for opts in ({"no_wrap": True}, {"no_wrap": True}, {"overflow": "fold", "ratio": 1}, {"no_wrap": True, "justify": "right"}):
        grid.add_column(**opts)
    for line in suite_lines(result):
        grid.add_row(*line)
    return grid


def _first_sentence(text: str) -> str:
    return text.split("; ")[0].split(". ")[0]


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
    """The backends of a row: ``a vs b`` for one pair, ``flipped vs 6 backends`` (every pair
    has ``col``), ``analytic vs 5 backends``, ``5 backends vs finite-difference``, ``5
    backends`` (each against its goal) or ``25 pairs``."""
    pairs = list(dict.fromkeys(c.backends for c in checks))
    firsts, seconds = list(dict.fromkeys(p[0] for p in pairs)), list(dict.fromkeys(p[1] for p in pairs))
    if len(pairs) == 1:
        a, b = pairs[0]
        return a if a == b else f"{a} vs {b}"
    if col and all(col in p for p in pairs):
        return f"{col} vs {len({x for p in pairs for x in p if x != col})} backends"
    if len(firsts) == 1:
        return f"{firsts[0]} vs {len(seconds)} backends"
    if len(seconds) == 1:
        return f"{len(firsts)} backends vs {seconds[0]}"
    if all(a == b for a, b in pairs):
        return f"{len(pairs)} backends"
    return f"{len(pairs)} pairs"


def _mark(checks: list[Check]) -> str:
    if all(c.passed for c in checks):
        return "[green]ok[/]"
    return "[bold red]FAIL[/]" if any(c.decisive_failure for c in checks) else "[yellow]below goal[/]"


def _worst(checks: list[Check]) -> Check:
    return max(checks, key=lambda c: (not c.passed, c.max_error / c.tolerance if c.tolerance else c.max_error))


def results_tables(result: VerifyResult, console: Console) -> list[Table]:
    revolute = revolute_of(result)
    title = f"{result.model}: {result.samples} configurations, seed {result.seed}; reference {reference(result)}"
    rows = []
    for prop, who, checks in _rows(result, "agreement"):
        w = _worst(checks)
        unit = escape(display_unit(w.unit, revolute))
        rows.append([escape(prop), escape(who), str(len(checks)), escape(w.frame), f"{w.max_error:.2e}",
                     f"{max(c.p99_error for c in checks):.2e}", f"{w.tolerance:.0e} {unit}", _mark(checks)])
    cols = [("property", NAME), ("backends", TEXT), ("checks", NUMBER), ("worst at", TEXT), ("max error", NUMBER),
            ("p99 error", NUMBER), ("tolerance", TEXT), ("result", TEXT)]
    tables = [fit_table(console, cols, rows, optional=("p99 error", "checks", "worst at"), title=title)] if rows else []
    perf = []
    from kinverify.suites.registry import properties

    props = properties()
    for prop, who, checks in _rows(result, PERFORMANCE):
        w = _worst(checks)
        what = props[prop].compares if prop in props else ""
        unit = escape(display_unit(w.unit, revolute))
        perf.append([escape(prop), escape(who), f"{w.max_error:.3g}", f"{w.tolerance:.3g} {unit}", escape(what), _mark(checks)])
    if perf:
        cols = [("property", NAME), ("solver / controller", TEXT), ("measured", NUMBER), ("goal", TEXT),
                ("what is measured", TEXT), ("result", TEXT)]
        tables.append(fit_table(console, cols, perf, optional=("what is measured",),
                                title="performance: shown against goals, not counted unless --gate"))
    return tables


def print_result(result: VerifyResult, console: Console | None = None) -> None:
    console = console or Console()
    console.print(suites_grid(result))
    for table in results_tables(result, console):
        console.print(table)
    revolute = revolute_of(result)
    for c in result.first_failures():
        q = ", ".join(f"{v:.6g}" for v in c.worst_q)
        console.print(f"[red]first disagreeing frame[/] for {c.property} ({escape(' vs '.join(c.backends))}): "
                      f"[bold]{escape(c.frame)}[/], max error {c.max_error:.3e} {display_unit(c.unit, revolute)} at q = [{q}]")
    style = {"error": "bold red", "warning": "yellow", "info": "cyan"}
    for f in result.findings:
        tag = "accepted" if f.accepted else f.severity
        console.print(f"[{style[f.severity] if not f.accepted else 'dim'}]{tag}[/] {f.kind} ({escape(f.label)}): {escape(f.message)}")
    for note in result.notes:
        console.print(f"[yellow]note:[/] {escape(note)}")
    console.print(f"verdict: {verdict_line(result)}")


def verdict_line(result: VerifyResult) -> str:
    """``PASS: ...`` / ``FAIL (...)`` / ``ERROR``: one line with what decided it."""
    n_fail, n_err = len(result.failed), len(result.failing_findings)
    what = f"{len(result.checks)} checks and {len(result.findings)} findings across {', '.join(result.backends)} in {result.duration_s:.1f} s"
    missed = f"; {len(result.missed_goals)} performance goal(s) missed (not counted)" if result.missed_goals else ""
    if result.verdict == "pass":
        return f"[bold green]PASS[/]: {what}{missed}"
    if result.verdict == "error":
        return f"[bold red]ERROR[/] (internal error in {len(result.internal_errors)} suite(s)): {what}"
    parts = [f"{n_fail} of {len(result.checks)} checks" if n_fail else "", f"{n_err} error findings" if n_err else ""]
    return f"[bold red]FAIL[/] ({', '.join(p for p in parts if p)}): {what}{missed}"


def track_table(spec, result, console: Console) -> Table:
    """``kinverify track``'s metrics per controller, units after the joint types (rad, m)."""
    u = joint_unit(j.type == "revolute" for j in spec.joints)
    t = result.trajectory
    cols = [("controller", NAME), (f"RMS error (motion) [{u}]", NUMBER), (f"max error (whole run) [{u}]", NUMBER),
            (f"error at end of motion [{u}]", NUMBER), ("tool path deviation [m]", NUMBER), (f"overshoot [{u}]", NUMBER),
            ("settling time [s]", NUMBER), (f"residual speed [{u}/s]", NUMBER), (f"speed at end of hold [{u}/s]", NUMBER),
            ("result", TEXT)]
    rows = [[escape(m.controller), f"{m.rms_error:.3e}", f"{m.max_error:.3e}", f"{m.final_error:.3e}", f"{m.ee_path_deviation:.3e}",
             f"{m.overshoot:.3e}", "-" if m.settling_time is None else f"{m.settling_time:.3f}", f"{m.residual_speed:.3e}",
             f"{m.final_speed:.3e}", "[green]ok[/]" if m.passed else "[bold red]FAIL[/]"] for m in result.metrics]
    return fit_table(console, cols, rows, optional=(f"speed at end of hold [{u}/s]", f"overshoot [{u}]", "settling time [s]",
                                                    "tool path deviation [m]", f"error at end of motion [{u}]"),
                     title=f"kinverify track: {spec.name}, {t.duration:g} s motion + {t.hold:g} s hold")
