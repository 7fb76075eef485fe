"""Mutation score of one module by its own tests (docs/testing.md).

    python tools/mutation.py kinverify/results.py tests/test_results.py [more test files...]

mutmut (the ``mutation`` extra) mutates the module and runs only the given tests against each
mutant, in a scratch copy of the project (``.mutation/<module>/``, kept for ``mutmut browse`` and
``mutmut show`` there): ``[tool.mutmut]`` of pyproject.toml with ``only_mutate`` and the test
selection narrowed to the arguments. Prints mutmut's counts (killed, survived, no tests...) as
JSON; exit 0 when it ran, whatever the score. One worker (``--max-children 1``): the machine is
shared.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
COPIED = ("kinverify", "tests", "models", "pyproject.toml")


def narrowed(pyproject: str, module: str, tests: list[str]) -> str:
    """pyproject.toml with its ``[tool.mutmut]`` table mutating ``module`` alone, tested by ``tests``."""
    head, sep, _ = pyproject.partition("[tool.mutmut]")
    if not sep:
        raise SystemExit("pyproject.toml has no [tool.mutmut] table")
    return head + "\n".join(
        [
            "[tool.mutmut]",
            'source_paths = ["kinverify"]',
            f"only_mutate = {json.dumps([module])}",
            'also_copy = ["models"]',
            'pytest_add_cli_args = ["-p", "no:cacheprovider", "-n", "0"]',
            f"pytest_add_cli_args_test_selection = {json.dumps(tests)}",
            "",
        ]
    )


def scratch(module: str, tests: list[str]) -> Path:
    """A fresh copy of the project in ``.mutation/<module>/`` with ``[tool.mutmut]`` narrowed."""
    work = ROOT / ".mutation" / re.sub(r"[^\w.]+", "_", module)
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir(parents=True)
    for name in COPIED:
        src = ROOT / name
        if src.is_dir():
            shutil.copytree(src, work / name, ignore=shutil.ignore_patterns("__pycache__", ".hypothesis"))
        else:
            shutil.copy2(src, work / name)
    (work / "pyproject.toml").write_text(narrowed((ROOT / "pyproject.toml").read_text(), module, tests))
    return work


def main(argv: list[str]) -> int:
    if len(argv) < 2 or not argv[0].endswith(".py"):
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    module, tests = argv[0], argv[1:]
    for path in (module, *tests):
        if not (ROOT / path).is_file():
            print(f"mutation: {path} is not a file of the project", file=sys.stderr)
            return 2
    work = scratch(module, tests)
    mutmut = [sys.executable, "-m", "mutmut"]
    subprocess.run([*mutmut, "run", "--max-children", "1"], cwd=work, check=True, stdout=subprocess.DEVNULL)
    subprocess.run([*mutmut, "export-cicd-stats"], cwd=work, check=True, stdout=subprocess.DEVNULL)
    stats = json.loads((work / "mutants" / "mutmut-cicd-stats.json").read_text())
    survivors = subprocess.run([*mutmut, "results"], cwd=work, check=True, capture_output=True, text=True).stdout
    print(json.dumps({"module": module, "tests": tests, **stats}, indent=1))
    print("\n".join(line.strip() for line in survivors.splitlines() if line.strip()) or "no survivors")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
