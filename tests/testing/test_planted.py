"""The planted-change strategies say true things: MuJoCo compiles the planted MJCF, and what it
computes from it differs from the original by the recorded change, of the recorded size; an
equivalent rewrite computes the same robot in every configuration. Checked with MuJoCo alone on a
generated robot (no file mode, no shared files)."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify import load_spec
from kinverify.generate import generate_urdf
from kinverify.testing import strategies as kst
from kinverify.testing.planted import _group_mass
from tests.paths import MODELS

URDF = kst.mesh_free_urdf(generate_urdf(load_spec(MODELS / "arm3.toml")))
MJCF = kst.mujoco_mjcf(URDF)
# the same arm with its last joint a slide (a gripper's finger): where slide_offset_along is planted
SLIDE_MJCF = kst.mujoco_mjcf('type="prismatic"'.join(URDF.rpartition('type="revolute"')[::2]))


def compiled(text: str, qpos=None) -> tuple[mujoco.MjModel, mujoco.MjData]:
    model = mujoco.MjModel.from_xml_string(text)
    data = mujoco.MjData(model)
    if qpos is not None:
        data.qpos[:] = qpos
    mujoco.mj_forward(model, data)
    return model, data


def angle(a, b) -> float:
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), np.dot(a, b)))


def turn(r1, r2) -> tuple[float, np.ndarray]:
    rel = r1.reshape(3, 3).T @ r2.reshape(3, 3)
    vee = np.array([rel[2, 1] - rel[1, 2], rel[0, 2] - rel[2, 0], rel[1, 0] - rel[0, 1]])
    return float(np.arctan2(np.linalg.norm(vee) / 2, (np.trace(rel) - 1) / 2)), vee / max(np.linalg.norm(vee), 1e-300)


def test_the_mujoco_written_mjcf_is_the_urdfs_robot_with_every_link_a_body():
    model, _ = compiled(MJCF)
    links = [el.get("name") for el in ET.fromstring(URDF).iter("link")]
    assert {model.body(i).name for i in range(model.nbody)} == {"world", *links}
    assert kst.PLANTED_KINDS == (
        "axis_flip",
        "axis_tilt",
        "frame_offset_along",
        "frame_offset_across",
        "frame_turn",
        "frame_turn_twist",
        "frame_twist",
        "slide_offset_along",
        "mass",
        "com",
        "inertia",
        "range",
        "damping",
    )


def test_every_kind_can_be_planted_on_the_arm_or_its_slide_variant():
    assert set(kst.plantable_kinds(MJCF)) | set(kst.plantable_kinds(SLIDE_MJCF)) == set(kst.PLANTED_KINDS)
    assert "slide_offset_along" not in kst.plantable_kinds(MJCF) and "frame_twist" in kst.plantable_kinds(MJCF)


@settings(max_examples=40, deadline=None)
@given(
    st.sampled_from([(MJCF, k) for k in kst.plantable_kinds(MJCF)] + [(SLIDE_MJCF, "slide_offset_along")]).flatmap(
        lambda mk: st.tuples(st.just(mk[0]), kst.planted_changes(mk[0], kinds=(mk[1],), max_changes=1))
    )
)
def test_a_planted_change_is_what_mujoco_computes_differently_by_its_size(change):
    original, (text, (planted,)) = change
    (m0, d0), (m1, d1) = compiled(original), compiled(text)
    kind, size = planted.kind, planted.size
    if kind in ("mass", "com", "inertia"):
        b = m0.body(planted.body).id
        if kind == "mass":
            assert abs(m1.body_mass[b] - m0.body_mass[b]) == pytest.approx(size, rel=1e-9)
        elif kind == "com":
            share = m0.body_mass[b] / _group_mass(
                next(e for e in ET.fromstring(MJCF).iter("body") if e.get("name") == planted.body)
            )
            assert np.linalg.norm(d1.xipos[b] - d0.xipos[b]) * share == pytest.approx(size, rel=1e-9)
        else:
            assert np.abs(np.sort(m1.body_inertia[b]) - np.sort(m0.body_inertia[b])).max() == pytest.approx(size, rel=1e-6)
        return
    j = m0.joint(planted.joint).id
    if kind == "range":
        assert np.abs(m1.jnt_range[j] - m0.jnt_range[j]).max() == pytest.approx(size, rel=1e-9)
    elif kind == "damping":
        assert abs(m1.dof_damping[m0.jnt_dofadr[j]] - m0.dof_damping[m0.jnt_dofadr[j]]) == pytest.approx(size, rel=1e-9)
    elif kind == "axis_flip":
        assert angle(d0.xaxis[j], d1.xaxis[j]) == pytest.approx(np.pi)
        np.testing.assert_allclose(m1.jnt_range[j], -m0.jnt_range[j][::-1])
    elif kind == "axis_tilt":
        assert angle(d0.xaxis[j], d1.xaxis[j]) == pytest.approx(size, rel=1e-6)
    else:
        b = m0.body(planted.body).id
        axis = d0.xaxis[j]
        if kind.startswith("frame_offset") or kind == "slide_offset_along":
            moved = d1.xpos[b] - d0.xpos[b]
            assert np.linalg.norm(moved) == pytest.approx(size, rel=1e-6)
            along = abs(np.dot(moved, axis)) / np.linalg.norm(moved)
            assert along == pytest.approx(1.0 if kind.endswith("along") else 0.0, abs=1e-6)
            assert m1.jnt_type[j] == (mujoco.mjtJoint.mjJNT_SLIDE if kind == "slide_offset_along" else m0.jnt_type[j])
        else:
            turned, about = turn(d0.xmat[b], d1.xmat[b])
            assert turned == pytest.approx(size, rel=1e-6)
            twist = abs(np.dot(d0.xmat[b].reshape(3, 3) @ about, axis))
            if kind == "frame_twist":  # about the joint's own axis
                assert twist == pytest.approx(1.0, abs=1e-6)
            else:
                assert (0.4 < twist < 0.95) if kind.endswith("twist") else twist < 1e-6


@settings(max_examples=20, deadline=None)
@given(kst.equivalent_rewrites(MJCF), st.lists(st.floats(-1.0, 1.0), min_size=9, max_size=9))
def test_an_equivalent_rewrite_is_the_same_robot_in_every_configuration(rewrite, q):
    text, what = rewrite
    m0, _ = compiled(MJCF)
    qpos = np.clip(np.asarray(q[: m0.nq]), m0.jnt_range[:, 0], m0.jnt_range[:, 1])
    (m0, d0), (m1, d1) = compiled(MJCF, qpos), compiled(text, qpos)
    assert text != MJCF
    np.testing.assert_allclose(m1.body_mass, m0.body_mass, rtol=1e-12)
    for name in ("xpos", "xanchor", "xaxis"):
        np.testing.assert_allclose(getattr(d1, name), getattr(d0, name), atol=1e-9, err_msg=f"{what}: {name}")
    weighs = m0.body_mass > 0  # a massless body's centre of mass is nowhere in particular
    np.testing.assert_allclose(d1.xipos[weighs], d0.xipos[weighs], atol=1e-9, err_msg=f"{what}: xipos")
    for b in range(1, m0.nbody):  # each body's inertia about its centre of mass, in the world
        i0 = d0.ximat[b].reshape(3, 3) @ np.diag(m0.body_inertia[b]) @ d0.ximat[b].reshape(3, 3).T
        i1 = d1.ximat[b].reshape(3, 3) @ np.diag(m1.body_inertia[b]) @ d1.ximat[b].reshape(3, 3).T
        np.testing.assert_allclose(i1, i0, atol=1e-12, err_msg=what)
    turned = [b for b in range(1, m0.nbody) if turn(d0.xmat[b], d1.xmat[b])[0] > 1e-6]
    assert ("fullinertia" in what) == (not turned), what  # a turned frame is the only other rewrite


def test_a_body_of_a_small_share_of_its_rigid_body_is_no_mass_site():
    """A 1 g drive link welded to a 1 kg thigh: planting 5-30 % on its mass changes the rigid body's
    by less than the files write it to (1 ± 0.0005 kg), so mass (like com) is planted only on a
    body of at least a quarter of its rigid body's mass."""
    arm = """<mujoco><worldbody><body name="drive"><joint name="j" axis="0 0 1"/>
      <inertial pos="0 0 0" mass="{m}" diaginertia="1e-06 1e-06 1e-06"/>
      <body name="thigh"><inertial pos="0 0 -0.1" mass="1" diaginertia="0.01 0.01 0.001"/></body>
    </body></worldbody></mujoco>"""
    assert "mass" not in kst.plantable_kinds(arm.format(m="0.001"))
    assert "mass" in kst.plantable_kinds(arm.format(m="0.5"))
