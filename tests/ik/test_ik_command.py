"""``kinverify ik`` on files: a URDF chain and a file of targets, the JSON and the three figures,
initial guesses, unreachable targets, and bad input as one line with exit 2 (real pin)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from kinverify.cli import main
from kinverify.generate import generate_urdf
from kinverify.ik import SerialChain
from kinverify.model.specfile import load_spec
from tests.paths import MODELS

PANDA = load_spec(MODELS / "panda.toml")


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("ik")
    urdf = d / "panda.urdf"
    urdf.write_text(generate_urdf(PANDA))
    chain = SerialChain.from_urdf(urdf.read_text(), "world", "flange")
    rng = np.random.default_rng(7)
    q_true = rng.uniform(chain.lower, chain.upper, (40, 7))
    targets = chain.poses(q_true)
    np.save(d / "targets.npy", targets)
    np.save(d / "q_true.npy", q_true)
    return d, chain, targets, q_true


def _args(d, *extra):
    return ["ik", "--urdf", str(d / "panda.urdf"), "--base", "world", "--tip", "flange", *extra]


@pytest.mark.parametrize("per_target", [False, True])
def test_batch_on_a_urdf_writes_the_summary_and_every_target(files, per_target, capsys):
    d, chain, targets, _ = files
    out = d / f"out{per_target}.json"
    assert main(_args(d, "--targets", str(d / "targets.npy"), "--json", str(out), *(["--per-target"] if per_target else []))) == 0
    data = json.loads(out.read_text())
    assert data["success_rate"] == 1.0 and data["solved"] == data["targets"] == 40 and data["batched"] is not per_target
    assert data["joints"] == chain.names and len(data["results"]) == 40
    q = np.array([r["q"] for r in data["results"]])
    assert ((q >= chain.lower) & (q <= chain.upper)).all()
    reached = chain.poses(q)
    assert np.abs(reached[:, :3, 3] - targets[:, :3, 3]).max() <= 1e-6
    times = np.array([r["time_ms"] for r in data["results"]])
    assert data["median_ms"] == pytest.approx(np.median(times)) and data["p99_ms"] == pytest.approx(np.percentile(times, 99))
    assert all(
        r["iterations"] >= 1 and r["position_error_m"] <= 1e-6 and r["rotation_error_rad"] <= 1e-6 for r in data["results"]
    )
    printed = capsys.readouterr().out
    assert "success_rate 100.00 %" in printed and f"median_ms {data['median_ms']:.4g}" in printed
    assert f"p99_ms {data['p99_ms']:.4g}" in printed


def test_initial_guesses_are_where_the_solver_starts(files, tmp_path):
    d, _, _, q_true = files
    np.save(tmp_path / "initial.npy", q_true)  # already the answers: one evaluation each, nothing moves
    out = tmp_path / "out.json"
    assert (
        main(_args(d, "--targets", str(d / "targets.npy"), "--initial", str(tmp_path / "initial.npy"), "--json", str(out))) == 0
    )
    results = json.loads(out.read_text())["results"]
    assert all(r["iterations"] == 1 and r["restarts"] == 0 for r in results)
    np.testing.assert_allclose([r["q"] for r in results], q_true, atol=1e-12)


def test_an_unreachable_target_is_exit_1_and_still_reported(files, tmp_path):
    d, _, targets, _ = files
    far = targets[:3].copy()
    far[1, :3, 3] = [5.0, 0.0, 0.0]  # 5 m away: beyond the Panda's ~1.2 m reach
    np.save(tmp_path / "far.npy", far)
    out = tmp_path / "out.json"
    assert main(_args(d, "--targets", str(tmp_path / "far.npy"), "--json", str(out))) == 1
    data = json.loads(out.read_text())
    assert [r["success"] for r in data["results"]] == [True, False, True]
    assert data["results"][1]["position_error_m"] > 3.0 and data["success_rate"] == pytest.approx(2 / 3)


def test_targets_on_a_spec_frame(files, tmp_path, capsys):
    d, _, targets, _ = files
    assert main(["ik", str(MODELS / "panda.toml"), "--targets", str(d / "targets.npy"), "--json", str(tmp_path / "o.json")]) == 0
    assert json.loads((tmp_path / "o.json").read_text())["success_rate"] == 1.0
    assert "success_rate 100.00 %" in capsys.readouterr().out


def _bad_files(d):
    t = np.load(d / "targets.npy")
    nan, skew, row = t.copy(), t.copy(), t.copy()
    nan[3, 1, 1] = np.nan
    skew[2, :3, :3] *= 1.1
    row[0, 3, 0] = 1.0
    for name, array in (("shape", t[:, :3]), ("nan", nan), ("skew", skew), ("row", row), ("initial", np.zeros((40, 6)))):
        np.save(d / f"bad_{name}.npy", array)
    (d / "text.npy").write_text("not numpy")


@pytest.mark.parametrize(
    "extra, message",
    [
        (["--targets", "{d}/bad_shape.npy"], "has shape (40, 3, 4)"),
        (["--targets", "{d}/bad_nan.npy"], "target 3 has a non-finite value"),
        (["--targets", "{d}/bad_skew.npy"], "target 2's rotation block is not a rotation"),
        (["--targets", "{d}/bad_row.npy"], "target 0's last row"),
        (["--targets", "{d}/targets.npy", "--initial", "{d}/bad_initial.npy"], "--initial"),
        (["--targets", "{d}/text.npy"], "is not an .npy file"),
        (["--targets", "{d}/missing.npy"], "is not a file"),
        (["--targets", "{d}/targets.npy", "--tip", "flange_mount"], "has no link 'flange_mount' (a joint has that name)"),
        (["--targets", "{d}/targets.npy", "--base", "nowhere"], "--base"),
        (["--target", "0.3", "0.1"], "--target needs 3 values"),
        (["--targets", "{d}/targets.npy", "--tol-pos", "nan"], "--tol-pos"),
    ],
)
def test_bad_input_is_one_line_and_exit_2_and_no_json(files, extra, message, capsys):
    d = files[0]
    _bad_files(d)
    out = d / "never.json"
    assert main(_args(d, *[e.format(d=d) for e in extra], "--json", str(out))) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists()


def test_a_spec_and_a_urdf_together_or_neither_is_refused(files, capsys):
    d = files[0]
    assert (
        main(["ik", str(MODELS / "panda.toml"), "--urdf", str(d / "panda.urdf"), "--tip", "flange", "--target", "0", "0", "1"])
        == 2
    )
    assert main(["ik", "--target", "0", "0", "1"]) == 2
    assert main(["ik", "--urdf", str(d / "panda.urdf"), "--target", "0", "0", "1"]) == 2  # no --tip
    assert capsys.readouterr().err.count("kinverify: error:") == 3


def test_help_and_ik_on_a_urdf_load_no_heavy_library(files, tmp_path):
    """Start-up: ``kinverify --help`` and ``kinverify ik --urdf`` (batched numpy) import neither
    MuJoCo (even with MUJOCO_GL asking for GL), Pinocchio, yourdfpy nor matplotlib."""
    import os
    import subprocess
    import sys

    from tests.paths import ROOT

    d = files[0]
    heavy = ("mujoco", "pinocchio", "yourdfpy", "trimesh", "matplotlib")
    code = (
        "import sys, contextlib, io; from kinverify.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()):\n"
        "    try: rc = main(sys.argv[1:])\n"
        "    except SystemExit as e: rc = e.code\n"
        f"print(rc, [m for m in {heavy!r} if m in sys.modules])"
    )
    env = {**os.environ, "MUJOCO_GL": "egl", "PYTHONPATH": str(ROOT)}
    for argv in (["--help"], _args(d, "--targets", str(d / "targets.npy"), "--json", str(tmp_path / "o.json"))):
        out = subprocess.run([sys.executable, "-c", code, *argv], env=env, capture_output=True, text=True, timeout=120)
        assert out.returncode == 0, out.stderr[-2000:]
        assert out.stdout.split("\n")[-2] == "0 []", out.stdout
