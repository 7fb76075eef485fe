"""How ``kinverify verify`` grows with the number of joints: serial chains of n revolute joints.

    python benchmarks/bench_scaling.py [--joints 5,10,20,30,50] [--samples 1000] [--baseline REF]
                                       [--plot benchmarks/results/scaling.svg] [--markdown OUT.md]

Each chain (axes cycling z, y, x; 0.12 m links; ±2.5 rad; 1 kg capsules; a tool 5 cm past the
last link) is written as a spec file and verified at the default options in a fresh process
(all suites; ``--samples`` as given), timed per suite by :mod:`verify_runs`. The work per
configuration is at least frames × Jacobian columns, so the fitted exponent of time against n
(least squares on log-log, the largest three sizes) should stay at or below 2. ``--baseline REF``
also times REF (``git archive``) on the sizes that take it under ``--timeout`` seconds.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_ik import machine  # noqa: E402
from verify_runs import export_tree, temp_folder, timed_run  # noqa: E402

AXES = ([0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0])


def chain_toml(n: int) -> str:
    lines = [
        f'name = "chain{n}"',
        f'description = "serial chain of {n} revolute joints (scaling benchmark)"',
        "[base]",
        "xyz = [0.0, 0.0, 0.0]",
        "[base.link]",
        'name = "base"',
        "mass = 2.0",
    ]
    for i in range(n):
        lines += [
            "[[joints]]",
            f'name = "j{i + 1}"',
            'type = "revolute"',
            f"xyz = [0.0, 0.0, {0.1 if i == 0 else 0.12}]",
            f"axis = {AXES[i % 3]}",
            'limits = { lower = -2.5, upper = 2.5, unit = "rad", velocity = 2.0, effort = 50.0 }',
            "damping = 0.1",
            "[joints.link]",
            f'name = "l{i + 1}"',
            "mass = 1.0",
            'geometry = { shape = "capsule", radius = 0.03, fromto = [0.0, 0.0, 0.02, 0.0, 0.0, 0.1] }',
        ]
    lines += ["[[tools]]", 'name = "tool"', f'parent = "l{n}"', "xyz = [0.0, 0.0, 0.05]"]
    return "\n".join(lines) + "\n"


def exponent(ns, times) -> float:
    """Least-squares slope of log(time) against log(n) over the largest three sizes."""
    x, y = np.log(ns[-3:]), np.log(times[-3:])
    return float(np.polyfit(x, y, 1)[0]) if len(x) >= 2 else float("nan")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--joints", default="5,10,20,30,50")
    ap.add_argument("--samples", type=int, default=1000)
    ap.add_argument("--baseline", help="also time this git ref")
    ap.add_argument("--timeout", type=float, default=600, help="--baseline: stop growing n once a run takes longer (s)")
    ap.add_argument("--plot", default=str(ROOT / "benchmarks" / "results" / "scaling.svg"))
    ap.add_argument("--markdown")
    ap.add_argument("--json", help="also write every run's measurements to this file")
    args = ap.parse_args(argv)
    folder = temp_folder()
    ns = [int(x) for x in args.joints.split(",")]
    trees = {"this checkout": ROOT}
    if args.baseline:
        trees[args.baseline] = export_tree(args.baseline, ROOT, folder)
    results = {name: {} for name in trees}
    load = [os.getloadavg()[0]]
    for n in ns:
        spec = Path(folder) / f"chain{n}.toml"
        spec.write_text(chain_toml(n))
        for name, tree in trees.items():
            done = results[name]
            if name != "this checkout" and done and max(r["process_wall_s"] for r in done.values()) > args.timeout:
                continue
            argv = [
                "verify",
                str(spec),
                "--samples",
                str(args.samples),
                "--quiet",
                "--json",
                f"{folder}/c.json",
                "--report",
                f"{folder}/c.html",
            ]
            done[n] = timed_run(tree, argv, folder)
            print(
                f"{name}: {n} joints: {done[n]['process_wall_s']:.1f} s wall, {done[n]['process_cpu_s']:.1f} s CPU "
                f"(exit {done[n]['exit_code']})",
                flush=True,
            )
        load.append(os.getloadavg()[0])
    lines = table(results, args, load)
    print("\n".join(lines))
    if args.markdown:
        Path(args.markdown).write_text("\n".join(lines) + "\n")
    if args.json:
        Path(args.json).write_text(json.dumps({"load": load, "samples": args.samples, "results": results}, indent=1))
    plot(results, args.plot)
    print(f"plot: {args.plot}")
    return 0


def table(results: dict, args, load) -> list[str]:
    when = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = [
        f"{when}; {machine()}; load average (1 min) {', '.join(f'{x:.1f}' for x in load)}.",
        "",
        f"`kinverify verify chainN.toml --samples {args.samples}` (every suite), one fresh process per size.",
        "",
    ]
    for name, done in results.items():
        ns = sorted(done)
        suites = list(dict.fromkeys(s for r in done.values() for s in r["suites"]))
        out += [
            f"{name}:",
            "",
            "| joints | wall s | CPU s | " + " | ".join(f"{s} CPU s" for s in suites) + " | report CPU s |",
            "|---:|---:|---:|" + "---:|" * (len(suites) + 1),
        ]
        for n in ns:
            r = done[n]
            out.append(
                f"| {n} | {r['process_wall_s']:.1f} | {r['process_cpu_s']:.1f} | "
                + " | ".join(f"{r['suites'].get(s, {}).get('cpu', 0.0):.2f}" for s in suites)
                + f" | {r['report']['cpu']:.2f} |"
            )
        if len(ns) >= 3:
            cpu = [done[n]["process_cpu_s"] for n in ns]
            work = [done[n]["process_cpu_s"] - done[n]["startup_s"] for n in ns]
            out += [
                "",
                f"Growth exponent (log-log slope over the largest three sizes): whole process CPU "
                f"{exponent(ns, cpu):.2f}, without start-up {exponent(ns, work):.2f}.",
            ]
        out.append("")
    return out


def plot(results: dict, path: str) -> None:
    import matplotlib
    import matplotlib.ticker

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    for name, done in results.items():
        ns = sorted(done)
        if not ns:
            continue
        ax.plot(ns, [done[n]["process_wall_s"] for n in ns], "o-", label=f"{name}: wall")
        ax.plot(ns, [done[n]["process_cpu_s"] for n in ns], "s--", label=f"{name}: CPU")
    ref = results["this checkout"]
    if ref:
        n0 = min(ref)
        ns = np.array(sorted(ref), dtype=float)
        base = ref[n0]["process_cpu_s"]
        ax.plot(ns, base * (ns / n0) ** 2, ":", color="grey", label="∝ n² from the smallest")
    ax.set_xscale("log")
    ax.set_yscale("log")
    sizes = sorted({n for done in results.values() for n in done})
    ax.set_xticks(sizes, [str(n) for n in sizes])
    ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.set_xlabel("joints n")
    ax.set_ylabel("seconds")
    ax.set_title("kinverify verify on serial chains (default options)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, metadata={"Date": None})
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
