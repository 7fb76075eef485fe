"""The ``ik`` property suite of ``kinverify verify``.

Targets are FK (reference backend) of uniform random configurations inside the limits: full
pose for arms with >= 6 joints, position only below. The LM solver runs on every backend with
analytic Jacobians; the seed's solver runs next to it for the report only (it is not expected
to reach 1e-6). Checks: ``ik.success_rate``, ``ik.limits``, ``ik.cross_fk`` (each solution
through every other backend's FK), ``ik.closed_form`` (arm3-shaped specs), ``ik.unreachable``.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ..results import Check
from .closed_form import Arm3ClosedForm
from .figures import ik_figures, solver_data
from .frame_model import FrameModel, residuals
from .lm import IKOptions, IKSolutions, solve_lm
from .seed_pinv import solve_seed_pinv
from .targets import reachable_targets, unreachable_targets

if TYPE_CHECKING:
    from ..verify import SuiteResult

DEFAULT_TARGETS = 50
DEFAULT_UNREACHABLE = 5
TOL_POS, TOL_ROT = 1e-6, 1e-6  # m, rad
TOL_JOINT = 1e-6  # rad: numeric solution against the nearest closed-form branch (+ residual/σ_min)
ALLOWED_FAILURES = 0.001  # fraction of reachable targets a solver may miss


def ik_suite(ctx) -> "SuiteResult":
    from ..verify import SuiteResult

    opts, src = ctx.options, ctx.sources
    n = int(opts.extra.get("ik_targets", DEFAULT_TARGETS))
    section = {"title": "Inverse kinematics", "summary": "", "tables": [], "figures": [], "notes": []}
    if n <= 0 or not src.joint_names:
        section["summary"] = "skipped (--ik-targets 0)"
        return SuiteResult([], section)
    frame, dof = src.frames[-1], len(src.joint_names)
    position_only = dof < 6
    lower, upper = np.asarray(src.lower), np.asarray(src.upper)
    q_gen, targets = reachable_targets(ctx.backends[opts.reference], frame, lower, upper, n, opts.seed + 4)
    solvers = [b for b in ctx.backends.values() if b.jacobian_method == "analytic"]
    closed = _closed_form(src, frame)
    checks, rows, failures, plotted = [], [], [], []
    ik_opts = IKOptions(seed=opts.seed)
    for backend in solvers:
        model = FrameModel(backend, frame, src.revolute)
        sol = solve_lm(model, targets, lower, upper, position_only, ik_opts)
        ok = sol.solved(TOL_POS, TOL_ROT)
        checks.append(_success_check(sol, ok, frame))
        checks.append(_limits_check(sol, lower, upper, frame))
        checks += _cross_checks(sol, ok, targets, ctx.backends, frame)
        if closed is not None:
            checks.append(_closed_form_check(sol, ok, targets, closed, frame, model))
        rows.append(_row(sol, ok))
        plotted.append(solver_data(sol, ok, sol.success))
        if backend.name == opts.reference:
            seed = solve_seed_pinv(model, targets, lower, upper)  # the baseline, once (not checked)
            pos, rot = residuals(model.poses(seed.q), targets, position_only)  # against the full targets
            seed_ok = (pos <= TOL_POS) & (rot <= TOL_ROT)
            rows.append(_row(seed, seed_ok))
            plotted.append(solver_data(seed, seed_ok, seed.success))
        failures += [[backend.name, int(k), _fmt(q_gen[k]), _fmt(targets[k, :3, 3]), _fmt(sol.seed_q[k]),
                      float(sol.pos_error[k]), float(sol.rot_error[k])] for k in np.flatnonzero(~ok)[:10]]
    unreach_rows = []
    if src.spec is not None:
        checks_u, unreach_rows = _unreachable(ctx, solvers, frame, position_only, lower, upper, closed)
        checks += checks_u
    else:
        section["notes"].append("ik.unreachable needs a spec (reach bound); not run in file mode")
    solved = sum(int(r[3]) for r in rows if r[0] == "lm")  # within TOL_POS / TOL_ROT
    section["summary"] = (f"{n} random reachable {'position' if position_only else 'full-pose'} targets for {frame}; "
                          f"LM solved {solved} of {n * len(solvers)} across {len(solvers)} backends "
                          f"within {TOL_POS:g} m / {TOL_ROT:g} rad")
    section["tables"].append({"title": "Solvers (timings and iterations per solve; not asserted)",
                              "columns": ["solver", "backend", "targets", "solved", "success rate", "solved at own tolerance", "median ms",
                                          "p95 ms", "median iterations", "p95 iterations", "max restarts",
                                          "max position error [m]", "max rotation error [rad]", "batched"],
                              "rows": rows})
    # the plots' data stays in the section: ik_figures(section["solvers"], **section["tolerance"]) redraws them
    section["solvers"], section["tolerance"] = plotted, {"tol_pos": TOL_POS, "tol_rot": TOL_ROT}
    section["figures"] += ik_figures(plotted, TOL_POS, TOL_ROT)
    if failures:
        section["tables"].append({"title": "Failures (first 10 per backend)", "columns":
                                  ["backend", "target", "target q [rad/m]", "target xyz [m]", "last seed q",
                                   "position error [m]", "rotation error [rad]"], "rows": failures})
    if unreach_rows:
        section["tables"].append({"title": "Unreachable targets", "columns":
                                  ["solver", "targets", "reported solved", "min closest approach [m]",
                                   "reach lower bound [m]"], "rows": unreach_rows})
    section["notes"] += [
        "ik.success_rate: max_error and p99_error are the fraction of targets NOT solved within "
        f"{TOL_POS:g} m / {TOL_ROT:g} rad, tolerance the allowed fraction ({ALLOWED_FAILURES:g}).",
        "ik.cross_fk: error = max(position error [m], rotation error [rad]) of each solution through "
        "the confirming backend's FK.",
        "seed-pinv (the seed's pseudo-inverse IK: step 0.1, tolerance 1e-3 m, 100 iterations, from q = 0, "
        "position only) is shown for comparison and not checked.",
        "Batched solves (analytic) report the batch time divided by the number of targets.",
    ]
    return SuiteResult(checks, section)


def _closed_form(src, frame):
    if src.spec is None:
        return None
    try:
        return Arm3ClosedForm.from_spec(src.spec, frame if frame in src.spec.tool_names else None)
    except (InputError, StopIteration):
        return None


def _fmt(v) -> list[float]:
    return [round(float(x), 9) for x in v]


def _row(sol: IKSolutions, ok) -> list:
    t = sol.time_s * 1e3
    return [sol.solver, sol.backend, len(sol), int(ok.sum()), float(ok.mean()) if len(ok) else 0.0, int(sol.success.sum()),
            float(np.median(t)), float(np.percentile(t, 95)), float(np.median(sol.iterations)),
            float(np.percentile(sol.iterations, 95)), int(sol.restarts.max()), float(sol.pos_error.max()),
            float(sol.rot_error.max()), sol.batched]


def _success_check(sol, ok, frame) -> Check:
    fail = float(1 - ok.mean())
    worst = int(np.argmin(ok)) if not ok.all() else int(np.argmax(np.maximum(sol.pos_error, sol.rot_error)))
    q = sol.seed_q[worst] if not ok.all() else sol.q[worst]
    return Check("ik.success_rate", frame, (sol.backend, sol.backend), fail, fail, ALLOWED_FAILURES,
                 fail <= ALLOWED_FAILURES, tuple(q.tolist()), "fraction", len(sol), (),
                 f"fraction of {len(sol)} targets not solved within {TOL_POS:g} m / {TOL_ROT:g} rad "
                 f"(max_error = p99_error = that fraction); worst_q: a failing target's last seed, else the worst solution")


def _limits_check(sol, lower, upper, frame) -> Check:
    over = np.maximum(lower - sol.q, sol.q - upper).max(axis=1).clip(min=0.0)
    k = int(np.argmax(over))
    return Check("ik.limits", frame, (sol.backend, "limits"), float(over.max()), float(np.percentile(over, 99)), 0.0,
                 bool(over.max() <= 0.0), tuple(sol.q[k].tolist()), "rad|m", len(sol), (),
                 "largest distance of a returned configuration outside the joint limits")


def _cross_checks(sol, ok, targets, backends, frame) -> list[Check]:
    out = []
    q = sol.q[ok]
    for name, other in backends.items():
        if name == sol.backend or not len(q) or frame not in other.frames:
            continue
        poses = other.evaluate(q, with_jacobians=False).poses[:, other.frames.index(frame)]
        pos, rot = residuals(poses, targets[ok], sol.position_only or not other.has_rotation)
        err = np.maximum(pos, rot)
        k = int(np.argmax(err))
        out.append(Check("ik.cross_fk", frame, (sol.backend, name), float(err.max()), float(np.percentile(err, 99)),
                         TOL_POS, bool(err.max() <= TOL_POS), tuple(q[k].tolist()), "m|rad", len(q), (),
                         "max(position [m], rotation [rad]) error of the solutions through this backend's FK"))
    return out


def _closed_form_check(sol, ok, targets, closed, frame, model) -> Check:
    """Joint distance (angles wrapped) of each solution to the nearest closed-form branch, divided
    by its allowance ``TOL_JOINT + residual / σ_min(J)``: how far the residual alone can move the
    solution (large next to singularities, e.g. a straight elbow)."""
    q = sol.q[ok]
    if not len(q):
        return Check("ik.closed_form", frame, (sol.backend, "closed-form"), 0.0, 0.0, 1.0, True, tuple(sol.q[0].tolist()),
                     "ratio", 0, (), "no solution to compare")
    sigma = np.linalg.svd(model(q)[1][:, :3], compute_uv=False)[:, -1]
    ratio = []
    for qk, tk, res, sk in zip(q, targets[ok], sol.pos_error[ok], sigma):
        branches = closed.all_branches(tk[:3, 3])
        d = np.abs(np.angle(np.exp(1j * (branches - qk)))).max(axis=1).min() if len(branches) else np.inf
        ratio.append(d / (TOL_JOINT + res / max(sk, 1e-300)))
    ratio = np.array(ratio)
    k = int(np.argmax(ratio))
    return Check("ik.closed_form", frame, (sol.backend, "closed-form"), float(ratio.max()), float(np.percentile(ratio, 99)),
                 1.0, bool(ratio.max() <= 1.0), tuple(q[k].tolist()), "ratio", len(q), (),
                 f"joint distance (wrapped, rad) to the nearest closed-form branch over its allowance "
                 f"{TOL_JOINT:g} rad + residual/σ_min(J); passes at <= 1")


def _unreachable(ctx, solvers, frame, position_only, lower, upper, closed):
    targets, bound = unreachable_targets(ctx.sources.spec, frame, DEFAULT_UNREACHABLE, ctx.options.seed + 5)
    checks, rows = [], []
    note = ("fraction of targets beyond the reach bound reported solved or with a closest approach below the bound; "
            "max_error = p99_error = that fraction")
    for backend in solvers:
        sol = solve_lm(FrameModel(backend, frame, ctx.sources.revolute), targets, lower, upper, position_only,
                       IKOptions(seed=ctx.options.seed, max_restarts=3))
        bad = sol.success | (sol.pos_error < bound - 1e-9)
        checks.append(_fraction_check(bad, (backend.name, "geometry"), frame, sol.q, note))
        rows.append([backend.name, len(targets), int(sol.success.sum()), float(sol.pos_error.min()), float(bound.min())])
    if closed is not None:
        res = [closed.solve(t[:3, 3]) for t in targets]
        dist = np.array([r.closest_distance for r in res])
        bad = np.array([r.reachable for r in res]) | (dist < bound - 1e-9)
        checks.append(_fraction_check(bad, ("closed-form", "geometry"), frame, np.zeros((len(targets), len(lower))), note))
        rows.append(["closed-form", len(targets), int(sum(r.reachable for r in res)), float(dist.min()), float(bound.min())])
    return checks, rows


def _fraction_check(bad, pair, frame, q, note) -> Check:
    frac = float(bad.mean())
    k = int(np.argmax(bad))
    return Check("ik.unreachable", frame, pair, frac, frac, 0.0, frac <= 0.0, tuple(q[k].tolist()), "fraction",
                 len(bad), (), note)
