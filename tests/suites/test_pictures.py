"""The pictures suite: the skeleton's data (frames on the kinematic tree, poses from the backends'
FK at home and at the worst configuration), the kinematic tree, MuJoCo offscreen renderings in a
child process with a camera fitted to the arm, and the note when GL is unavailable."""

from __future__ import annotations

import io

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from matplotlib.image import imread

from kinverify.backends import ModelSources
from kinverify.backends.analytic import AnalyticBackend
from kinverify.report.skeleton import skeleton_svg
from kinverify.report.tree import layout, tree_svg
from kinverify.suites.pictures import HEIGHT, WIDTH, fit_distance, kinematic_tree, png_bytes, render_in_child
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
    page = render_html(result).replace("&#39;", "'")
    assert section.notes[0] in page
    assert '<figure class="plot skeleton"><svg' in page  # the skeleton needs no GL


def test_skeleton_data_is_the_backends_fk_on_the_kinematic_tree():
    spec = load_spec(ARM3)
    result = verify(
        ModelSources.from_spec(spec), VerifyOptions(samples=20, suites=["pictures"], backends=["analytic", "pinocchio-urdf"])
    )
    data = result.sections["pictures"].data
    assert data["frames"] == list(spec.frame_names) and data["parents"] == [-1, 0, 1, 2, 3]  # a chain, base first
    assert data["other"] == "" and data["disagreements"] == []  # nothing disagrees: only the reference is drawn
    ref = AnalyticBackend(spec)
    for key in ("home", "worst"):
        q = np.array([data["configurations"][key]])
        np.testing.assert_allclose(data["poses"][key]["analytic"], ref.poses(q)[0], atol=1e-12)
    tree = data["tree"]
    assert [j["name"] for j in tree["joints"] if j["type"] == "revolute"] == list(spec.joint_names)
    assert skeleton_svg(data).startswith("<svg")


def test_kinematic_tree_layout_puts_children_after_their_parent():
    urdf = """<robot name="t"><link name="base"/><link name="a"/><link name="b"/><link name="c"/>
      <joint name="j1" type="revolute"><parent link="base"/><child link="a"/></joint>
      <joint name="j2" type="prismatic"><parent link="a"/><child link="b"/></joint>
      <joint name="j3" type="fixed"><parent link="a"/><child link="c"/></joint></robot>"""
    tree = kinematic_tree(urdf, ["base", "b"], ["j1", "j2"])
    place, joints = layout(tree)
    assert {j["name"] for j in joints} == {"j1", "j2", "j3"}
    assert place["a"][0] == place["base"][0] + 1 and place["b"][0] == place["c"][0] == place["a"][0] + 1
    assert place["a"][1] == (place["b"][1] + place["c"][1]) / 2  # a parent centred on its children
    svg = tree_svg(tree, {"j2": "error", "c": "warning"})
    assert svg.count("<rect") == 4 and 'stroke="#c62828"' in svg and 'stroke="#f9a825"' in svg


@settings(max_examples=60, deadline=None)
@given(
    arrays(np.float64, st.tuples(st.integers(1, 30), st.just(3)), elements=st.floats(-5, 5)),
    st.floats(-180, 180),
    st.floats(-80, 80),
)
def test_fitted_camera_sees_every_point(points, azimuth, elevation):
    fovy, aspect = 45.0, WIDTH / HEIGHT
    d = fit_distance(points, azimuth, elevation, fovy, aspect)
    az, el = np.radians(azimuth), np.radians(elevation)
    forward = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
    right = np.array([np.sin(az), -np.cos(az), 0.0])
    up = np.cross(right, forward)
    depth = d + points @ forward  # distance in front of a camera at lookat - d * forward
    assert (depth > 0).all()
    tan_v = np.tan(np.radians(fovy) / 2)
    assert (np.abs(points @ up) <= tan_v * depth + 1e-9).all()
    assert (np.abs(points @ right) <= tan_v * aspect * depth + 1e-9).all()
