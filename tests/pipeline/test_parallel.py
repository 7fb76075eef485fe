"""``--jobs`` and ``--executor dask``: the same chunks, merged in chunk order, give the same
verdicts and the same numbers as one sequential pass (real pin, mujoco and yourdfpy)."""

from __future__ import annotations

import importlib.util

import pytest

from kinverify.cli import main
from kinverify.model.specfile import load_spec
from kinverify.run import VerifyOptions, verify_spec

HAS_DASK = importlib.util.find_spec("dask") is not None and importlib.util.find_spec("distributed") is not None
# Only the kinematics suite runs its chunks through the executors; the others would add minutes
# and compare nothing an executor touches.
CHUNKED = ["kinematics"]


def options(**kw) -> VerifyOptions:
    return VerifyOptions(samples=400, chunk=90, fd_samples=30, suites=CHUNKED, **kw)


def _numbers(result):
    return result.verdict, [c.to_dict() for c in result.checks]


@pytest.fixture(scope="module")
def sequential():
    """One sequential pass per model: the results every executor must reproduce exactly."""
    out = {}
    for model in ("arm3", "scara"):
        spec = load_spec(f"models/{model}.toml")
        out[model] = (spec, verify_spec(spec, options()))
    return out


@pytest.mark.parametrize("model", ["arm3", "scara"])
def test_jobs_2_identical_to_jobs_1(sequential, model):
    spec, one = sequential[model]
    two = verify_spec(spec, options(jobs=2))
    assert len(one.checks) > 0 and one.checks[0].samples > 0
    assert _numbers(two) == _numbers(one)


def test_progress_reports_every_configuration_in_order(sequential):
    spec, one = sequential["arm3"]
    seen, suite = [], []  # every suite reports its own work; the kinematics suite counts configurations
    result = verify_spec(
        spec,
        options(jobs=2, on_progress=lambda done, total: seen.append((done, total)) if suite[-1] == "kinematics" else None),
        progress=suite.append,
    )
    total = one.samples
    assert seen[-1] == (total, total)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)
    assert _numbers(result) == _numbers(one)


@pytest.mark.skipif(not HAS_DASK, reason="dask.distributed not installed (pip install 'kinverify[dask]')")
def test_dask_local_cluster_identical(sequential):
    spec, one = sequential["arm3"]
    via_dask = verify_spec(spec, options(jobs=2, executor="dask"))
    assert _numbers(via_dask) == _numbers(one)


@pytest.mark.skipif(not HAS_DASK, reason="dask.distributed not installed (pip install 'kinverify[dask]')")
def test_dask_existing_scheduler_identical(sequential):
    from dask.distributed import LocalCluster

    spec, one = sequential["scara"]
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=40) as cluster:
        remote = verify_spec(spec, options(executor="dask", scheduler=cluster.scheduler_address))
    assert _numbers(remote) == _numbers(one)


def test_slow_backend_capped_with_a_note(sequential):
    spec, _ = sequential["arm3"]
    r = verify_spec(spec, options(slow_samples=150))
    n = r.samples
    for c in r.checks:
        if c.backends == ("analytic", "yourdfpy") and c.property.startswith("fk."):
            assert c.samples == 150 and "first 150 of" in c.note
        elif c.property.startswith("fk."):
            assert c.samples == n and "slow" not in c.note


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--jobs", "0"], "--jobs must be >= 1"),
        (["--scheduler", "tcp://127.0.0.1:1"], "--scheduler needs --executor dask"),
        (["--chunk", "0"], "--chunk must be >= 1"),
    ],
)
def test_bad_executor_options_exit_2(tmp_path, capsys, argv, message):
    code = main(
        [
            "verify",
            "models/arm3.toml",
            "--samples",
            "10",
            "--json",
            str(tmp_path / "r.json"),
            "--report",
            str(tmp_path / "r.html"),
            *argv,
        ]
    )
    err = capsys.readouterr().err
    assert code == 2 and message in err and "Traceback" not in err
