"""Ctrl-C (SIGINT) and SIGTERM in a real kinverify process are never lost, whenever they arrive:
exit 130 or 143, one line, no traceback, nothing written.

The hard moments are made to happen exactly, not by timing: a ``sitecustomize`` module (on the
child's ``PYTHONPATH``, test-only) sends the process its own signal the moment a given module
starts importing, e.g. inside ``trimesh``'s ``try: ... except BaseException`` (which swallows the
``KeyboardInterrupt``), or inside ``import mujoco``; or while the outputs are renamed into place."""

from __future__ import annotations

import importlib.util
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from tests.fuzz.conftest import FILES

HOOK = """
import importlib.abc, os, signal, sys

_AT = os.environ["KV_TEST_SIGNAL_AT"]
_SIGNALS = [getattr(signal, name) for name in os.environ["KV_TEST_SIGNALS"].split(",")]
_fired = []


def _fire():
    if not _fired:
        _fired.append(True)
        for sig in _SIGNALS:
            os.kill(os.getpid(), sig)


if _AT.startswith("os.replace:"):  # while the outputs are renamed into place (onto a file of this name)
    _replace = os.replace

    def replace(src, dst, *args, **kwargs):
        if os.path.basename(dst) == _AT.split(":")[1]:
            _fire()
        return _replace(src, dst, *args, **kwargs)

    os.replace = replace
else:  # the moment module _AT starts importing
    class _Hook(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path=None, target=None):
            if name == _AT:
                _fire()
            return None

    sys.meta_path.insert(0, _Hook())
"""


def _run(work: Path, argv: list[str], at: str, signals: str) -> subprocess.CompletedProcess:
    hook = work / "hook"
    hook.mkdir(exist_ok=True)
    (hook / "sitecustomize.py").write_text(HOOK)
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join([str(hook), os.environ.get("PYTHONPATH", "")]),
        "KV_TEST_SIGNAL_AT": at,
        "KV_TEST_SIGNALS": signals,
    }
    env.pop("KINVERIFY_DEBUG", None)
    return subprocess.run(
        [sys.executable, "-m", "kinverify", *argv], cwd=work, env=env, capture_output=True, text=True, timeout=300
    )


OUTPUTS = ["--json", "out/r.json", "--report", "out/r.html"]


@pytest.mark.parametrize(
    "at, signals, code, line",
    [
        ("trimesh.path", "SIGINT", 130, "kinverify: interrupted"),  # trimesh catches BaseException around this import
        ("mujoco._structs", "SIGTERM", 143, "kinverify: terminated"),  # within `import mujoco`: was exit 3
        ("pinocchio", "SIGTERM,SIGINT", 143, "kinverify: terminated"),  # a second signal at once: no traceback
    ],
)
def test_a_signal_during_a_library_import_is_never_lost(work, at, signals, code, line):
    proc = _run(work, ["verify", "--urdf", "u.urdf", "--mjcf", "r.xml", *FILES, *OUTPUTS], at, signals)
    assert proc.returncode == code and proc.stderr == line + "\n", (proc.returncode, proc.stderr)
    assert not list((work / "out").iterdir()) and not list(work.rglob(".*.tmp"))


def test_a_signal_while_the_outputs_are_renamed_lets_them_finish_and_still_counts(work):
    proc = _run(work, ["generate", "m.toml", "--out", "out"], "os.replace:arm3.urdf", "SIGINT")
    assert proc.returncode == 130 and proc.stderr == "kinverify: interrupted\n", (proc.returncode, proc.stderr)
    assert (work / "out" / "arm3.urdf").read_text().rstrip().endswith("</robot>")  # both complete, none cut half-way
    assert (work / "out" / "arm3.xml").read_text().rstrip().endswith("</mujoco>")
    assert not list(work.rglob(".*.tmp"))


def test_without_a_signal_the_hooked_run_writes_its_outputs(work):
    """The hook itself changes nothing: the same run, never reaching its file, completes."""
    proc = _run(work, ["generate", "m.toml", "--out", "out"], "os.replace:elsewhere", "SIGINT")
    assert proc.returncode == 0 and proc.stderr == "", proc.stderr
    usd = ["arm3.usda"] if importlib.util.find_spec("pxr") else []  # the usd extra
    assert sorted(p.name for p in (work / "out").iterdir()) == ["arm3.sdf", "arm3.urdf", *usd, "arm3.xml"]


def test_sigterm_from_outside_at_any_moment_exits_143(work):
    """A real SIGTERM from another process, while the run is loading its libraries."""
    import time

    proc = subprocess.Popen(
        [sys.executable, "-m", "kinverify", "verify", "--urdf", "u.urdf", "--mjcf", "r.xml", *FILES, *OUTPUTS],
        cwd=work,
        stderr=subprocess.PIPE,
        stdout=subprocess.DEVNULL,
        text=True,
    )
    time.sleep(0.4)
    proc.send_signal(signal.SIGTERM)
    proc.send_signal(signal.SIGTERM)
    err = proc.communicate(timeout=300)[1]
    if proc.returncode in (0, 1):  # the machine was fast enough to finish first: then it wrote everything
        assert sorted(p.name for p in (work / "out").iterdir()) == ["r.html", "r.json"]
        return
    assert proc.returncode in (143, -signal.SIGTERM) and "Traceback" not in err, err
    assert err in ("", "kinverify: terminated\n"), err  # "": before kinverify's first line, Python's default
    assert not list((work / "out").iterdir())
