"""The ``ik`` property suite of ``kinverify verify``.

Targets are FK (reference backend) of uniform random configurations inside the limits: full
pose for arms with >= 6 joints, position only below. The LM solver (:mod:`kinverify.ik.lm`)
runs on every backend with analytic Jacobians, each on its own FK (batched on ``analytic``,
target by target elsewhere), restarting from one seed table; the seed's solver runs next to it
for the report only (it is not expected to reach 1e-6). Checks: ``ik.failure_rate``, ``ik.limits``, ``ik.cross_fk`` (each solution
through every other backend's FK), ``ik.closed_form`` (arm3-shaped specs), ``ik.unreachable``. A solver that solves
fewer than half of the reachable targets is also a warning finding (``ik_solver_fails``): every target has a solution.
"""

from __future__ import annotations

import numpy as np

from kinverify.errors import InputError
from kinverify.model.floating import has_base
from kinverify.suites.base import (
    AGREEMENT,
    PERFORMANCE,
    Check,
    Finding,
    Property,
    Section,
    Suite,
    SuiteResult,
    VerifyContext,
    floored,
)
from kinverify.ik.closed_form import Arm3ClosedForm
from kinverify.ik.figures import ik_figures, solver_data
from kinverify.ik.frame_model import FrameModel, residuals
from kinverify.ik.lm import IKOptions, IKSolutions, solve_lm
from kinverify.ik.seed_pinv import solve_seed_pinv
from kinverify.ik.targets import reachable_targets, unreachable_targets

DEFAULT_TARGETS = 50
DEFAULT_UNREACHABLE = 5
TOL_POS, TOL_ROT = 1e-6, 1e-6  # m, rad
TOL_JOINT = 1e-6  # rad: numeric solution against the nearest closed-form branch (+ residual/σ_min)
WARN_SOLVED_BELOW = 0.5  # a solver that solves less than this share of reachable targets is broken: a warning finding


class IKSuite(Suite):
    name = "ik"
    title = "Inverse kinematics"
    properties = (
        Property(
            "ik.failure_rate",
            "fraction",
            0.001,
            PERFORMANCE,
            f"fraction of random reachable targets not solved within {TOL_POS:g} m / {TOL_ROT:g} rad by the LM solver",
        ),
        Property(
            "ik.cross_fk",
            "m|rad",
            1e-6,
            AGREEMENT,
            "each IK solution through every other backend's FK: max(position [m], rotation [rad]) error",
        ),
        Property("ik.limits", "rad|m", 0.0, PERFORMANCE, "largest distance of a returned configuration outside the limits"),
        Property(
            "ik.closed_form",
            "ratio",
            1.0,
            AGREEMENT,
            "joint distance to the nearest closed-form branch over 1e-6 rad + residual/σ_min(J) (arm3-shaped specs)",
        ),
        Property(
            "ik.unreachable",
            "fraction",
            0.0,
            AGREEMENT,
            "fraction of targets beyond the reach bound reported solved, or approached closer than the bound",
        ),
    )

    def solve(self, backend, model: FrameModel, targets, lower, upper, position_only: bool, options: IKOptions) -> IKSolutions:
        """The solver the suite measures (one place, so it can be swapped)."""
        return solve_lm(model, targets, lower, upper, position_only, options)

    def closed_form(self, sources, frame: str):
        """The closed-form solver the numeric solutions are compared with (arm3-shaped specs), or None."""
        return _closed_form(sources, frame)

    def run(self, ctx: VerifyContext) -> SuiteResult:
        return ik_suite(self, ctx)


