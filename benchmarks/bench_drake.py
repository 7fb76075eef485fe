"""What the ``drake`` extra costs: ``kinverify verify MODEL`` with Drake installed against the same
command without it, in one run.

``python benchmarks/bench_drake.py [--model models/panda.toml] [--rounds 3] [--json OUT]``

Both runs use this checkout and this venv, in fresh processes, alternating (with first, then
without, each round). "Without" hides pydrake behind a folder, first on ``PYTHONPATH``, whose
``pydrake`` package raises ImportError: the registry then lists drake-urdf, drake-mjcf and
drake-sdf as unavailable, exactly as in an install without the extra. Wall and CPU time come from
:mod:`verify_runs` (the whole process, imports included, and per suite); the figure is the ratio
of the medians, with / without (the issue's bound: at most 1.3).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import tempfile
from pathlib import Path

from verify_runs import timed_run

ROOT = Path(__file__).resolve().parent.parent
BOUND = 1.3


def pydrake_blocker(folder: str) -> str:
    """A folder whose ``pydrake`` package cannot be imported (the install without the extra)."""
    package = Path(folder) / "blocker" / "pydrake"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text(
        "raise ModuleNotFoundError(\"No module named 'pydrake' (hidden by benchmarks/bench_drake.py)\")\n"
    )
    return str(package.parent)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--model", default="models/panda.toml")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--json", help="write the measurements here")
    args = ap.parse_args(argv)
    work = tempfile.mkdtemp(prefix="kinverify-bench-drake-")
    blocker = pydrake_blocker(work)
    model = str((ROOT / args.model).resolve())
    runs = {"with": [], "without": []}
    for _ in range(args.rounds):
        for label, extra in (("with", {}), ("without", {"PYTHONPATH": os.pathsep.join([blocker, str(ROOT)])})):
            out = Path(work) / f"{label}.json"
            data = timed_run(
                ROOT, ["verify", model, "--quiet", "--json", str(out), "--report", str(out.with_suffix(".html"))], work, extra
            )
            result = json.loads(out.read_text())
            data["backends"] = result["backends"]
            runs[label].append(data)
    drake = sorted({b for r in runs["with"] for b in r["backends"] if b.startswith("drake")})
    assert drake and not any(b.startswith("drake") for r in runs["without"] for b in r["backends"]), (
        "the two runs must differ by Drake"
    )
    med = {
        label: {k: statistics.median(r[k] for r in rs) for k in ("process_wall_s", "process_cpu_s")} for label, rs in runs.items()
    }
    ratio = {k: med["with"][k] / med["without"][k] for k in ("process_wall_s", "process_cpu_s")}
    print(f"kinverify verify {args.model}, {args.rounds} rounds each, alternating; medians (whole process)")
    print(
        f"  with Drake ({', '.join(drake)}): wall {med['with']['process_wall_s']:.2f} s, CPU {med['with']['process_cpu_s']:.2f} s"
    )
    print(
        f"  without the extra:            wall {med['without']['process_wall_s']:.2f} s, CPU {med['without']['process_cpu_s']:.2f} s"
    )
    print(f"  ratio with / without: wall {ratio['process_wall_s']:.3f}, CPU {ratio['process_cpu_s']:.3f} (bound {BOUND})")
    exits = {label: [r["exit_code"] for r in rs] for label, rs in runs.items()}
    print(f"  exit codes: {exits}")
    if args.json:
        Path(args.json).write_text(
            json.dumps(
                {
                    "model": args.model,
                    "rounds": args.rounds,
                    "medians": med,
                    "ratio": ratio,
                    "exit_codes": exits,
                    "drake_backends": drake,
                    "runs": runs,
                },
                indent=1,
            )
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
