"""Run the CLI in-process on files written for one fuzz example and check what every run must
satisfy, whatever the input: exit 0, 1 or 2 (never 3, an internal error, nor a crash), no
traceback, one ``kinverify: error:`` line on exit 2, inputs byte-identical afterwards, and no
temporary file left behind.

``KINVERIFY_FUZZ_EXAMPLES=N`` sets every fuzz test's example count (nightly-style deep run, e.g.
``KINVERIFY_FUZZ_EXAMPLES=2000 pytest tests/fuzz``); by default each test runs its own small count
so the whole fuzz suite stays near 40 s on 2 cores. ``KINVERIFY_FUZZ_LOG=path.jsonl`` appends one
line per example (command, exit code, traceback seen, inputs changed) for counting.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

from hypothesis import HealthCheck, settings

from kinverify.cli import main


def fuzz_settings(default_examples: int):
    """Hypothesis settings for a fuzz test: ``default_examples`` unless KINVERIFY_FUZZ_EXAMPLES is set."""
    examples = int(os.environ.get("KINVERIFY_FUZZ_EXAMPLES", default_examples))
    return settings(max_examples=examples, deadline=None, suppress_health_check=list(HealthCheck))


def run_checked(capfd, argv: list[str], inputs: list[Path], out_dir: Path) -> tuple[int, str]:
    """Run ``kinverify argv`` and assert the invariants above; returns (exit code, stderr)."""
    before = {p: p.read_bytes() for p in inputs}
    capfd.readouterr()
    code = main(argv)
    out, err = capfd.readouterr()
    log_example(argv, code, "Traceback" in err + out, [p for p, data in before.items() if p.read_bytes() != data])
    assert code in (0, 1, 2), f"exit {code} for {argv}:\n{err}"
    assert "Traceback" not in err and "Traceback" not in out, err
    if code == 2:
        ours = [line for line in err.splitlines() if line.startswith("kinverify")]
        assert len(ours) == 1 and ours[0].startswith("kinverify: error:"), err
    for path, data in before.items():
        assert path.read_bytes() == data, f"input {path} changed"
    leftovers = [p.name for p in out_dir.rglob(".*.tmp")]
    assert not leftovers, f"temporary files left: {leftovers}"
    return code, err


def log_example(argv: list[str], code: int, traceback: bool, changed: list[Path]) -> None:
    path = os.environ.get("KINVERIFY_FUZZ_LOG")
    if path:
        with open(path, "a", encoding="utf-8") as log:
            log.write(json.dumps({"test": os.environ.get("PYTEST_CURRENT_TEST", "").split(" ")[0], "command": argv[0],
                                  "code": code, "traceback": traceback, "inputs_changed": len(changed)}) + "\n")
