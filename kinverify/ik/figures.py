"""Figures of the ``ik`` report section: success rate per solver and backend, and every target's
solve time per solver (one axes each: a panel per solver cost seconds to draw).

Both are drawn only from :func:`solver_data` records, which the suite keeps in its section
(``section["solvers"]``), so a saved JSON holds the numbers behind every bar and bin and
:func:`ik_figures` redraws the same SVG from them (the SVG output is deterministic).
"""

from __future__ import annotations

import numpy as np

from kinverify.report.plots import RC, figure_entry, new_figure
from kinverify.suites.base import Figure

MIN_MS = 1e-6  # a solve time of 0 (timer resolution) is drawn at this value on the log axis


def solver_data(sol, ok, own_ok) -> dict:
    """Plain record of one solver run: ``ok`` within the suite's tolerance, ``own_ok`` within the
    solver's own; per-target solve times in ms (4 significant digits)."""
    return {
        "solver": sol.solver,
        "backend": sol.backend,
        "targets": int(len(sol)),
        "solved": int(np.sum(ok)),
        "solved_own": int(np.sum(own_ok)),
        "batched": bool(sol.batched),
        "time_ms": [float(f"{t:.4g}") for t in np.asarray(sol.time_s, dtype=float) * 1e3],
    }


def _label(d: dict) -> str:
    return f"{d['solver']} / {d['backend']}"


def success_figure(solvers: list[dict], tol_pos: float, tol_rot: float) -> Figure:
    """Horizontal bars: percentage of targets solved within the suite's tolerance and within the
    solver's own tolerance, one pair of bars per solver/backend."""
    import matplotlib

    n = len(solvers)
    with matplotlib.rc_context(RC):
        fig = new_figure(figsize=(7.0, 0.5 * n + 1.1))
        ax = fig.add_subplot(1, 1, 1)
        y = np.arange(n)[::-1]
        rate = [100.0 * d["solved"] / d["targets"] if d["targets"] else 0.0 for d in solvers]
        own = [100.0 * d["solved_own"] / d["targets"] if d["targets"] else 0.0 for d in solvers]
        ax.barh(y + 0.2, rate, height=0.38, color="#1565c0", label=f"within {tol_pos:g} m / {tol_rot:g} rad (checked)")
        ax.barh(y - 0.2, own, height=0.38, color="#90a4ae", label="within the solver's own tolerance")
        for yy, r, o, d in zip(y, rate, own, solvers, strict=True):
            ax.text(min(r, 100) + 1, yy + 0.2, f"{r:.0f} % ({d['solved']}/{d['targets']})", va="center", fontsize=7)
            ax.text(min(o, 100) + 1, yy - 0.2, f"{o:.0f} %", va="center", fontsize=7, color="#546e7a")
        ax.set_yticks(y, [_label(d) for d in solvers])
        ax.set_xlim(0, 125)
        ax.set_xticks([0, 20, 40, 60, 80, 100])
        ax.set_xlabel("targets solved [%]")
        ax.grid(True, axis="x", alpha=0.3)
        ax.legend(fontsize=7, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=2, frameon=False)
        fig.tight_layout()
        return figure_entry(
            fig,
            "IK success rate per solver and backend",
            f"share of the reachable targets solved within {tol_pos:g} m / {tol_rot:g} rad (dark: "
            "1 − ik.failure_rate) and within the solver's own stopping tolerance (grey)",
        )


def time_figure(solvers: list[dict]) -> Figure:
    """One axes, one row per solver/backend, sharing a log time axis: every target's solve time
    (dots), the median (long red bar, its value at the right) and the 95th percentile (short bar)."""
    import matplotlib
    import matplotlib.ticker

    n = len(solvers)
    y = np.arange(n)[::-1]
    with matplotlib.rc_context(RC):
        fig = new_figure(figsize=(7.0, 0.42 * n + 1.0))
        ax = fig.add_subplot(1, 1, 1)
        for yy, d in zip(y, solvers, strict=True):
            t = np.maximum(np.asarray(d["time_ms"], dtype=float), MIN_MS)
            t = t[np.isfinite(t)]
            if not len(t):
                continue
            jitter = np.linspace(-0.25, 0.25, len(t)) if len(t) > 1 else np.zeros(1)
            ax.scatter(t, yy + jitter, s=4, color="#1565c0" if d["solver"] == "lm" else "#90a4ae", linewidths=0)
            med, p95 = float(np.median(t)), float(np.percentile(t, 95))
            ax.plot([med, med], [yy - 0.35, yy + 0.35], color="#c62828", lw=1.5)
            ax.plot([p95, p95], [yy - 0.2, yy + 0.2], color="#c62828", lw=0.8)
            ax.text(
                1.01,
                yy,
                f"median {med:.3g} ms" + (" (batch / N)" if d["batched"] else ""),
                transform=ax.get_yaxis_transform(),
                va="center",
                fontsize=6.5,
            )
        ax.set_yticks(y, [_label(d) for d in solvers])
        ax.set_ylim(-0.6, n - 0.4)
        ax.set_xscale("log")
        # plain decimal tick labels: the default 10^k ones go through mathtext, the slowest part of drawing
        ax.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        ax.minorticks_off()
        ax.set_xlabel("solve time per target [ms]")
        ax.grid(True, axis="x", alpha=0.3)
        fig.tight_layout()
        return figure_entry(
            fig,
            "IK solve time per target",
            "each target's solve time (dots) per solver and backend on a log axis; long red bar: median "
            "(value at the right), short red bar: 95th percentile. Batched solvers solve all targets in one "
            "call and report the batch time divided by the number of targets, so all their solves share one "
            "value. Timings are not asserted.",
        )


def ik_figures(solvers: list[dict], tol_pos: float, tol_rot: float) -> list[Figure]:
    """Both figures from the section's ``solvers`` records (none when there are none)."""
    if not solvers:
        return []
    return [success_figure(solvers, tol_pos, tol_rot), time_figure(solvers)]
