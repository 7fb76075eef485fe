"""Mutation score of a package, estimated on a uniform random sample of its mutants (docs/testing.md).

    python tools/mutation_sample.py kinverify/io --size 80 --seed 30
    python tools/mutation_sample.py kinverify/io --size 80 --seed 30 --only kinverify/io/read.py
    python tools/mutation_sample.py kinverify/io --size 80 --seed 30 --report
    python tools/mutation_sample.py kinverify/filemode/compare/inertials.py --size 40 --seed 1

Every module of the package is mutated by mutmut (the ``mutation`` extra); the mutants of the whole
package (or of the one module given instead of a package) form one population, from which ``--size`` are drawn uniformly with ``--seed``. Each
sampled mutant is run against its module's own test module alone, the one that mirrors it
(``kinverify/filemode/align/fit.py`` -> ``tests/filemode/align/test_fit.py``), in the module's
scratch copy (``.mutation/<module>/``, as ``tools/mutation.py`` makes it, kept for ``mutmut show``):
``mutmut run --max-children 1 NAME...``. A module without its own test module has its sampled
mutants counted as not killed ("no test module"), as are mutants whose function its tests never
call ("no tests"). Results are kept in ``.mutation/sample/<package>-<seed>-<size>.json``;
A run left unfinished is resumed by the same command (modules whose test module is smallest go
first); ``--only MODULE`` runs that module's share of the sample again (after writing tests) and
``--report`` prints the figures without running anything.

The score is (killed + timeout) / (sample - equivalent), with its 95 % Wilson interval; the
equivalent ones are the sampled mutants listed, one line each, under "Sampled mutants judged
equivalent" in docs/testing.md. Exit 0 when it ran, whatever the score; 2 on bad arguments.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import math
import random
import re
import subprocess
import sys
from collections import Counter
from pathlib import Path

from mutation import ROOT, scratch
from mutmut.mutation.file_mutation import mutate_file_contents
from mutmut.stats import status_by_exit_code
from mutmut.utils.format_utils import get_mutant_name

DETECTED = ("killed", "timeout")
EQUIVALENT_HEADING = "### Sampled mutants judged equivalent"


def own_tests(module: str) -> str | None:
    """The test module mirroring ``module`` (``kinverify/a/b.py`` -> ``tests/a/test_b.py``), if any."""
    rel = Path(module).relative_to("kinverify")
    test = Path("tests") / rel.parent / f"test_{rel.name}"
    return str(test) if (ROOT / test).is_file() else None


def population(package: str, cache: Path) -> list[tuple[str, str]]:
    """(module, mutant name) of every mutant mutmut makes in ``package``, modules in path order;
    kept in ``cache`` for sources unchanged (making them takes minutes for a large package)."""
    paths = [ROOT / package] if package.endswith(".py") else sorted((ROOT / package).rglob("*.py"))
    digest = hashlib.sha256(b"".join(p.read_bytes() + str(p).encode() for p in paths)).hexdigest()
    if cache.is_file() and (kept := json.loads(cache.read_text()))["sources"] == digest:
        return [tuple(pair) for pair in kept["mutants"]]
    out = []
    for path in paths:
        module = str(path.relative_to(ROOT))
        names = mutate_file_contents(module, path.read_text(), None, None).mutant_names
        out += [(module, get_mutant_name(Path(module), name)) for name in names]
    cache.parent.mkdir(parents=True, exist_ok=True)
    cache.write_text(json.dumps({"sources": digest, "mutants": out}, ensure_ascii=False))
    return out


def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """95 % Wilson score interval of a proportion k/n."""
    if n == 0:
        return (0.0, 1.0)
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return (max(0.0, centre - half), min(1.0, centre + half))


def equivalent_names() -> set[str]:
    """Mutant names listed under the "Sampled mutants judged equivalent" heading of docs/testing.md:
    the names a line starts with (one or more, each in backquotes, before the reason)."""
    text = (ROOT / "docs" / "testing.md").read_text()
    _, _, section = text.partition(EQUIVALENT_HEADING)
    section = re.split(r"\n#{1,3} ", section)[0]
    heads = [line.partition("`: ")[0] for line in section.splitlines() if line.startswith("- `")]
    return {name for head in heads for name in re.findall(r"`([^`]+__mutmut_\d+)", head + "`")}


def run_module(module: str, tests: str, names: list[str]) -> dict[str, str]:
    """Status of each named mutant of ``module`` run against ``tests`` alone."""
    work = scratch(module, [tests])
    cmd = [sys.executable, "-m", "mutmut", "run", "--max-children", "1", *names]
    done = subprocess.run(cmd, cwd=work, capture_output=True, text=True)
    if done.returncode != 0:
        if "could not find any test case" in done.stdout:  # the tests call no mutated function
            return dict.fromkeys(names, "no tests")
        raise SystemExit(f"mutation_sample: mutmut failed in {work}:\n{done.stdout[-3000:]}{done.stderr[-3000:]}")
    meta = json.loads((work / "mutants" / f"{module}.meta").read_text())
    return {name: status_by_exit_code[meta["exit_code_by_key"].get(name)] for name in names}


def report(package: str, sample: dict[str, dict[str, str]], total: int, equivalent: set[str]) -> str:
    rows = ["| module | sampled | killed | timeout | survived | no tests | no test module | equivalent |"]
    rows.append("| --- | --- | --- | --- | --- | --- | --- | --- |")
    by_module: dict[str, Counter[str]] = {}
    for name, entry in sample.items():
        status = "equivalent" if name in equivalent and entry["status"] not in DETECTED else entry["status"]
        by_module.setdefault(entry["module"], Counter())[status] += 1
    overall: Counter[str] = Counter()
    for module in sorted(by_module):
        c = by_module[module]
        overall += c
        cols = [c["killed"], c["timeout"], c["survived"], c["no tests"], c["no test module"], c["equivalent"]]
        rows.append(f"| `{module}` | {sum(c.values())} | " + " | ".join(map(str, cols)) + " |")
    n = sum(overall.values())
    scored = n - overall["equivalent"]
    detected = sum(overall[s] for s in DETECTED)
    low, high = wilson(detected, scored)
    rows.append("")
    rows.append(
        f"{package}: {n} sampled of {total} mutants; killed {overall['killed']}, timeout {overall['timeout']}, "
        f"survived {overall['survived']}, no tests {overall['no tests']}, no test module {overall['no test module']}, "
        f"other {n - sum(overall[s] for s in (*DETECTED, 'survived', 'no tests', 'no test module', 'equivalent'))}, "
        f"equivalent {overall['equivalent']}; score {detected}/{scored} = {100 * detected / max(scored, 1):.0f} % "
        f"(95 % CI {100 * low:.0f}-{100 * high:.0f} %)"
    )
    survivors = sorted(name for name, e in sample.items() if e["status"] not in DETECTED and name not in equivalent)
    rows.append("not killed: " + (", ".join(survivors) if survivors else "none"))
    return "\n".join(rows)


def main(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="mutation_sample.py", description=__doc__.splitlines()[0])
    parser.add_argument("package", help="a package folder, e.g. kinverify/io, or one module of it")
    parser.add_argument("--size", type=int, default=80, help="mutants drawn from the package (default 80)")
    parser.add_argument("--seed", type=int, default=30, help="seed of the draw (default 30)")
    parser.add_argument("--only", metavar="MODULE", help="run again only this module's share of the sample")
    parser.add_argument("--report", action="store_true", help="print the stored figures, run nothing")
    args = parser.parse_args(argv)
    package = args.package.rstrip("/")
    one_module = package.endswith(".py") and (ROOT / package).is_file()
    if not (one_module or (ROOT / package / "__init__.py").is_file()) or args.size < 1:
        print(f"mutation_sample: {package} is not a package or module of the project (or --size < 1)", file=sys.stderr)
        return 2
    kept = ROOT / ".mutation" / "sample"
    everything = population(package, kept / f"{package.replace('/', '.')}-mutants.json")
    drawn = random.Random(args.seed).sample(everything, min(args.size, len(everything)))
    store = kept / f"{package.replace('/', '.')}-{args.seed}-{args.size}.json"
    sample: dict[str, dict[str, str]] = json.loads(store.read_text()) if store.is_file() else {}
    sample = {name: sample.get(name, {"module": module, "status": "not checked"}) for module, name in drawn}
    if not args.report:
        if args.only:
            modules = sorted({module for module, _ in drawn if module == args.only})
            if not modules:
                print(f"mutation_sample: no sampled mutant in {args.only}", file=sys.stderr)
                return 2
        else:  # resumed: modules already measured are left as they are; the fastest test modules first
            todo = {module for module, name in drawn if sample[name]["status"] == "not checked"}
            modules = sorted(todo, key=lambda m: (ROOT / (own_tests(m) or m)).stat().st_size if own_tests(m) else 0)
        for module in modules:
            names = [name for m, name in drawn if m == module]
            tests = own_tests(module)
            statuses = run_module(module, tests, names) if tests else dict.fromkeys(names, "no test module")
            for name, status in statuses.items():
                sample[name]["status"] = status
            kept_now = json.loads(store.read_text()) if store.is_file() else {}  # another run's modules kept
            store.parent.mkdir(parents=True, exist_ok=True)
            store.write_text(json.dumps({**sample, **kept_now, **{n: sample[n] for n in statuses}}, indent=1, ensure_ascii=False))
            print(f"{module} ({tests or 'no test module'}): {dict(Counter(statuses.values()))}", flush=True)
    print(report(package, sample, len(everything), equivalent_names()))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
