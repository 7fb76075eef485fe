"""kinverify benchmarks: ``python benchmarks/run.py [--quick] [--json OUT] [--compare OLD.json]``.

``--compare OLD.json --against NEW.json`` compares two stored runs without running anything.

Per shipped model (models/*.toml), every figure a ratio or rate taken in this one run:

- ``cps.<backend>`` configurations/s of each backend's FK + Jacobian (yourdfpy: FK only) and
  ``raw_cps.<backend>`` of the raw library loop (benchmarks/raw.py);
- ``cps.xval`` configurations/s of the full FK + Jacobian cross-validation (the kinematics suite,
  every backend, without the finite-difference checks, which raw calls do not do), and
  ``overhead`` = its time / the sum of the raw loops' times over the same configurations; also
  ``overhead_no_yourdfpy`` without the (slow, FK-only) yourdfpy backend, and the per-backend
  ``overhead.<backend>`` = adapter time / raw time;
- ``analytic_fk_vs_numpy``: time of the analytic FK of all frames / numpy's own stacked 4×4
  products over the same data (per joint T ← T @ origin @ motion, motions made before timing);
- ``peak_mb.1e5`` / ``peak_mb.1e7`` (``--quick``: 1e6): peak RSS of a fresh ``verify`` run
  (``--jobs 2``; backends analytic + pinocchio-urdf only, to keep the 1e7 run to minutes): the
  main process's peak plus the largest worker's (``peak_mb_main``, ``peak_mb_worker``);
- ``jobs2_speedup``: time of ``--jobs 1`` / time of ``--jobs 2`` (default verify options, every
  backend), worker start-up included.

Sizes: 5,000 configurations for the rates (``--quick``: 1,000), 1e6 for the analytic FK figure,
10,000 for ``--jobs`` (``--quick``: 4,000), ``--big N`` for the large memory run. Timings take
the best of two interleaved repeats. ``--compare OLD.json`` prints new/old for
every figure the two runs share.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from raw import raw_for  # noqa: E402

from kinverify.backends import ModelSources, build_backends  # noqa: E402
from kinverify.model.kinematics import frame_poses, joint_motion  # noqa: E402
from kinverify.pipeline.sampling import Samples  # noqa: E402
from kinverify.model.specfile import load_spec  # noqa: E402
from kinverify.run import VerifyContext, VerifyOptions  # noqa: E402
from kinverify.suites.kinematics import KinematicsSuite  # noqa: E402

MEMORY_BACKENDS = "analytic,pinocchio-urdf"
MEMORY_JOBS = 2  # the 1e7 runs take minutes per model even so


def best(fn, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t)
    return min(times)


def cross_validation(sources, backends: dict, n: int, repeats: int) -> dict:
    """Adapter and raw rates per backend, and the full cross-validation against raw calls."""
    samples = Samples(sources.lower, sources.upper, sources.revolute, n, seed=1)
    q = np.asarray(samples)
    out, raw_t, adapt_t = {}, {}, {}
    for name, b in backends.items():
        raw = raw_for(b)
        fk_only = b.jacobian_method != "analytic"

        def adapt(b=b, fk_only=fk_only):
            return b.evaluate(q, with_jacobians=not fk_only)

        raw_t[name], adapt_t[name] = 1e30, 1e30
        for _ in range(repeats):  # interleaved: the machine's load hits both alike
            raw_t[name] = min(raw_t[name], best(lambda raw=raw, b=b: raw(b, q), 1))
            adapt_t[name] = min(adapt_t[name], best(adapt, 1))
        out[f"raw_cps.{name}"] = len(q) / raw_t[name]
        out[f"cps.{name}"] = len(q) / adapt_t[name]
        out[f"overhead.{name}"] = adapt_t[name] / raw_t[name]

    def xval(names):
        opts = VerifyOptions(samples=n, seed=1, fd_samples=0, slow_samples=None, chunk=10_000)
        ctx = VerifyContext(sources, {k: backends[k] for k in names}, samples, opts)
        return lambda: KinematicsSuite().run(ctx)

    for label, names in (("", list(backends)), ("_no_yourdfpy", [k for k in backends if k != "yourdfpy"])):
        t_x, t_raw = 1e30, sum(raw_t[k] for k in names)
        for _ in range(repeats):
            t_x = min(t_x, best(xval(names), 1))
        out[f"cps.xval{label}"] = len(q) / t_x
        out[f"overhead{label}"] = t_x / t_raw
    return out


def analytic_vs_numpy(spec, n: int, chunk: int = 4096, repeats: int = 3) -> float:
    q = np.random.default_rng(0).uniform(spec.lower, spec.upper, (chunk, spec.dof))
    motions = [joint_motion(j, q[:, i]) for i, j in enumerate(spec.joints)]
    origins = [j.origin.transform for j in spec.joints]
    base = np.broadcast_to(spec.base_origin.transform, (chunk, 4, 4))
    reps = max(1, n // chunk)

    def products():
        for _ in range(reps):
            t = base
            for o, m in zip(origins, motions, strict=True):
                t = (t @ o) @ m

    def ours():
        for _ in range(reps):
            frame_poses(spec, q)

    t_np, t_ours = 1e30, 1e30
    for _ in range(repeats):
        t_np = min(t_np, best(products, 1))
        t_ours = min(t_ours, best(ours, 1))
    return t_ours / t_np


_CHILD = """
import json, resource, sys, time
sys.path.insert(0, {root!r})
from kinverify.model.specfile import load_spec
from kinverify.run import VerifyOptions, verify_spec
t = time.perf_counter()
r = verify_spec(load_spec({model!r}), VerifyOptions(samples={n}, backends={backends!r}, jobs={jobs}, suites=["kinematics"]))
print(json.dumps({{"seconds": time.perf_counter() - t, "verdict": r.verdict,
                   "self_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
                   "children_mb": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024}}))
