"""Generated URDF and MJCF: deterministic, same names, loadable by every library, and free of
the seed model's defects (ctrlrange in degrees, two control loops per joint)."""

from __future__ import annotations

import io
import math
import os
import tempfile
import xml.etree.ElementTree as ET

import mujoco
import numpy as np
import pinocchio as pin
import pytest
import yourdfpy
from hypothesis import given, settings

from kinverify import load_spec
from kinverify.testing import strategies as kst
from kinverify.generate import generate_mjcf, generate_urdf

MODELS = ["models/arm3.toml", "models/ur5e.toml", "models/panda.toml", "models/scara.toml"]


@pytest.mark.parametrize("path", MODELS)
def test_generation_is_deterministic(path):
    a, b = load_spec(path), load_spec(path)
    assert generate_urdf(a) == generate_urdf(b)
    assert generate_mjcf(a) == generate_mjcf(b)


@pytest.mark.parametrize("path", MODELS)
def test_same_names_in_both_files(path):
    spec = load_spec(path)
    urdf, mjcf = ET.fromstring(generate_urdf(spec)), ET.fromstring(generate_mjcf(spec))
    urdf_joints = [j.get("name") for j in urdf.iter("joint") if j.get("type") != "fixed"]
    mjcf_joints = [j.get("name") for j in mjcf.iter("joint")]
    assert urdf_joints == mjcf_joints == list(spec.joint_names)
    urdf_links = {el.get("name") for el in urdf.iter("link")}
    mjcf_bodies = {b.get("name") for b in mjcf.iter("body")}
    mjcf_sites = {s.get("name") for s in mjcf.iter("site")}
    assert set(spec.link_names) <= urdf_links & mjcf_bodies
    assert set(spec.tool_names) <= urdf_links & mjcf_sites


def _load_everywhere(spec):
    urdf, mjcf = generate_urdf(spec), generate_mjcf(spec)
    mj = mujoco.MjModel.from_xml_string(mjcf)
    pin_urdf = pin.buildModelFromXML(urdf)
    fd, path = tempfile.mkstemp(suffix=".xml")
    with os.fdopen(fd, "w") as handle:
        handle.write(mjcf)
    try:
        pin_mjcf = pin.buildModelFromMJCF(path)
    finally:
        os.unlink(path)
    robot = yourdfpy.URDF.load(io.BytesIO(urdf.encode()), load_meshes=False, build_collision_scene_graph=False)
    return mj, pin_urdf, pin_mjcf, robot


@pytest.mark.parametrize("path", MODELS)
def test_shipped_models_load_in_every_library(path):
    spec = load_spec(path)
    mj, pin_urdf, pin_mjcf, robot = _load_everywhere(spec)
    assert mj.njnt == pin_urdf.nq == pin_mjcf.nq == len(robot.actuated_joint_names) == spec.dof


@settings(max_examples=25, deadline=None)
@given(kst.arm_specs(trees=True, floating=True))
def test_random_specs_load_in_every_library(spec):
    mj, pin_urdf, pin_mjcf, robot = _load_everywhere(spec)
    base = 6 if spec.floating else 0  # a free joint / free-flyer (yourdfpy counts a floating joint as one)
    assert mj.nv == pin_urdf.nv == pin_mjcf.nv == spec.dof + base
    assert len(robot.actuated_joint_names) == spec.dof + (1 if spec.floating else 0)
    masses = [mj.body_mass[mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_BODY, j.link.name)] for j in spec.joints]
    np.testing.assert_allclose(masses, [j.link.inertial.mass for j in spec.joints])
    parents = [mj.body_parentid[mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_BODY, j.link.name)] for j in spec.joints]
    assert [mj.body(p).name for p in parents] == [spec.link_names[p] for p in spec.parent_indices]  # the tree, nested


