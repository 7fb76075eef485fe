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

import contextlib
import json
import os
import signal
import stat
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
    lines = [line for line in err.splitlines() if line.strip()]
    assert all(line.startswith("kinverify") for line in lines), f"a library's message on stderr:\n{err}"
    if code == 2:
        assert len(lines) == 1 and lines[0].startswith("kinverify: error:"), err
    for path, data in before.items():
        assert path.read_bytes() == data, f"input {path} changed"
    leftovers = [p.name for p in out_dir.rglob(".*.tmp")]
    assert not leftovers, f"temporary files left: {leftovers}"
    return code, err


def log_example(argv: list[str], code: int, traceback: bool, changed: list[Path]) -> None:
    path = os.environ.get("KINVERIFY_FUZZ_LOG")
    if path:
        with open(path, "a", encoding="utf-8") as log:
            log.write(
                json.dumps(
                    {
                        "test": os.environ.get("PYTEST_CURRENT_TEST", "").split(" ")[0],
                        "command": argv[0],
                        "code": code,
                        "traceback": traceback,
                        "inputs_changed": len(changed),
                    }
                )
                + "\n"
            )


class Hung(BaseException):
    """A run still going after its deadline (not an Exception: the CLI must not turn it into an exit code)."""


@contextlib.contextmanager
def deadline(seconds: int = 60):
    """Fail a run that blocks (a FIFO opened for reading waits for a writer) instead of hanging the suite."""

    def expired(signum, frame):
        raise Hung(f"still running after {seconds} s")

    previous = signal.signal(signal.SIGALRM, expired)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def snapshot(folder: Path) -> dict[str, bytes]:
    """The bytes of every regular file under ``folder`` (FIFOs, devices and files over 64 MB, such
    as a sparse 3 GB file, by name only)."""
    out = {}
    for p in sorted(folder.rglob("*")):
        try:
            st = os.stat(p)
        except OSError:
            out[str(p.relative_to(folder))] = b"<dangling>"
            continue
        regular = stat.S_ISREG(st.st_mode) and st.st_size < 64 * 2**20
        out[str(p.relative_to(folder))] = p.read_bytes() if regular else b"<not read>"
    return out


def refused(capfd, argv: list[str], folder: Path, *words: str) -> str:
    """Run ``kinverify argv`` in-process: exit 2 within the deadline, one line on stderr holding
    ``words``, no traceback, nothing in ``folder`` written, replaced or left behind."""
    from kinverify.cli import main

    before = snapshot(folder)
    capfd.readouterr()
    with deadline():
        code = main(argv)
    out, err = capfd.readouterr()
    lines = [line for line in err.splitlines() if line.strip()]
    log_example(argv, code, "Traceback" in err + out, [])
    assert code == 2 and len(lines) == 1, f"exit {code}, stderr:\n{err}"
    assert "Traceback" not in err + out
    for word in words:
        assert word in lines[0], lines[0]
    assert snapshot(folder) == before, "a file changed, appeared or was left behind"
    return lines[0]