def ik_suite(suite: IKSuite, ctx: VerifyContext) -> SuiteResult:
    opts, src = ctx.options, ctx.sources
    n = int(opts.extra.get("ik_targets", DEFAULT_TARGETS))
    section = Section(IKSuite.title)
    if n <= 0 or not src.joint_names:
        section.summary = "skipped (--ik-targets 0)"
        return SuiteResult([], section)
    if has_base(src.joint_names):
        section.summary = (
            "skipped: the base floats, so moving it reaches every target; IK of the arm from a held "
            "base is not run for floating-base models"
        )
        return SuiteResult([], section)
    frame, dof = src.frames[-1], len(src.joint_names)
    position_only = dof < 6
    lower, upper = np.asarray(src.lower), np.asarray(src.upper)
    q_gen, targets = reachable_targets(ctx.backends[opts.reference], frame, lower, upper, n, opts.seed + 4)
    # solvers: analytic Jacobians in double precision (a float32 library, like Newton, confirms only)
    solvers = [b for b in ctx.backends.values() if b.jacobian_method == "analytic" and not getattr(b, "agreement_floor", None)]
    models = _models(solvers, frame, src.revolute, opts.reference)
    closed = suite.closed_form(src, frame)
    checks, rows, failures, plotted, solved_by = [], [], [], [], {}
    ik_opts = IKOptions(seed=opts.seed, start="seeded")
    report = opts.on_progress or (lambda done, total: None)
    for k, backend in enumerate(solvers):
        report(k, len(solvers))
        model = models[backend.name]
        sol = suite.solve(backend, model, targets, lower, upper, position_only, ik_opts)
        ok = sol.solved(TOL_POS, TOL_ROT)
        solved_by[backend.name] = int(ok.sum())
        checks.append(_failure_check(ctx, sol, ok, frame))
        checks.append(_limits_check(ctx, sol, lower, upper, frame))
        checks += _cross_checks(ctx, sol, ok, targets, ctx.backends, frame)
        if closed is not None:
            checks.append(_closed_form_check(ctx, sol, ok, targets, closed, frame, model))
        rows.append(_row(sol, ok))
        plotted.append(solver_data(sol, ok, sol.success))
        if backend.name == opts.reference:
            seed = solve_seed_pinv(model, targets, lower, upper)  # the baseline, once (not checked)
            pos, rot = residuals(model.poses(seed.q), targets, position_only)  # against the full targets
            seed_ok = (pos <= TOL_POS) & (rot <= TOL_ROT)
            rows.append(_row(seed, seed_ok))
            plotted.append(solver_data(seed, seed_ok, seed.success))
        failures += [
            [
                backend.name,
                int(k),
                _fmt(q_gen[k]),
                _fmt(targets[k, :3, 3]),
                _fmt(sol.seed_q[k]),
                float(sol.pos_error[k]),
                float(sol.rot_error[k]),
            ]
            for k in np.flatnonzero(~ok)[:10]
        ]
    report(len(solvers), len(solvers))
    unreach_rows = []
    if src.spec is not None:
        checks_u, unreach_rows = _unreachable(suite, ctx, solvers, models, frame, position_only, lower, upper, closed)
        checks += checks_u
    else:
        section.notes.append("ik.unreachable needs a spec (reach bound); not run in file mode")
    solved = sum(int(r[3]) for r in rows if r[0] == "lm")  # within TOL_POS / TOL_ROT
    section.summary = (
        f"{n} random reachable {'position' if position_only else 'full-pose'} targets for {frame}; "
        f"LM solved {solved} of {n * len(solvers)} across {len(solvers)} backends "
        f"within {TOL_POS:g} m / {TOL_ROT:g} rad"
    )
    section.table(
        "Solvers (timings and iterations per solve; not asserted)",
        [
            "solver",
            "backend",
            "targets",
            "solved",
            "success rate",
            "solved at own tolerance",
            "median ms",
            "p95 ms",
            "median iterations",
            "p95 iterations",
            "max restarts",
            "max position error [m]",
            "max rotation error [rad]",
            "batched",
        ],
        rows,
    )
    # the plots' data stays in the section: ik_figures(data["solvers"], **data["tolerance"]) redraws them
    section.data.update(solvers=plotted, tolerance={"tol_pos": TOL_POS, "tol_rot": TOL_ROT})
    section.figures += ik_figures(plotted, TOL_POS, TOL_ROT)
    if failures:
        section.table(
            "Failures (first 10 per backend)",
            [
                "backend",
                "target",
                "target q [rad/m]",
                "target xyz [m]",
                "last seed q",
                "position error [m]",
                "rotation error [rad]",
            ],
            failures,
        )
    if unreach_rows:
        section.table(
            "Unreachable targets",
            ["solver", "targets", "reported solved", "min closest approach [m]", "reach lower bound [m]"],
            unreach_rows,
        )
    section.notes += [
        "ik.failure_rate: max_error and p99_error are the fraction of targets not solved within "
        f"{TOL_POS:g} m / {TOL_ROT:g} rad; the goal is the largest fraction allowed. A solver's performance: shown, "
        f"not counted in the verdict unless gated (--gate ik.failure_rate); below {WARN_SOLVED_BELOW:.0%} solved, a "
        "warning finding.",
        "ik.cross_fk: error = max(position error [m], rotation error [rad]) of each solution through "
        "the confirming backend's FK.",
        "seed-pinv (the seed's pseudo-inverse IK: step 0.1, tolerance 1e-3 m, 100 iterations, from q = 0, "
        "position only) is shown for comparison and not checked.",
        "Batched solves (analytic) report the batch time divided by the number of targets. The solver stops at "
        f"{ik_opts.tol_pos:g} m / {ik_opts.tol_rot:g} rad; the first attempt starts from the better of a random guess "
        f"and the best of {ik_opts.seed_samples} stored configurations (a table built once, not timed), restarts from "
        "the next ones.",
    ]
    return SuiteResult(checks, section, _unsolved_findings(solved_by, n, frame))


