"""Terminal summary with rich: one row per (property, backend pair), worst frame shown."""

from __future__ import annotations

from rich.console import Console
from rich.table import Table

from kinverify.results import VerifyResult


def _group(result: VerifyResult):
    groups: dict[tuple, list] = {}
    for c in result.checks:
        groups.setdefault((c.property, c.backends), []).append(c)
    return groups


def print_result(result: VerifyResult, console: Console | None = None) -> None:
    console = console or Console()
    table = Table(title=f"kinverify: {result.model} ({result.samples} configurations, seed {result.seed})")
    for col in ("property", "backends", "frames", "worst frame", "max error", "p99 error", "tolerance", ""):
        table.add_column(col, justify="right" if "error" in col or col == "tolerance" else "left")
    for (prop, pair), checks in _group(result).items():
        worst = max(checks, key=lambda c: c.max_error)
        ok = all(c.passed for c in checks)
        mark = "[green]ok[/]" if ok else "[bold red]FAIL[/]" if any(c.counts for c in checks) else "[yellow]below goal[/]"
        table.add_row(prop, " vs ".join(pair), str(len(checks)), worst.frame, f"{worst.max_error:.2e}",
                      f"{max(c.p99_error for c in checks):.2e}", f"{worst.tolerance:.0e} {worst.unit}",
                      mark)
    console.print(table)
    for c in result.first_failures():
        q = ", ".join(f"{v:.6g}" for v in c.worst_q)
        console.print(f"[red]first disagreeing frame[/] for {c.property} ({' vs '.join(c.backends)}): "
                      f"[bold]{c.frame}[/], max error {c.max_error:.3e} {c.unit} at q = [{q}]")
    style = {"error": "bold red", "warning": "yellow", "info": "cyan"}
    for f in result.findings:
        tag = "accepted" if f.accepted else f.severity
        console.print(f"[{style[f.severity] if not f.accepted else 'dim'}]{tag}[/] {f.kind} ({f.label}): {f.message}")
    for note in result.notes:
        console.print(f"[yellow]note:[/] {note}")
    for c in result.missed_goals:
        console.print(f"[yellow]below its goal (performance, not counted):[/] {c.property} ({' vs '.join(c.backends)}): "
                      f"{c.max_error:.3g} {c.unit} against a goal of {c.tolerance:.3g}")
    console.print(f"verdict: {verdict_line(result)}")


def verdict_line(result: VerifyResult) -> str:
    """``PASS: ...`` / ``FAIL (...)`` / ``ERROR``: one line with what decided it."""
    n_fail, n_err = len(result.failed), len(result.failing_findings)
    what = f"{len(result.checks)} checks and {len(result.findings)} findings across {', '.join(result.backends)} in {result.duration_s:.1f} s"
    if result.verdict == "pass":
        return f"[bold green]PASS[/]: {what}"
    if result.verdict == "error":
        return f"[bold red]ERROR[/] (internal error in {len(result.internal_errors)} suite(s)): {what}"
    parts = [f"{n_fail} of {len(result.checks)} checks" if n_fail else "", f"{n_err} error findings" if n_err else ""]
    return f"[bold red]FAIL[/] ({', '.join(p for p in parts if p)}): {what}"
