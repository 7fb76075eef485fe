"""``kinverify verify`` before and after, side by side in one run: wall and CPU time per suite.

    python benchmarks/bench_verify.py [--baseline main] [--model models/panda.toml] [--rounds 3] [--markdown OUT.md]

The baseline is ``git archive BASELINE`` unpacked in a temporary folder (no working tree is
touched); this checkout is the other side. Both verify the same spec file (this checkout's) at
the default options (``--quiet``, report and JSON into the temporary folder), each run in a fresh
process, the two alternating (A B B A ...) so load from other processes falls on both alike.
Per suite: wall and CPU time (this process plus the renderers it waits for) from the same driver
(:mod:`verify_runs`); per run: the whole process's wall and CPU, imports included. Medians over
the rounds.
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


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", default="main", help="git ref measured against this checkout (default main)")
    ap.add_argument("--model", default="models/panda.toml")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--markdown", help="also write the table to this file")
    ap.add_argument("--json", help="also write every run's measurements to this file")
    args = ap.parse_args(argv)
    folder = temp_folder()
    trees = {args.baseline: export_tree(args.baseline, ROOT, folder), "this checkout": ROOT}
    model = str((ROOT / args.model).resolve())
    runs = {name: [] for name in trees}
    load = [os.getloadavg()[0]]
    for r in range(args.rounds):
        order = list(trees) if r % 2 == 0 else list(trees)[::-1]
        for name in order:
            argv = ["verify", model, "--quiet", "--json", f"{folder}/{r}.json", "--report", f"{folder}/{r}.html"]
            runs[name].append(timed_run(trees[name], argv, folder))
            print(f"round {r + 1}: {name}: {runs[name][-1]['process_wall_s']:.1f} s wall", flush=True)
        load.append(os.getloadavg()[0])
    lines = table(runs, args, load)
    print("\n".join(lines))
    if args.markdown:
        Path(args.markdown).write_text("\n".join(lines) + "\n")
    if args.json:
        Path(args.json).write_text(json.dumps({"load": load, "model": args.model, "runs": runs}, indent=1))
    return 0


def table(runs: dict, args, load) -> list[str]:
    names = list(runs)
    suites = list(dict.fromkeys(s for rs in runs.values() for r in rs for s in r["suites"]))

    def med(name, get):
        return float(np.median([get(r) for r in runs[name]]))

    when = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    out = [
        f"{when}; {machine()}; load average (1 min) {', '.join(f'{x:.1f}' for x in load)} (start, after each round).",
        "",
        f"`kinverify verify {args.model}` at the default options, {args.rounds} rounds each, alternating; medians. "
        f"CPU: the process and the renderers it waits for.",
        "",
        "| | " + " | ".join(f"{n} wall s | {n} CPU s" for n in names) + " | wall after / before |",
        "|---|" + "---:|" * (2 * len(names) + 1),
    ]
    rows = [
        (s, lambda r, s=s: r["suites"].get(s, {}).get("wall", 0.0), lambda r, s=s: r["suites"].get(s, {}).get("cpu", 0.0))
        for s in suites
    ]
    rows += [
        ("report (JSON + HTML)", lambda r: r["report"]["wall"], lambda r: r["report"]["cpu"]),
        ("start-up (imports)", lambda r: r["startup_s"], lambda r: float("nan")),
        ("**whole process**", lambda r: r["process_wall_s"], lambda r: r["process_cpu_s"]),
    ]
    for label, wall, cpu in rows:
        cells = []
        for n in names:
            c = med(n, cpu)
            cells += [f"{med(n, wall):.2f}", "-" if np.isnan(c) else f"{c:.2f}"]
        before, after = med(names[0], wall), med(names[-1], wall)
        cells.append(f"{after / before:.2f}" if before > 0 else "-")
        out.append(f"| {label} | " + " | ".join(cells) + " |")
    codes = {n: sorted({r["exit_code"] for r in runs[n]}) for n in names}
    out += [
        "",
        f"Exit codes: {codes}; kinverify imported from: " + "; ".join(f"{n}: {runs[n][0]['kinverify']}" for n in names) + ".",
    ]
    return out


if __name__ == "__main__":
    sys.exit(main())
