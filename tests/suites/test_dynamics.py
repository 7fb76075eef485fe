"""Dynamics cross-validation: Pinocchio on the URDF against MuJoCo on the MJCF, on random specs
and on every shipped model; a model whose MJCF mass differs from its URDF must fail."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from kinverify.testing import strategies as kst
from kinverify.backends import ModelSources
from kinverify.suites.dynamics import DynamicsSuite
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.spec import Inertial
from kinverify.model.specfile import load_spec, spec_from_dict
from kinverify.tracking.models import MujocoDynamics, PinocchioDynamics
from kinverify.run import VerifyOptions, verify

MODELS = sorted(str(p) for p in Path("models").glob("*.toml"))


@st.composite
def specs_with_joint_dynamics(draw, max_joints: int = 5):
    """Random specs whose joints also carry damping and armature (the MJCF-only parameter)."""
    d = draw(kst.spec_dicts(max_joints=max_joints))
    for joint in d["joints"]:
        joint["damping"] = draw(st.floats(0.0, 2.0))
        joint["armature"] = draw(st.floats(0.0, 0.1))
    return spec_from_dict(d)


def _pair(spec, mjcf_spec=None):
    pin = PinocchioDynamics(generate_urdf(spec), spec.joint_names, [j.armature for j in spec.joints])
    return pin, MujocoDynamics(generate_mjcf(mjcf_spec or spec), spec.joint_names)


def _as_mujoco_runs(pin, mj):
    """Pinocchio given the inertials MuJoCo's run time uses where its compiler aligned a body's
    inertial frame with the body's (body_sameframe: tested on their own below), as the suite does."""
    return pin.with_inertials(mj.run_inertials())


_LIMITS = {"lower": -1.5, "upper": 1.5, "unit": "rad"}
# A 1e-6 m joint offset: l2 is a capsule 1e-6 m long, its centre of mass 5e-7 m up its axis; MuJoCo
# runs it at l2's origin (body_sameframe), and M(0)[0, 0] moves by 2·m·0.25 m·5e-7 m = 5e-7 kg·m².
TINY_LINK = spec_from_dict(
    {
        "name": "random_arm",
        "joints": [
            {"name": "j1", "axis": [1, 0, 0], "limits": _LIMITS, "link": {"name": "l1", "mass": 1.0}, "damping": 0.5},
            {"name": "j2", "axis": [0, 1, 0], "xyz": [0.0, 0.0, 0.25], "limits": _LIMITS, "link": {"name": "l2", "mass": 2.0}},
            {"name": "j3", "axis": [1, 0, 0], "xyz": [0.0, 0.0, 1e-6], "limits": _LIMITS, "link": {"name": "l3", "mass": 2.0}},
        ],
        "tools": [{"name": "tool", "parent": "l3", "xyz": [0.0, 0.0, 0.1]}],
    }
)


@st.composite
def specs_and_configurations(draw, max_joints: int = 5):
    spec = draw(specs_with_joint_dynamics(max_joints))
    return spec, draw(kst.configurations(spec))


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(specs_and_configurations())
@example((TINY_LINK, np.zeros(3)))
def test_mass_matrix_spd_and_equal_across_backends(case):
    spec, q = case
    pin, mj = _pair(spec)
    pin = _as_mujoco_runs(pin, mj)
    rng = np.random.default_rng(0)
    v, a = rng.uniform(-2, 2, spec.dof), rng.uniform(-5, 5, spec.dof)
    M = pin.mass(q)
    assert np.allclose(M, M.T, rtol=0, atol=1e-14)
    assert np.linalg.eigvalsh(M)[0] > 0
    scale = max(1.0, np.abs(M).max())
    assert np.abs(M - mj.mass(q)).max() <= 1e-9 * scale
    assert np.abs(pin.gravity(q) - mj.gravity(q)).max() <= 1e-9 * max(1.0, np.abs(mj.gravity(q)).max())
    assert np.abs(pin.bias(q, v) - mj.bias(q, v)).max() <= 1e-9 * max(1.0, np.abs(mj.bias(q, v)).max())
    tau = mj.inverse(q, v, a)
    assert np.abs(pin.inverse(q, v, a) - tau).max() <= 1e-9 * max(1.0, np.abs(tau).max())


