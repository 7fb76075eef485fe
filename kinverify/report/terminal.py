"""Terminal summary with rich: one row per (property, backend pair), worst frame shown."""

from __future__ import annotations

from rich.console import Console
from rich.table import Table

from ..results import VerifyResult


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
        table.add_row(prop, " vs ".join(pair), str(len(checks)), worst.frame, f"{worst.max_error:.2e}",
                      f"{max(c.p99_error for c in checks):.2e}", f"{worst.tolerance:.0e} {worst.unit}",
                      "[green]ok[/]" if ok else "[bold red]FAIL[/]")
    console.print(table)
    for c in result.first_failures():
        q = ", ".join(f"{v:.6g}" for v in c.worst_q)
        console.print(f"[red]first disagreeing frame[/] for {c.property} ({' vs '.join(c.backends)}): "
                      f"[bold]{c.frame}[/], max error {c.max_error:.3e} {c.unit} at q = [{q}]")
    for note in result.notes:
        console.print(f"[yellow]note:[/] {note}")
    n_fail = len(result.failed)
    verdict = "[bold green]PASS[/]" if result.passed else f"[bold red]FAIL[/] ({n_fail} of {len(result.checks)} checks)"
    console.print(f"verdict: {verdict}: {len(result.checks)} checks across {', '.join(result.backends)} in {result.duration_s:.1f} s")