def test_arm3_actuators_fix_the_seed_defects():
    spec = load_spec("models/arm3.toml")
    for kind in ("motor", "position"):
        mj = mujoco.MjModel.from_xml_string(generate_mjcf(spec, actuators=kind))
        # one actuator per joint: no position loop fighting a velocity loop
        assert mj.nu == spec.dof
        assert sorted(mj.actuator_trnid[:, 0].tolist()) == list(range(spec.dof))
        if kind == "position":
            # ctrlrange in radians, equal to the joint range (the seed wrote degrees)
            np.testing.assert_allclose(mj.actuator_ctrlrange, mj.jnt_range)
            assert np.all(np.abs(mj.actuator_ctrlrange) <= math.pi + 1e-12)
        else:
            np.testing.assert_allclose(mj.actuator_ctrlrange[:, 1], [j.limits.effort for j in spec.joints])
    # the arm has no contacts (Pinocchio knows none), the seed scene is there
    assert np.all(mj.geom_contype == 0) and np.all(mj.geom_conaffinity == 0)
    names = {mj.geom(i).name for i in range(mj.ngeom)}
    assert {"floor", "tabletop"} <= names
    assert mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_SITE, "target") >= 0
    sensors = {mj.sensor(i).name for i in range(mj.nsensor)}
    assert {"joint1_pos", "joint1_vel", "end_effector_pos"} <= sensors
    assert mj.opt.integrator == mujoco.mjtIntegrator.mjINT_EULER


def test_mjcf_keeps_full_float_precision():
    spec = load_spec("models/panda.toml")
    mj = mujoco.MjModel.from_xml_string(generate_mjcf(spec))
    # body quaternions must round-trip: compare to the spec's rpy through MuJoCo's own conversion
    quat = np.empty(4)
    from kinverify.model.transforms import matrix_to_quat, rpy_to_matrix

    for joint in spec.joints:
        bid = mujoco.mj_name2id(mj, mujoco.mjtObj.mjOBJ_BODY, joint.link.name)
        quat[:] = matrix_to_quat(rpy_to_matrix(joint.origin.rpy))
        assert np.allclose(mj.body_quat[bid], quat, atol=1e-15) or np.allclose(mj.body_quat[bid], -quat, atol=1e-15)


@pytest.mark.parametrize("path", MODELS + ["models/space_arm.toml"])
def test_sdf_is_deterministic_and_names_what_the_urdf_names(path):
    from kinverify.generate import generate_sdf

    spec = load_spec(path)
    assert generate_sdf(spec) == generate_sdf(load_spec(path))
    sdf = ET.fromstring(generate_sdf(spec))
    assert sdf.tag == "sdf" and float(sdf.get("version")) >= 1.9
    model = sdf.find("model")
    assert [j.get("name") for j in model.iter("joint") if j.get("type") != "fixed"] == list(spec.joint_names)
    assert {el.get("name") for el in model.iter("link")} == set(spec.link_names)
    assert {f.get("name") for f in model.iter("frame")} == set(spec.tool_names)
    welded = [j for j in model.iter("joint") if j.findtext("parent") == "world"]
    assert len(welded) == (0 if spec.floating else 1)  # a floating base is a free body


def test_sdf_writes_subnormal_numbers_as_zero_and_every_other_number_exactly():
    from kinverify import spec_from_dict
    from kinverify.generate import generate_sdf

    spec = spec_from_dict(
        {
            "name": "tiny",
            "joints": [
                {
                    "type": "revolute",
                    "axis": [0, 0, 1],
                    "xyz": [0.1, 0.25, 2.2250738585072014e-308],
                    "limits": {"lower": -1, "upper": 1, "unit": "rad"},
                }
            ],
        }
    )
    text = generate_sdf(spec)
    assert "0.1 0.25 2.2250738585072014e-308" in text  # the smallest normal number is written as it is
    subnormal = spec_from_dict(
        {
            "name": "tiny",
            "joints": [
                {
                    "type": "revolute",
                    "axis": [0, 0, 1],
                    "xyz": [0.1, 0.25, 1e-310],
                    "limits": {"lower": -1, "upper": 1, "unit": "rad"},
                }
            ],
        }
    )
    assert "0.1 0.25 0.0 " in generate_sdf(subnormal) and "e-310" not in generate_sdf(subnormal)
