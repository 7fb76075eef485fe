"""Figures of the ``ik`` report section: success rate per solver and backend, and the
distribution of solve times per solver.

Both are drawn only from :func:`solver_data` records, which the suite keeps in its section
(``section["solvers"]``), so a saved JSON holds the numbers behind every bar and bin and
:func:`ik_figures` redraws the same SVG from them (the SVG output is deterministic).
"""

from __future__ import annotations

import math

import numpy as np

from kinverify.report.plots import RC, figure_entry, new_figure

MIN_MS = 1e-6  # a solve time of 0 (timer resolution) is drawn at this value on the log axis
BINS = 30


def solver_data(sol, ok, own_ok) -> dict:
    """Plain record of one solver run: ``ok`` within the suite's tolerance, ``own_ok`` within the
    solver's own; per-target solve times in ms (4 significant digits)."""
    return {"solver": sol.solver, "backend": sol.backend, "targets": int(len(sol)), "solved": int(np.sum(ok)),
            "solved_own": int(np.sum(own_ok)), "batched": bool(sol.batched),
            "time_ms": [float(f"{t:.4g}") for t in np.asarray(sol.time_s, dtype=float) * 1e3]}


def _label(d: dict) -> str:
    return f"{d['solver']} / {d['backend']}"


def success_figure(solvers: list[dict], tol_pos: float, tol_rot: float) -> dict:
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
        for yy, r, o, d in zip(y, rate, own, solvers):
            ax.text(min(r, 100) + 1, yy + 0.2, f"{r:.0f} % ({d['solved']}/{d['targets']})", va="center", fontsize=7)
            ax.text(min(o, 100) + 1, yy - 0.2, f"{o:.0f} %", va="center", fontsize=7, color="#546e7a")
        ax.set_yticks(y, [_label(d) for d in solvers])
        ax.set_xlim(0, 125)
        ax.set_xticks([0, 20, 40, 60, 80, 100])
        ax.set_xlabel("targets solved [%]")
        ax.grid(True, axis="x", alpha=0.3)
        ax.legend(fontsize=7, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=2, frameon=False)
        fig.tight_layout()
        return figure_entry(fig, "IK success rate per solver and backend",
                            f"share of the reachable targets solved within {tol_pos:g} m / {tol_rot:g} rad (what ik.success_rate "
                            "checks; dark) and within the solver's own stopping tolerance (grey)")


def time_figure(solvers: list[dict]) -> dict:
    """Small multiples, one per solver/backend, sharing a log time axis: histogram of per-target
    solve times with the median (solid) and 95th percentile (dashed) marked."""
    import matplotlib

    times = [np.maximum(np.asarray(d["time_ms"], dtype=float), MIN_MS) for d in solvers]
    finite = np.concatenate([t[np.isfinite(t)] for t in times]) if times else np.array([])
    lo, hi = (float(finite.min()), float(finite.max())) if len(finite) else (1e-3, 1.0)
    lo, hi = lo / 1.5, max(hi * 1.5, lo * 10)
    edges = np.geomspace(lo, hi, BINS + 1)
    cols = 2 if len(solvers) > 1 else 1
    rows = math.ceil(len(solvers) / cols)
    with matplotlib.rc_context(RC):
        fig = new_figure(figsize=(4.2 * cols, 1.55 * rows + 0.6))
        axes = fig.subplots(rows, cols, sharex=True, squeeze=False).ravel()
        for ax, d, t in zip(axes, solvers, times):
            t = t[np.isfinite(t)]
            ax.hist(t, bins=edges, color="#1565c0" if d["solver"] == "lm" else "#90a4ae")
            if len(t):
                med, p95 = float(np.median(t)), float(np.percentile(t, 95))
                ax.axvline(med, color="#c62828", lw=1.2, label=f"median {med:.3g} ms")
                ax.axvline(p95, color="#c62828", lw=1.2, ls="--", label=f"p95 {p95:.3g} ms")
                ax.legend(fontsize=6, loc="upper right")
            ax.set_xscale("log")
            ax.set_title(_label(d) + (" (batched: batch time / targets)" if d["batched"] else ""), fontsize=8)
            ax.set_ylabel("targets")
            ax.grid(True, which="major", alpha=0.3)
            ax.minorticks_off()
        for ax in axes[len(solvers):]:
            ax.set_visible(False)
        for ax in axes[-cols:]:
            ax.set_xlabel("solve time per target [ms]")
            ax.xaxis.set_tick_params(labelbottom=True)
        fig.tight_layout()
        return figure_entry(fig, "IK solve time per target",
                            "histogram per solver and backend on a log time axis; solid line: median, dashed: 95th "
                            "percentile. Batched solvers solve all targets in one call and report the batch time divided "
                            "by the number of targets, so all their solves share one value. Timings are not asserted.")


def ik_figures(solvers: list[dict], tol_pos: float, tol_rot: float) -> list[dict]:
    """Both figures from the section's ``solvers`` records (none when there are none)."""
    if not solvers:
        return []
    return [success_figure(solvers, tol_pos, tol_rot), time_figure(solvers)]