def test_mujoco_running_a_centre_of_mass_within_1e6_m_at_the_body_origin_is_named_and_matched():
    """MuJoCo's compiler takes l2's inertial frame, 5e-7 m from its origin, for the body frame:
    the stated models differ by 5e-7 in M (Pinocchio and Drake keep the stated centre of mass);
    given what MuJoCo runs, Pinocchio agrees to rounding, and verify passes naming l2."""
    pin, mj = _pair(TINY_LINK)
    assert mj.moved_coms() == [("l2", 5e-7)] and mj.snapped_inertia_frames() == []
    q = np.zeros(3)
    assert 4.9e-7 < np.abs(pin.mass(q) - mj.mass(q)).max() < 5.1e-7
    assert np.abs(_as_mujoco_runs(pin, mj).mass(q) - mj.mass(q)).max() < 1e-15
    assert np.abs(pin.mass(q) - _pair(TINY_LINK)[0].mass(q)).max() == 0  # the copy, not pin, was changed
    result = verify(ModelSources.from_spec(TINY_LINK), VerifyOptions(samples=10, suites=["dynamics"]))
    assert result.checks and all(c.passed for c in result.checks)
    assert any("body_sameframe" in n and "centre of mass of l2 (5e-07 m" in n for n in result.sections["dynamics"].notes)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(specs_and_configurations(max_joints=4))
def test_pinocchio_euler_step_matches_mj_step(case):
    import mujoco

    spec, q = case
    pin, mj = _pair(spec)
    pin = _as_mujoco_runs(pin, mj)
    rng = np.random.default_rng(1)
    v, tau = rng.uniform(-1, 1, spec.dof), rng.uniform(-1, 1, spec.dof)
    m, d = mj.model, mj.data
    mujoco.mj_resetData(m, d)
    d.qpos[mj.qadr], d.qvel[mj.vadr], d.qfrc_applied[mj.vadr] = q, v, tau
    mujoco.mj_forward(m, d)
    if d.nefc:  # a configuration exactly at a joint limit activates MuJoCo's limit constraint
        return
    mujoco.mj_step(m, d)
    q1, v1 = pin.step_euler(q, v, tau, m.opt.timestep)
    scale = max(1.0, np.abs(d.qvel).max())
    assert np.abs(d.qvel[mj.vadr] - v1).max() <= 1e-9 * scale
    assert np.abs(d.qpos[mj.qadr] - q1).max() <= 1e-9 * scale


@pytest.mark.parametrize("path", MODELS)
def test_dynamics_agree_to_1e9_on_every_shipped_model(path):
    result = verify(ModelSources.from_spec(load_spec(path)), VerifyOptions(samples=30, suites=["dynamics"]))
    props = {c.property for c in result.checks}
    velocity_terms = set() if load_spec(path).floating else {"dynamics.bias", "dynamics.inverse", "dynamics.forward"}
    assert {
        "dynamics.mass_matrix",
        "dynamics.gravity",
        "dynamics.damping",
        "dynamics.friction",
        "dynamics.armature",
    } | velocity_terms <= props
    for c in result.checks:
        assert c.passed, c
        if c.property in ("dynamics.mass_matrix", "dynamics.gravity", "dynamics.bias", "dynamics.inverse", "dynamics.forward"):
            assert 1e-9 <= c.tolerance <= 1e-9 * 1e3 and c.max_error <= c.tolerance
    assert "URDF cannot express" in result.sections["dynamics"].tables[1].rows[0][5]


def heavier_link(spec, index: int, factor: float = 1.2):
    """``spec`` with ``joints[index].link`` ``factor`` times as heavy (mass and inertia)."""
    joints = list(spec.joints)
    link = joints[index].link
    i = link.inertial
    heavier = Inertial(i.mass * factor, i.com, tuple(x * factor for x in i.inertia))
    joints[index] = dataclasses.replace(joints[index], link=dataclasses.replace(link, inertial=heavier))
    return dataclasses.replace(spec, joints=tuple(joints))


