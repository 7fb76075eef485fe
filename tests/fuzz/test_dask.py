"""``--executor dask`` cleans up after itself: a SIGTERM while the local cluster starts is exit 143
with one line (distributed's exit handler printed a traceback: a half-started cluster cannot be
closed), and no run leaves ``dask-scratch-space/`` (or anything else) in ``$TMPDIR``
(kinverify/pipeline/parallel.py). The signal is sent by the process itself the moment a module
starts importing, as in test_signals.py, so the moment is exact, not a matter of timing."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(importlib.util.find_spec("distributed") is None, reason="dask.distributed not installed")

HOOK = """
import importlib.abc, os, signal, sys

_AT = os.environ.get("KV_TEST_SIGNAL_AT", "")
_MAIN = os.environ.setdefault("KV_TEST_MAIN_PID", str(os.getpid())) == str(os.getpid())  # not in the workers


class _Hook(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if _MAIN and name == _AT:
            os.kill(os.getpid(), signal.SIGTERM)
        return None


sys.meta_path.insert(0, _Hook())
"""


def _dask_run(work: Path, at: str) -> tuple[subprocess.CompletedProcess, list[str]]:
    hook, tmp = work / "hook", work / "tmp"
    hook.mkdir()
    tmp.mkdir()
    (hook / "sitecustomize.py").write_text(HOOK)
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(hook), os.environ.get("PYTHONPATH", "")]),
        "KV_TEST_SIGNAL_AT": at,
        "TMPDIR": str(tmp),
    }
    env.pop("KINVERIFY_DEBUG", None)
    argv = [
        "verify",
        "m.toml",
        "--samples",
        "40",
        "--skip",
        "ik",
        "--skip",
        "tracking",
        "--skip",
        "pictures",
        "--backends",
        "analytic",
        "--executor",
        "dask",
        "--jobs",
        "1",
        "--quiet",
        "--json",
        "out/r.json",
        "--report",
        "out/r.html",
    ]
    proc = subprocess.run(
        [sys.executable, "-m", "kinverify", *argv], cwd=work, env=env, capture_output=True, text=True, timeout=300
    )
    return proc, sorted(p.name for p in tmp.iterdir())


def test_sigterm_while_the_cluster_starts_is_one_line_and_leaves_nothing(work):
    proc, left = _dask_run(work, "multiprocessing.synchronize")  # imported as the worker processes start
    assert proc.returncode == 143 and proc.stderr == "kinverify: terminated\n", (proc.returncode, proc.stderr)
    assert left == [] and not list((work / "out").iterdir())


def test_a_dask_run_leaves_no_scratch_space(work):
    proc, left = _dask_run(work, "")
    assert proc.returncode == 0, proc.stderr
    assert left == [] and sorted(p.name for p in (work / "out").iterdir()) == ["r.html", "r.json"]