"""


def child_run(model: str, n: int, backends=None, jobs: int = 1) -> dict:
    """One ``verify`` in a fresh process: its peak RSS (MB) and its wall time."""
    code = _CHILD.format(root=str(ROOT), model=model, n=n, backends=backends, jobs=jobs)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    res = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True)
    return json.loads(res.stdout.strip().splitlines()[-1])


def bench_model(path: Path, quick: bool, log, big: int) -> dict:
    spec = load_spec(path)
    sources = ModelSources.from_spec(spec)
    backends = {b.name: b for b in build_backends(sources)}
    n_x = 1000 if quick else 5_000
    fig = cross_validation(sources, backends, n_x, 2)
    fig["xval_samples"] = n_x
    log(f"  {path.stem}: cross-validation done")
    fig["analytic_fk_vs_numpy"] = analytic_vs_numpy(spec, 100_000 if quick else 1_000_000)
    for n, key in ((100_000, "1e5"), (big, f"1e{round(np.log10(big))}")):
        r = child_run(str(path), n, MEMORY_BACKENDS.split(","), jobs=MEMORY_JOBS)
        fig[f"peak_mb.{key}"] = r["self_mb"] + r["children_mb"]
        fig[f"peak_mb_main.{key}"], fig[f"peak_mb_worker.{key}"] = r["self_mb"], r["children_mb"]
        fig[f"seconds.{key}"] = r["seconds"]
        log(f"  {path.stem}: {n} configurations: {r['self_mb']:.0f} + {r['children_mb']:.0f} MB, {r['seconds']:.0f} s")
    n_j = 4000 if quick else 10_000
    t1 = child_run(str(path), n_j, None, 1)["seconds"]
    t2 = child_run(str(path), n_j, None, 2)["seconds"]
    fig["jobs2_speedup"] = t1 / t2
    fig["jobs_samples"] = n_j
    return fig


def machine() -> dict:
    mem = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    return {
        "cpus": os.cpu_count(),
        "memory_gib": round(mem, 1),
        "python": platform.python_version(),
        "platform": platform.platform(),
        "numpy": np.__version__,
    }


def print_table(results: dict) -> None:
    cols = [
        "model",
        "xval cfg/s",
        "overhead",
        "overhead w/o yourdfpy",
        "analytic FK / numpy",
        "peak MB 1e5",
        "peak MB big",
        "jobs 2 speed-up",
    ]
    print(" | ".join(cols))
    for model, f in results["models"].items():
        big = next(v for k, v in f.items() if k.startswith("peak_mb.") and k != "peak_mb.1e5")
        print(
            " | ".join(
                [
                    model,
                    f"{f['cps.xval']:.0f}",
                    f"{f['overhead']:.2f}",
                    f"{f['overhead_no_yourdfpy']:.2f}",
                    f"{f['analytic_fk_vs_numpy']:.2f}",
                    f"{f['peak_mb.1e5']:.0f}",
                    f"{big:.0f}",
                    f"{f['jobs2_speedup']:.2f}",
                ]
            )
        )
    print()
    print("configurations/s per backend (adapter / raw loop, ratio):")
    for model, f in results["models"].items():
        parts = [
            f"{k[4:]} {f[k]:.0f}/{f['raw_' + k]:.0f} ({f['overhead.' + k[4:]]:.2f})"
            for k in f
            if k.startswith("cps.") and not k.startswith("cps.xval")
        ]
        print(f"  {model}: " + ", ".join(parts))


def compare(new: dict, old: dict) -> None:
    print("figure: new / old")
    for model, f in new["models"].items():
        for key, value in f.items():
            prev = old.get("models", {}).get(model, {}).get(key)
            if isinstance(prev, (int, float)) and prev:
                print(f"  {model}.{key}: {value / prev:.3f}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--quick", action="store_true", help="small sizes (1e6 instead of 1e7 for memory, 1000 configurations for rates)"
    )
    ap.add_argument("--json", help="write the figures here (e.g. benchmarks/results/<date>.json)")
    ap.add_argument("--compare", help="a previous --json output: print new/old per figure")
    ap.add_argument("--models", nargs="*", help="model files (default models/*.toml)")
    ap.add_argument("--against", metavar="NEW.json", help="with --compare: compare two stored runs, running nothing")
    ap.add_argument("--big", type=float, help="configurations of the large memory run (default 1e7, --quick 1e6)")
    args = ap.parse_args(argv)
    old = _load(args.compare) if args.compare else None
    if args.against:
        if old is None:
            ap.error("--against needs --compare OLD.json")
        compare(_load(args.against), old)
        return 0
    models = [Path(m) for m in args.models] if args.models else sorted((ROOT / "models").glob("*.toml"))
    log = lambda msg: print(msg, file=sys.stderr, flush=True)  # noqa: E731
    big = int(args.big or (1e6 if args.quick else 1e7))
    results = {"machine": machine(), "big": big, "quick": args.quick, "memory_backends": MEMORY_BACKENDS, "models": {}}
    for path in models:
        log(f"benchmarking {path.stem}...")
        results["models"][path.stem] = bench_model(path, args.quick, log, big)
    print_table(results)
    if args.json:
        from kinverify.io.write import write_atomic

        write_atomic(args.json, json.dumps(results, indent=1))
    if old is not None:
        compare(results, old)
    return 0


def _load(path: str) -> dict:
    try:
        return json.loads(Path(path).read_text())
    except (OSError, ValueError) as err:
        sys.exit(f"benchmarks/run.py: error: {path}: cannot read benchmark JSON: {err}")


if __name__ == "__main__":
    sys.exit(main())
