"""IK benchmark: kinverify's solver against its peers in one process, or across the shipped models.

    python benchmarks/bench_ik.py --compare-peers [--targets 300] [--rounds 3] [--markdown OUT.md]
    python benchmarks/bench_ik.py [--targets 2000] [--models ur5e,panda]

``--compare-peers``: the Franka Panda URDF (``../shared/real-robots/panda/panda_erd.urdf``, found
in the nearest ancestor folder holding ``shared/real-robots``; ``--urdf`` to choose), chain
``panda_link0`` -> ``panda_link8``; ``--targets`` reachable full-pose targets (FK of uniform random
in-limit configurations, seed 12345) and the same initial guesses for every solver (uniform random
in-limit, seed 67890). One judge: Pinocchio's FK on the returned q; success = within 1e-6 m and
1e-4 rad (also shown: 1e-6 rad) and inside the limits. Peers (``pip install -e .[bench]``):
TRAC-IK (pytracik, 5 ms timeout), RTB ``ik_LM``/``ik_NR``, ikpy; one that cannot be imported is
skipped with one line. Each solver is warmed up on 10 other targets, then every round solves all
targets with the solver order rotated (load from other processes hits all alike); GC is off while
timing; statistics pool the rounds. Time per target: ``perf_counter`` around each call; the
batched row's is its batch time / N (the same for every target, so its p99 is that too).

Without ``--compare-peers``: per shipped model, kinverify's LM (per target on ``--backend`` and
batched on ``analytic``) and the seed's pseudo-inverse IK, every solution confirmed by the FK of
every other backend.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # one BLAS thread: no fight over the cores

import argparse
import gc
import platform
import sys
import tempfile
import time
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

POS_TOL, ROT_TOL, ROT_TIGHT = 1e-6, 1e-4, 1e-6
PANDA = "shared/real-robots/panda/panda_erd.urdf"


def default_urdf() -> str:
    for folder in ROOT.parents:
        if (folder / PANDA).is_file():
            return str(folder / PANDA)
    return str(ROOT.parent / PANDA)


def machine() -> str:
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{cpu}, {os.cpu_count()} cores, Python {platform.python_version()}, numpy {np.__version__}"


def compare_peers(args) -> int:
    import ik_peers

    problem = ik_peers.make_problem(args.urdf, args.base, args.tip, args.targets)
    warm = ik_peers.make_problem(args.urdf, args.base, args.tip, 10, 999, 998)
    judge = ik_peers.Judge(problem.text, problem.joints, problem.tip)
    solvers = ik_peers.kinverify_solvers(problem, POS_TOL, (ROT_TOL, ROT_TIGHT))
    folder = tempfile.mkdtemp(prefix="kinverify-bench-")
    for name, make in ik_peers.PEERS.items():
        if name in args.skip:
            continue
        try:
            solvers += make(problem, folder) if name != "TRAC-IK" else make(problem)
        except Exception as err:  # ImportError, or the library refusing the model
            print(
                f"skipped {name}: {type(err).__name__}: {str(err).strip().splitlines()[0] if str(err).strip() else ''}"
                " (pip install -e .[bench])",
                flush=True,
            )
    load = [os.getloadavg()[0]]
    for _label, run, _ in solvers:
        run(warm.targets, warm.q0)
    acc = {label: {"ok": [], "tight": [], "t": [], "cpu": [], "wall": [], "outside": 0, "none": 0} for label, _, _ in solvers}
    for r in range(args.rounds):
        for label, run, _ in solvers[r % len(solvers) :] + solvers[: r % len(solvers)]:
            gc.collect()
            gc.disable()
            try:
                t0 = time.perf_counter()
                q, times, cpu = run(problem.targets, problem.q0)
                wall = time.perf_counter() - t0
            finally:
                gc.enable()
            pe, re, inside = judge.errors(q, problem.targets, problem.lower, problem.upper)
            a = acc[label]
            a["ok"].append((pe <= POS_TOL) & (re <= ROT_TOL) & inside)
            a["tight"].append((pe <= POS_TOL) & (re <= ROT_TIGHT) & inside)
            a["t"].append(times * 1e3)
            a["cpu"].append(np.asarray(cpu) * 1e3)
            a["wall"].append(wall * 1e3 / len(q))
            a["outside"] += int((np.isfinite(pe) & ~inside).sum())
            a["none"] += int((~np.isfinite(pe)).sum())
        load.append(os.getloadavg()[0])
    rows = {label: _stats(a) for label, a in acc.items()}
    ref = rows[solvers[0][0]]
    lines = _table(rows, ref, solvers[0][0], problem, args, load)
    print("\n".join(lines))
    if args.markdown:
        Path(args.markdown).write_text("\n".join(lines) + "\n")
        print(f"\nwritten: {args.markdown}")
    return 0


def _stats(a: dict) -> dict:
    t, c = np.concatenate(a["t"]), np.concatenate(a["cpu"])
    return {
        "success": 100 * np.concatenate(a["ok"]).mean(),
        "tight": 100 * np.concatenate(a["tight"]).mean(),
        "median": float(np.median(t)),
        "p99": float(np.percentile(t, 99)),
        "wall": float(np.median(a["wall"])),
        "cpu_median": float(np.median(c)),
        "cpu_p99": float(np.percentile(c, 99)),
        "outside": a["outside"],
        "none": a["none"],
    }


def _table(rows: dict, ref: dict, ref_label: str, p, args, load) -> list[str]:
    when = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        f"{when}; {machine()}; load average (1 min) {', '.join(f'{x:.1f}' for x in load)} (start, after each round).",
        "",
        f"{os.path.relpath(p.urdf, ROOT)}, {p.base} -> {p.tip} ({len(p.joints)} joints), {len(p.targets)} reachable "
        f"full-pose targets x {args.rounds} rounds, the same initial guesses for every solver; success: Pinocchio FK "
        f"of the answer within {POS_TOL:g} m and {ROT_TOL:g} rad (and {ROT_TIGHT:g} rad) and inside the limits.",
        "",
        "| solver | success % (1e-6 m, 1e-4 rad) | success % (1e-6 m, 1e-6 rad) | median ms | p99 ms "
        "| median / kinverify | p99 / kinverify | CPU median / p99 ms | call wall / N ms |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for label, r in rows.items():
        extra = f" ({r['none']} without answer)" if r["none"] else ""
        extra += f" ({r['outside']} outside the limits)" if r["outside"] else ""
        lines.append(
            f"| {label}{extra} | {r['success']:.2f} | {r['tight']:.2f} | {r['median']:.3f} | {r['p99']:.3f} "
            f"| {r['median'] / ref['median']:.2f} | {r['p99'] / ref['p99']:.2f} "
            f"| {r['cpu_median']:.3f} / {r['cpu_p99']:.3f} | {r['wall']:.3f} |"
        )
    lines += [
        "",
        f"Ratios are to the first row ({ref_label}). Batched rows: time per target = batch time / N, so "
        "median = p99. CPU: process CPU time per target (all threads), which leaves out the time the scheduler "
        "gave other processes. 'call wall / N': the whole call's wall time per target, loop overhead included.",
    ]
    lm = next((r for label, r in rows.items() if "ik_LM" in label), None)
    trac = next((r for label, r in rows.items() if "TRAC-IK" in label), None)
    checks = [
        ("success >= 99.9 %", ref["success"] >= 99.9),
        ("median <= 0.3 ms", ref["median"] <= 0.3),
        ("p99 <= 3 ms", ref["p99"] <= 3.0),
        ("CPU p99 <= 3 ms", ref["cpu_p99"] <= 3.0),
    ]
    if lm:
        checks.append(("median <= RTB ik_LM's", ref["median"] <= lm["median"]))
    if trac:
        checks.append(("more often right than TRAC-IK", ref["success"] > trac["success"]))
    lines += ["", f"Goals for {ref_label}: " + "; ".join(f"{name}: {'yes' if ok else 'NO'}" for name, ok in checks) + "."]
    return lines


def models_mode(args) -> int:
    from kinverify import load_spec
    from kinverify.backends import ModelSources, build_backend, build_backends
    from kinverify.ik import FrameModel, IKOptions, reachable_targets, residuals, solve_lm, solve_seed_pinv

    for name in args.models.split(","):
        spec = load_spec(ROOT / "models" / f"{name}.toml")
        sources = ModelSources.from_spec(spec)
        frame, position_only = sources.frames[-1], spec.dof < 6
        backends = {b.name: b for b in build_backends(sources)}
        lower, upper = np.asarray(sources.lower), np.asarray(sources.upper)
        _, targets = reachable_targets(backends["analytic"], frame, lower, upper, args.targets, args.seed)
        print(
            f"{name}: {args.targets} reachable {'position' if position_only else 'full-pose'} targets for {frame} "
            f"({spec.dof} joints), success within {POS_TOL:g} m / {ROT_TIGHT:g} rad",
            flush=True,
        )
        analytic = FrameModel(backends["analytic"], frame, sources.revolute)
        for label, model in (
            (f"lm on {args.backend}", FrameModel(build_backend(args.backend, sources), frame, sources.revolute)),
            ("lm on analytic (batched)", analytic),
        ):
            model.seed_model = analytic
            sol = solve_lm(model, targets, lower, upper, position_only, IKOptions(seed=args.seed))
            _line(label, sol, sol.solved(POS_TOL, ROT_TIGHT), targets, backends, frame, position_only)
        seed = solve_seed_pinv(analytic, targets, lower, upper)
        pos, rot = residuals(analytic.poses(seed.q), targets, position_only)
        _line("seed-pinv (analytic)", seed, (pos <= POS_TOL) & (rot <= ROT_TIGHT), targets, backends, frame, position_only)
    return 0


def _line(label, sol, ok, targets, backends, frame, position_only) -> None:
    """One solver's figures; 'confirmed': solved and within 1e-6 through every other backend's FK."""
    from kinverify.ik import residuals

    confirmed = ok.copy()
    for other in backends.values():
        if other.name != sol.backend and ok.any():
            poses = other.poses(sol.q[ok])[:, other.frames.index(frame)]
            pos, rot = residuals(poses, targets[ok], position_only or not other.has_rotation)
            confirmed[np.flatnonzero(ok)[np.maximum(pos, rot) > POS_TOL]] = False
    t = sol.time_s * 1e3
    print(
        f"  {label:<26} solved {ok.sum():>6}/{len(sol)} ({100 * ok.mean():7.3f} %)  confirmed {confirmed.sum()}  "
        f"median {np.median(t):.3f} ms  p99 {np.percentile(t, 99):.3f} ms  iterations median "
        f"{np.median(sol.iterations):.0f} p99 {np.percentile(sol.iterations, 99):.0f}",
        flush=True,
    )


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--compare-peers", action="store_true", help="the Panda comparison against TRAC-IK, RTB and ikpy")
    ap.add_argument("--targets", type=int, help="targets (default 300 with --compare-peers, else 2000)")
    ap.add_argument("--rounds", type=int, default=3, help="--compare-peers: rounds over all targets (default 3)")
    ap.add_argument("--urdf", default=default_urdf(), help="--compare-peers: the URDF (default the Panda's)")
    ap.add_argument("--base", default="panda_link0")
    ap.add_argument("--tip", default="panda_link8")
    ap.add_argument("--skip", action="append", default=[], choices=["RTB", "TRAC-IK", "ikpy"], help="leave a peer out")
    ap.add_argument("--markdown", help="--compare-peers: also write the table to this file")
    ap.add_argument("--models", default="ur5e,panda", help="without --compare-peers: shipped models")
    ap.add_argument("--backend", default="pinocchio-urdf", help="without --compare-peers: the per-target backend")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args(argv)
    if args.compare_peers:
        args.targets = args.targets or 300
        if not Path(args.urdf).is_file():
            print(f"bench_ik: {args.urdf} not found (--urdf)", file=sys.stderr)
            return 2
        return compare_peers(args)
    args.targets = args.targets or 2000
    return models_mode(args)


if __name__ == "__main__":
    sys.exit(main())