def test_mjcf_link_mass_20_percent_off_fails_dynamics():
    spec = load_spec("models/arm3.toml")
    sources = dataclasses.replace(ModelSources.from_spec(spec), mjcf=generate_mjcf(heavier_link(spec, 1)))
    result = verify(sources, VerifyOptions(samples=20, suites=["dynamics"]))
    failed = {c.property for c in result.checks if not c.passed}
    assert {"dynamics.mass_matrix", "dynamics.gravity", "dynamics.bias", "dynamics.inverse", "dynamics.forward"} <= failed
    worst = {c.property: c.max_error for c in result.checks if c.backends == ("pinocchio-urdf", "mujoco")}
    assert worst["dynamics.gravity"] > 0.1  # N·m: 20 % of the forearm's weight torque
    assert "dynamics.damping" not in failed and "dynamics.armature" not in failed


def test_armature_mismatch_is_reported_not_dropped():
    spec = load_spec("models/arm3.toml")
    mjcf = generate_mjcf(spec).replace('armature="0.01"', 'armature="0.02"', 1)
    result = verify(dataclasses.replace(ModelSources.from_spec(spec), mjcf=mjcf), VerifyOptions(samples=10, suites=["dynamics"]))
    arm = next(c for c in result.checks if c.property == "dynamics.armature")
    assert not arm.passed and abs(arm.max_error - 0.01) < 1e-12
    assert arm.backends == ("spec", "mjcf") and "URDF cannot express" in arm.note
    assert not next(c for c in result.checks if c.property == "dynamics.mass_matrix").passed


def test_tolerances_are_1e9_relative_for_state_comparisons():
    for prop in ("dynamics.mass_matrix", "dynamics.gravity", "dynamics.bias", "dynamics.inverse", "dynamics.forward"):
        assert DynamicsSuite.property(prop).tolerance == 1e-9


def test_mujoco_snapping_a_nearly_aligned_inertia_frame_is_named():
    """A capsule tilted by 6e-8 m over 0.25 m has principal axes 2.4e-7 rad off its link frame;
    MuJoCo drops that rotation (body_sameframe) and M differs by ~1e-9: the suite says why."""
    tilted = {
        "name": "l2",
        "inertial": {
            "mass": 1.0,
            "com": [2.9802322387695312e-08, 0.0, 0.125],
            "inertia": [0.0072766666666666206, 0.007276666666667009, 0.0004375862068969407, 0.0, -1.6305638455796405e-09, 0.0],
        },
    }
    sphere = {"shape": "sphere", "radius": 0.03}
    spec = spec_from_dict(
        {
            "name": "tilted",
            "joints": [
                {
                    "name": "j1",
                    "axis": [1, 0, 0],
                    "limits": {"lower": 0, "upper": 1, "unit": "rad"},
                    "link": {"name": "l1", "mass": 1.0, "geometry": sphere},
                },
                {
                    "name": "j2",
                    "axis": [1, 0, 0],
                    "rpy": [0, 1.5707963267948966, 0],
                    "limits": {"lower": 0, "upper": 1, "unit": "rad"},
                    "link": tilted,
                },
                {
                    "name": "j3",
                    "axis": [1, 0, 0],
                    "xyz": [5.960464477539063e-08, 0, 0.25],
                    "limits": {"lower": 0, "upper": 1, "unit": "rad"},
                    "link": {"name": "l3", "mass": 1.0, "geometry": sphere},
                },
            ],
            "tools": [{"name": "tool", "parent": "l3"}],
        }
    )
    pin, mj = _pair(spec)
    ((body, angle),) = mj.snapped_inertia_frames()
    assert body == "l2" and 2e-7 < angle < 3e-7
    q = np.array([0.0, 1.0, 0.0])
    assert 1e-10 < np.abs(pin.mass(q) - mj.mass(q)).max() < angle * 0.0072766  # bounded by angle·(I_max − I_min)
    result = verify(ModelSources.from_spec(spec), VerifyOptions(samples=5, suites=["dynamics"]))
    assert any("body_sameframe" in n and "l2" in n for n in result.sections["dynamics"].notes)
