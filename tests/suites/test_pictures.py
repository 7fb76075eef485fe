"""MuJoCo offscreen renderings in a child process, and the note when GL is unavailable."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from matplotlib.image import imread

from kinverify.backends import ModelSources
from kinverify.suites.pictures import HEIGHT, WIDTH, png_bytes, render_in_child
from kinverify.report.html import render_html
from kinverify.model.specfile import load_spec
from kinverify.run import VerifyOptions, verify
from tests.paths import MODELS

ARM3 = MODELS / "arm3.toml"


@settings(max_examples=20, deadline=None)
@given(arrays(np.uint8, st.tuples(st.integers(1, 9), st.integers(1, 9), st.just(3))))
def test_png_encoder_round_trips(image):
    decoded = imread(io.BytesIO(png_bytes(image)), format="png")
    np.testing.assert_array_equal(np.round(decoded * 255).astype(np.uint8), image)


def test_renders_home_and_another_pose_as_different_pngs():
    spec = load_spec(ARM3)
    sources = ModelSources.from_spec(spec)
    pngs, reason = render_in_child(sources.mjcf, spec.joint_names, [np.zeros(3), np.array([0.5, 1.0, -1.0])])
    if reason:
        pytest.skip(reason)  # no GL on this machine: the note path is tested below
    images = [imread(io.BytesIO(p), format="png") for p in pngs]
    assert [im.shape for im in images] == [(HEIGHT, WIDTH, 3)] * 2
    assert images[0].std() > 0.01 and np.abs(images[0] - images[1]).mean() > 1e-3


def test_unavailable_gl_becomes_a_note_in_the_report(monkeypatch):
    monkeypatch.setenv("MUJOCO_GL", "glx")  # GLX without an X display: the renderer cannot start
    monkeypatch.delenv("DISPLAY", raising=False)
    result = verify(ModelSources.from_spec(load_spec(ARM3)), VerifyOptions(samples=1, suites=["pictures"]))
    section = result.sections["pictures"]
    assert section.figures == [] and section.notes[0].startswith("rendering unavailable")
    assert "MUJOCO_GL=glx" in section.notes[0]
    assert section.notes[0] in render_html(result).replace("&#39;", "'")
