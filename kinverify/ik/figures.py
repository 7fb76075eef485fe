"""The figure of the ``ik`` report section: success rate and the distribution of solve times per
solver and backend, side by side in one figure (one drawing: cheap next to a panel per solver).

It is drawn only from :func:`solver_data` records, which the suite keeps in its section
(``section["solvers"]``), so a saved JSON holds the numbers behind every bar and bin and
:func:`ik_figures` redraws the same SVG from them (the SVG output is deterministic).
"""

from __future__ import annotations

import numpy as np

from kinverify.report.plots import RC, figure_entry, new_figure

MIN_MS = 1e-6  # a solve time of 0 (timer resolution) is drawn at this value on the log axis


def solver_data(sol, ok, own_ok) -> dict:
    """Plain record of one solver run: ``ok`` within the suite's tolerance, ``own_ok`` within the
    solver's own; per-target solve times in ms (4 significant digits)."""
    return {"solver": sol.solver, "backend": sol.backend, "targets": int(len(sol)), "solved": int(np.sum(ok)),
            "solved_own": int(np.sum(own_ok)), "batched": bool(sol.batched),
            "time_ms": [float(f"{t:.4g}") for t in np.asarray(sol.time_s, dtype=float) * 1e3]}


def _label(d: dict) -> str:
    return f"{d['solver']} / {d['backend']}"


def ik_figure(solvers: list[dict], tol_pos: float, tol_rot: float) -> dict:
    """One figure, one row per solver/backend, two panels sharing the rows. Left: percentage of
    targets solved within the suite's tolerance (dark) and within the solver's own (grey). Right:
    every target's solve time on a log axis (dots), its median (red bar) and 95th percentile
    (red tick)."""
    import matplotlib
    import matplotlib.ticker

    n = len(solvers)
    y = np.arange(n)[::-1]
    with matplotlib.rc_context(RC):
        fig = new_figure(figsize=(9.0, 0.42 * n + 1.3))
        left, right = fig.subplots(1, 2, sharey=True, gridspec_kw={"width_ratios": [1, 1.4]})
        rate = [100.0 * d["solved"] / d["targets"] if d["targets"] else 0.0 for d in solvers]
        own = [100.0 * d["solved_own"] / d["targets"] if d["targets"] else 0.0 for d in solvers]
        left.barh(y + 0.2, rate, height=0.38, color="#1565c0", label=f"within {tol_pos:g} m / {tol_rot:g} rad (checked)")
        left.barh(y - 0.2, own, height=0.38, color="#90a4ae", label="within the solver's own tolerance")
        for yy, r, d in zip(y, rate, solvers):
            left.text(min(r, 100) + 1, yy + 0.2, f"{r:.0f} % ({d['solved']}/{d['targets']})", va="center", fontsize=7)
        left.set_yticks(y, [_label(d) for d in solvers])
        left.set_xlim(0, 135)
        left.set_xticks([0, 50, 100])
        left.set_xlabel("targets solved [%]")
        left.legend(fontsize=6.5, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncol=1, frameon=False)
        times = [np.maximum(np.asarray(d["time_ms"], dtype=float), MIN_MS) for d in solvers]
        for yy, t, d in zip(y, times, solvers):
            t = t[np.isfinite(t)]
            if not len(t):
                continue
            jitter = np.linspace(-0.25, 0.25, len(t)) if len(t) > 1 else np.zeros(1)
            right.scatter(t, yy + jitter, s=4, color="#1565c0" if d["solver"] == "lm" else "#90a4ae", linewidths=0)
            med, p95 = float(np.median(t)), float(np.percentile(t, 95))
            right.plot([med, med], [yy - 0.35, yy + 0.35], color="#c62828", lw=1.5)
            right.plot([p95, p95], [yy - 0.2, yy + 0.2], color="#c62828", lw=0.8)
            right.text(1.01, yy, f"{med:.3g} ms" + (" (batch / N)" if d["batched"] else ""), transform=right.get_yaxis_transform(),
                       va="center", fontsize=6.5)
        right.set_xscale("log")
        # plain decimal tick labels: the default 10^k labels go through mathtext, the slowest part of drawing
        right.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
        right.set_xlabel("solve time per target [ms]")
        for ax in (left, right):
            ax.grid(True, axis="x", alpha=0.3)
        right.minorticks_off()
        fig.tight_layout()
        return figure_entry(fig, "IK success rate and solve time per solver and backend",
                            f"left: share of the reachable targets solved within {tol_pos:g} m / {tol_rot:g} rad (what "
                            "ik.success_rate checks; dark) and within the solver's own stopping tolerance (grey); right: "
                            "each target's solve time (dots), median (long red bar, value at the right) and 95th percentile "
                            "(short red bar). Batched solvers solve all targets in one call and report the batch time "
                            "divided by the number of targets. Timings are not asserted.")


def ik_figures(solvers: list[dict], tol_pos: float, tol_rot: float) -> list[dict]:
    """The section's figure from its ``solvers`` records (none when there are none)."""
    if not solvers:
        return []
    return [ik_figure(solvers, tol_pos, tol_rot)]