def _unsolved_findings(solved_by: dict[str, int], n: int, frame: str) -> list[Finding]:
    """One warning when some solvers solve fewer than ``WARN_SOLVED_BELOW`` of the reachable
    targets (FK of configurations inside the limits: each has a solution), naming them and what
    the others solved."""
    broken = {b: k for b, k in solved_by.items() if k < WARN_SOLVED_BELOW * n}
    if not n or not broken:
        return []
    others = {b: k for b, k in solved_by.items() if b not in broken}
    told = "; ".join(f"{b} solves {k} of {n}" for b, k in broken.items())
    rest = (
        f" (the other solvers: {', '.join(f'{b} {k}' for b, k in others.items())} of {n})"
        if others
        else " (so does every other solver)"
    )
    return [
        Finding(
            "ik_solver_fails",
            "warning",
            f"LM IK on reachable targets for {frame}: {told}{rest}; each target is the FK of a configuration inside "
            "the limits, so a solution exists: the solver or this backend's FK or Jacobian of the frame is wrong",
            subject=frame,
            subject_type="frame",
            property="ik.failure_rate",
            values={"solved": dict(solved_by), "targets": n, "backends": list(broken)},
            magnitude=1.0 - min(broken.values()) / n,
            unit="fraction",
        )
    ]


def _models(solvers, frame, revolute, reference) -> dict[str, FrameModel]:
    """One IK model per solver backend; all restart from one seed table, built with the
    reference's chain when it has one (else the first batched chain's; else each its own)."""
    models = {b.name: FrameModel(b, frame, revolute) for b in solvers}
    chains = [m for name, m in models.items() if m.chain is not None]
    owner = models[reference] if reference in models and models[reference].chain is not None else (chains[0] if chains else None)
    for m in models.values():
        m.seed_model = owner or m
    return models


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
    return [
        sol.solver,
        sol.backend,
        len(sol),
        int(ok.sum()),
        float(ok.mean()) if len(ok) else 0.0,
        int(sol.success.sum()),
        float(np.median(t)),
        float(np.percentile(t, 95)),
        float(np.median(sol.iterations)),
        float(np.percentile(sol.iterations, 95)),
        int(sol.restarts.max()),
        float(sol.pos_error.max()),
        float(sol.rot_error.max()),
        sol.batched,
    ]


def _failure_check(ctx, sol, ok, frame) -> Check:
    fail = float(1 - ok.mean())
    worst = int(np.argmin(ok)) if not ok.all() else int(np.argmax(np.maximum(sol.pos_error, sol.rot_error)))
    q = sol.seed_q[worst] if not ok.all() else sol.q[worst]
    return IKSuite.value_check(
        ctx.options,
        "ik.failure_rate",
        frame,
        (sol.backend, sol.backend),
        fail,
        q,
        samples=len(sol),
        note=f"fraction of {len(sol)} targets not solved within {TOL_POS:g} m / {TOL_ROT:g} rad "
        "(max_error = p99_error = that fraction); worst_q: a failing target's last seed, else the worst solution",
    )


def _limits_check(ctx, sol, lower, upper, frame) -> Check:
    over = np.maximum(lower - sol.q, sol.q - upper).max(axis=1).clip(min=0.0)
    k = int(np.argmax(over))
    return IKSuite.value_check(
        ctx.options,
        "ik.limits",
        frame,
        (sol.backend, "limits"),
        float(over.max()),
        sol.q[k],
        samples=len(sol),
        note="largest distance of a returned configuration outside the joint limits",
    )


