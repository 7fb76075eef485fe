"""Timing ``kinverify verify`` runs in fresh processes, for any source tree (this checkout or an
exported git ref), with wall and CPU time per suite measured the same way for every tree.

``python benchmarks/verify_runs.py OUT.json -- verify MODEL ...`` (run with the tree on PYTHONPATH)
is the driver: it wraps every registered suite's ``run`` and the report writers, runs the CLI and
writes what it measured. :func:`timed_run` starts it and adds the whole process's wall and CPU
time (imports included) from the parent.
"""

from __future__ import annotations

import json
import os
import resource
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve()


def cpu_now() -> float:
    me, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + children.ru_utime + children.ru_stime


def temp_folder() -> str:
    return tempfile.mkdtemp(prefix="kinverify-bench-")


def export_tree(ref: str, repo: Path, folder: str) -> Path:
    """``git archive REF`` unpacked into ``folder`` (the repository's working trees are not touched)."""
    out = Path(folder) / ref.replace("/", "_")
    out.mkdir(parents=True, exist_ok=True)
    archive = subprocess.run(["git", "-C", str(repo), "archive", "--format=tar", ref], check=True, capture_output=True).stdout
    tar_path = Path(folder) / "tree.tar"
    tar_path.write_bytes(archive)
    with tarfile.open(tar_path) as tar:
        tar.extractall(out, filter="data")
    return out


def timed_run(tree: Path, argv: list[str], workdir: str, env_extra: dict | None = None) -> dict:
    """Run ``kinverify ARGV`` from ``tree`` in a fresh process; returns the driver's measurements
    plus ``process_wall_s``/``process_cpu_s`` (the whole process, imports included)."""
    out = Path(workdir) / f"timing-{time.monotonic_ns()}.json"
    env = {**os.environ, "PYTHONPATH": str(tree), "OPENBLAS_NUM_THREADS": "1", **(env_extra or {})}
    before, t0 = resource.getrusage(resource.RUSAGE_CHILDREN), time.perf_counter()
    proc = subprocess.run(
        [sys.executable, str(HERE), str(out), "--", *argv], cwd=workdir, env=env, capture_output=True, text=True
    )
    wall, after = time.perf_counter() - t0, resource.getrusage(resource.RUSAGE_CHILDREN)
    if not out.is_file():
        raise RuntimeError(f"kinverify {' '.join(argv)} from {tree} failed ({proc.returncode}): {proc.stderr[-2000:]}")
    data = json.loads(out.read_text())
    data.update(
        process_wall_s=wall,
        process_cpu_s=(after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime),
        exit_code=proc.returncode,
    )
    return data


def _drive(out: str, argv: list[str]) -> None:
    t_start, c_start = time.perf_counter(), cpu_now()
    import kinverify.cli
    import kinverify.report
    import kinverify.report.html
    from kinverify.suites.registry import SUITES

    t_imported = time.perf_counter()
    suites, report = {}, {"wall": 0.0, "cpu": 0.0}

    def timed(fn, record):
        def wrapper(*args, **kwargs):
            t0, c0 = time.perf_counter(), cpu_now()
            try:
                return fn(*args, **kwargs)
            finally:
                record["wall"] += time.perf_counter() - t0
                record["cpu"] += cpu_now() - c0

        return wrapper

    for cls in SUITES:
        cls.run = timed(cls.run, suites.setdefault(cls.name, {"wall": 0.0, "cpu": 0.0}))
    kinverify.report.write_json = timed(kinverify.report.write_json, report)
    kinverify.report.html.write_html = timed(kinverify.report.html.write_html, report)
    code = kinverify.cli.main(argv)
    Path(out).write_text(
        json.dumps(
            {
                "kinverify": kinverify.__file__,
                "startup_s": t_imported - t_start,
                "suites": suites,
                "report": report,
                "run_wall_s": time.perf_counter() - t_start,
                "run_cpu_s": cpu_now() - c_start,
                "code": code,
            }
        )
    )


if __name__ == "__main__":
    sep = sys.argv.index("--")
    _drive(sys.argv[1], sys.argv[sep + 1 :])
