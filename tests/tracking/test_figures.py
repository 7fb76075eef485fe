"""The tracking animation: frames picked from the run, a GIF rendered offscreen in a child process,
and a "rendering unavailable" note (never a crash) when GL is missing or MUJOCO_GL is unknown."""

from __future__ import annotations

import base64
import io
import json
import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from PIL import Image

from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.mujoco_gl import accepted
from kinverify.model.specfile import load_spec
from kinverify.tracking.execute import execute
from kinverify.tracking.figures import SIZE, animation, frame_indices
from kinverify.tracking.quintic import hold, quintic
from kinverify.tracking.track import default_trajectory
from tests.paths import ROOT

ARM3 = load_spec(ROOT / "models" / "arm3.toml")


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 20_000), st.sampled_from([0.0005, 0.001, 0.002, 0.01]), st.floats(0.5, 60.0))
def test_frame_indices_span_the_run_at_the_frame_rate(n, dt, fps):
    idx = frame_indices(n, dt, fps)
    if n == 0:
        assert len(idx) == 0
        return
    assert idx[0] == 0 and idx[-1] == n - 1 and np.all(np.diff(idx) > 0)
    step = max(1, round(1 / (fps * dt)))
    assert np.diff(idx).max(initial=0) <= step  # never more than one frame period between frames
    assert len(idx) <= n // step + 2


@pytest.mark.parametrize("value", ["invalid", "osmesa", "egl", "disable"])
def test_mujoco_imports_whatever_mujoco_gl_says(value):
    """The dynamics MuJoCo does needs no GL: an unknown or unloadable MUJOCO_GL leaves it working
    and records why (``IMPORT_ERROR``) for the rendering child's note."""
    code = (
        "import kinverify, mujoco, numpy as np; from kinverify import mujoco_gl; "
        "m = mujoco.MjModel.from_xml_string('<mujoco><worldbody><body><joint/><geom size=\\'.1\\' mass=\\'2\\'/>"
        "</body></worldbody></mujoco>'); d = mujoco.MjData(m); mujoco.mj_forward(m, d); M = np.zeros((1, 1)); "
        "mujoco.mj_fullM(m, d, M); print(M[0, 0] > 0, repr(mujoco_gl.IMPORT_ERROR))"
    )
    env = {**os.environ, "MUJOCO_GL": value, "PYTHONPATH": str(ROOT)}
    probe = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=60)
    assert probe.returncode == 0, probe.stderr[-1000:]
    works, error = probe.stdout.split(" ", 1)
    assert works == "True"
    assert ("invalid value for environment variable MUJOCO_GL" in error) is (value == "invalid")
    assert accepted(value) is (value != "invalid")


def _run(duration=0.5, hold_s=0.2):
    tr = default_trajectory(ARM3)
    plan = hold(quintic(tr.q0, tr.q1, duration, 0.001), hold_s)
    return execute(ARM3, generate_urdf(ARM3), plan, "computed-torque", duration)


def test_animation_is_a_gif_of_the_executed_motion():
    run = _run()
    fig, reason = animation(run, generate_mjcf(ARM3), [0, 1, 2])
    if reason:
        pytest.skip(reason)  # no GL on this machine: the note paths are tested below
    assert fig.mime == "image/gif" and "computed-torque" in fig.title
    gif = Image.open(io.BytesIO(base64.b64decode(fig.data, validate=True)))
    assert gif.format == "GIF" and gif.size == SIZE
    frames = []
    for k in range(gif.n_frames):
        gif.seek(k)
        frames.append(np.asarray(gif.convert("RGB"), dtype=float))
    assert len(frames) >= 3  # identical hold frames may merge, the motion's frames do not
    assert frames[0].std() > 5 and np.abs(frames[0] - frames[-1]).mean() > 0.1  # a picture, and the arm moved


def test_unknown_mujoco_gl_is_a_note_in_verify_not_a_crash(tmp_path):
    """MUJOCO_GL=invalid makes ``import mujoco`` raise: verify still runs every MuJoCo check and
    the renderings turn into notes in the JSON and the HTML."""
    html, js = tmp_path / "r.html", tmp_path / "r.json"
    cmd = [
        sys.executable,
        "-m",
        "kinverify",
        "verify",
        str(ROOT / "models" / "arm3.toml"),
        "--samples",
        "5",
        "--skip",
        "ik",
        "--skip",
        "workspace",
        "--quiet",
        "--report",
        str(html),
        "--json",
        str(js),
    ]
    env = {**os.environ, "MUJOCO_GL": "invalid", "PYTHONPATH": str(ROOT)}
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "Traceback" not in proc.stderr
    data = json.loads(js.read_text())
    assert "mujoco" in data["backends"] and any(c["property"].startswith("dynamics.") for c in data["checks"])
    tracking = data["sections"]["tracking"]
    note = tracking["notes"][0]
    assert note.startswith("rendering unavailable (MUJOCO_GL=invalid)") and "not a GL backend" in note
    assert [f["mime"] for f in tracking["figures"]] == ["image/svg+xml", "image/svg+xml"]  # the plots stay
    assert data["sections"]["pictures"]["notes"][0].startswith("rendering unavailable (MUJOCO_GL=invalid)")
    assert "not a GL backend MuJoCo knows" in html.read_text(encoding="utf-8").replace("&#39;", "'")
