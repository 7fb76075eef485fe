"""IK benchmark: success rate, median and p95 time per solve, LM vs the seed's solver, same process.

    PYTHONPATH=. python benchmarks/bench_ik.py [--targets 10000] [--models ur5e,panda] [--backend pinocchio-urdf]

Targets: FK (analytic) of uniform random configurations inside the limits, full pose (position +
orientation); success = within 1e-6 m and 1e-6 rad on the solver's backend, and every solution is
put through the FK of every other backend ("confirmed" = all of them within 1e-6 too). seed-pinv
is the seed's pseudo-inverse IK (position only, from q = 0, step 0.1, tol 1e-3 m, 100 iterations):
its own success is at 1e-3 m position only; its "solved" column is at 1e-6 m / 1e-6 rad full pose.
The analytic row solves all targets in one batch (time = batch time / targets).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from kinverify import load_spec
from kinverify.backends import ModelSources, build_backend, build_backends
from kinverify.ik import FrameModel, IKOptions, reachable_targets, residuals, solve_lm, solve_seed_pinv

TOL = 1e-6


def _confirm(sol, targets, others, frame) -> tuple[int, float]:
    ok = sol.solved(TOL, TOL)
    worst = 0.0
    confirmed = ok.copy()
    for other in others:
        poses = other.poses(sol.q[ok])[:, other.frames.index(frame)]
        pos, rot = residuals(poses, targets[ok], not other.has_rotation)
        err = np.maximum(pos, rot)
        worst = max(worst, float(err.max(initial=0.0)))
        confirmed[np.flatnonzero(ok)[err > TOL]] = False
    return int(confirmed.sum()), worst


def _line(label, sol, ok, confirmed, worst, wall):
    t = sol.time_s * 1e3
    n = len(sol)
    conf = f"{confirmed}/{n}" if confirmed is not None else "-"
    print(f"  {label:<28} solved {ok.sum():>6}/{n} ({100 * ok.mean():7.3f} %)  median {np.median(t):7.3f} ms  "
          f"p95 {np.percentile(t, 95):8.3f} ms  iterations median {np.median(sol.iterations):5.0f} "
          f"p95 {np.percentile(sol.iterations, 95):5.0f}  confirmed {conf}  max other-backend error "
          f"{worst:.1e}  wall {wall:.1f} s", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--targets", type=int, default=10_000)
    ap.add_argument("--models", default="ur5e,panda")
    ap.add_argument("--backend", default="pinocchio-urdf", help="sequential solver backend (default pinocchio-urdf)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--no-batch", action="store_true", help="skip the batched analytic LM row")
    args = ap.parse_args()
    for name in args.models.split(","):
        spec = load_spec(f"models/{name}.toml")
        sources = ModelSources.from_spec(spec)
        frame = sources.frames[-1]
        backends = {b.name: b for b in build_backends(sources)}
        lower, upper = np.asarray(sources.lower), np.asarray(sources.upper)
        _, targets = reachable_targets(backends["analytic"], frame, lower, upper, args.targets, args.seed)
        print(f"{name}: {args.targets} random reachable full-pose targets for {frame} ({spec.dof} joints), tolerance "
              f"{TOL:g} m / {TOL:g} rad", flush=True)
        model = FrameModel(build_backend(args.backend, sources), frame, sources.revolute)
        others = [b for n, b in backends.items() if n != args.backend]
        t0 = time.perf_counter()
        sol = solve_lm(model, targets, lower, upper, False, IKOptions(seed=args.seed))
        wall = time.perf_counter() - t0
        ok = sol.solved(TOL, TOL)
        confirmed, worst = _confirm(sol, targets, others, frame)
        _line(f"lm on {args.backend}", sol, ok, confirmed, worst, wall)
        if not ok.all():
            bad = np.flatnonzero(~ok)[:5]
            print(f"    failures (first 5): targets {bad.tolist()}, errors {sol.pos_error[bad].tolist()} m, "
                  f"{sol.rot_error[bad].tolist()} rad; max restarts {sol.restarts.max()}")
        if not args.no_batch:
            amodel = FrameModel(backends["analytic"], frame, sources.revolute)
            t0 = time.perf_counter()
            asol = solve_lm(amodel, targets, lower, upper, False, IKOptions(seed=args.seed))
            wall = time.perf_counter() - t0
            aok = asol.solved(TOL, TOL)
            conf, worst = _confirm(asol, targets, [b for n, b in backends.items() if n != "analytic"], frame)
            _line("lm on analytic (batch)", asol, aok, conf, worst, wall)
        t0 = time.perf_counter()
        seed = solve_seed_pinv(model, targets, lower, upper)
        wall = time.perf_counter() - t0
        pos, rot = residuals(model.poses(seed.q), targets, False)  # its answers against the full-pose targets
        _line(f"seed-pinv on {args.backend}", seed, (pos <= TOL) & (rot <= TOL), None, 0.0, wall)
        print(f"    seed-pinv at its own tolerance (1e-3 m, position only): {seed.success.sum()}/{len(seed)} "
              f"({100 * seed.success.mean():.2f} %)")
        ratio = np.median(seed.time_s) / np.median(sol.time_s)
        print(f"    median time ratio seed-pinv / lm: {ratio:.2f}", flush=True)


if __name__ == "__main__":
    main()