def _stats(errors, q):
    from kinverify.pipeline.stats import ErrorStats

    st = ErrorStats()
    st.update(errors, q)
    return st


def _cross_checks(ctx, sol, ok, targets, backends, frame) -> list[Check]:
    out = []
    q = sol.q[ok]
    for name, other in backends.items():
        if name == sol.backend or not len(q) or frame not in other.frames:
            continue
        poses = other.evaluate(q, with_jacobians=False).poses[:, other.frames.index(frame)]
        pos, rot = residuals(poses, targets[ok], sol.position_only or not other.has_rotation)
        err = np.maximum(pos, rot)
        out.append(
            floored(
                IKSuite.check(
                    ctx.options,
                    "ik.cross_fk",
                    frame,
                    (sol.backend, name),
                    _stats(err, q),
                    "max(position [m], rotation [rad]) error of the solutions through this backend's FK",
                ),
                [other],
            )
        )
    return out


def _closed_form_check(ctx, sol, ok, targets, closed, frame, model) -> Check:
    """Joint distance (angles wrapped) of each solution to the nearest closed-form branch, divided
    by its allowance ``TOL_JOINT + residual / σ_min(J)``: how far the residual alone can move the
    solution (large next to singularities, e.g. a straight elbow)."""
    q = sol.q[ok]
    if not len(q):
        return IKSuite.value_check(
            ctx.options,
            "ik.closed_form",
            frame,
            (sol.backend, "closed-form"),
            0.0,
            sol.q[0],
            samples=0,
            note="no solution to compare",
        )
    sigma = np.linalg.svd(model(q)[1][:, :3], compute_uv=False)[:, -1]
    ratio = []
    for qk, tk, res, sk in zip(q, targets[ok], sol.pos_error[ok], sigma, strict=True):
        branches = closed.all_branches(tk[:3, 3])
        d = np.abs(np.angle(np.exp(1j * (branches - qk)))).max(axis=1).min() if len(branches) else np.inf
        ratio.append(d / (TOL_JOINT + res / max(sk, 1e-300)))
    return IKSuite.check(
        ctx.options,
        "ik.closed_form",
        frame,
        (sol.backend, "closed-form"),
        _stats(np.array(ratio), q),
        f"joint distance (wrapped, rad) to the nearest closed-form branch over its allowance "
        f"{TOL_JOINT:g} rad + residual/σ_min(J); passes at <= 1",
    )


def _unreachable(suite, ctx, solvers, models, frame, position_only, lower, upper, closed):
    targets, bound = unreachable_targets(ctx.sources.spec, frame, DEFAULT_UNREACHABLE, ctx.options.seed + 5)
    checks, rows = [], []
    note = (
        "fraction of targets beyond the reach bound reported solved or with a closest approach below the bound; "
        "max_error = p99_error = that fraction"
    )
    for backend in solvers:
        sol = suite.solve(
            backend,
            models[backend.name],
            targets,
            lower,
            upper,
            position_only,
            IKOptions(seed=ctx.options.seed, max_restarts=3, start="seeded"),
        )
        bad = sol.success | (sol.pos_error < bound - 1e-9)
        checks.append(_fraction_check(ctx, bad, (backend.name, "geometry"), frame, sol.q, note))
        rows.append([backend.name, len(targets), int(sol.success.sum()), float(sol.pos_error.min()), float(bound.min())])
    if closed is not None:
        res = [closed.solve(t[:3, 3]) for t in targets]
        dist = np.array([r.closest_distance for r in res])
        bad = np.array([r.reachable for r in res]) | (dist < bound - 1e-9)
        checks.append(_fraction_check(ctx, bad, ("closed-form", "geometry"), frame, np.zeros((len(targets), len(lower))), note))
        rows.append(["closed-form", len(targets), int(sum(r.reachable for r in res)), float(dist.min()), float(bound.min())])
    return checks, rows


def _fraction_check(ctx, bad, pair, frame, q, note) -> Check:
    frac = float(bad.mean())
    k = int(np.argmax(bad))
    return IKSuite.value_check(ctx.options, "ik.unreachable", frame, pair, frac, q[k], note=note, samples=len(bad))
