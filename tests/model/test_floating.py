"""A floating base as six coordinates in front of the joints: the math, the spec format, and every
library agreeing on FK, Jacobians, mass matrix and gravity in those coordinates on random
floating-base trees (each library's native free-flyer converted at its adapter)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kinverify import SpecError, load_spec, spec_from_dict
from kinverify.backends import ModelSources, build_backends
from kinverify.backends.base import finite_difference_jacobians, pair_floor
from kinverify.model.floating import BASE_COORDINATES, base_coordinates, base_transforms, rate_matrices, velocity_map
from kinverify.model.kinematics import frame_poses, geometric_jacobians
from kinverify.model.transforms import rotation_log, rpy_to_matrix
from kinverify.testing import strategies as kst
from kinverify.tracking.models import MujocoDynamics, PinocchioDynamics
from tests.paths import MODELS

coordinates = st.lists(st.floats(-3, 3), min_size=6, max_size=6).map(np.array)


@given(coordinates)
def test_base_pose_is_urdf_rpy_and_round_trips(b):
    t = base_transforms(b)
    assert np.abs(t[:3, :3] - rpy_to_matrix(b[3:])).max() < 1e-15 and np.all(t[:3, 3] == b[:3])
    again = base_transforms(base_coordinates(t))
    assert np.abs(again - t).max() < 1e-12


@given(coordinates)
def test_rate_matrix_gives_the_world_angular_velocity(b):
    h = 1e-7
    r0 = base_transforms(b)[:3, :3]
    fd = np.stack([rotation_log(base_transforms(b + h * e)[:3, :3] @ r0.T) / h for e in np.eye(6)[3:]], axis=-1)
    assert np.abs(rate_matrices(b) - fd).max() < 1e-6
    s = velocity_map(b, linear_in_body=True)
    assert np.allclose(s[:3, :3], r0.T) and np.allclose(s[3:, 3:], r0.T @ rate_matrices(b))
    assert np.allclose(velocity_map(b, linear_in_body=False)[:3, :3], np.eye(3))


def test_the_spec_says_floating_and_the_configuration_leads_with_the_base():
    spec = load_spec(MODELS / "space_arm.toml")
    assert spec.floating and spec.coordinate_names[:6] == BASE_COORDINATES and spec.nq == spec.dof + 6
    lower, upper = spec.coordinate_limits
    assert np.allclose(lower[:3], np.array(spec.base_origin.xyz) - 1) and upper[4] == pytest.approx(math.pi / 2)
    tool = frame_poses(spec, spec.home())[0, spec.frame_names.index("tool"), :3, 3]
    assert np.allclose(tool, [0, 0, 1.85], atol=1e-15)
    with pytest.raises(SpecError, match=r"base.floating: expected true or false, got 'yes'"):
        spec_from_dict(
            {
                "name": "x",
                "base": {"floating": "yes"},
                "joints": [{"axis": [0, 0, 1], "limits": {"lower": -1, "upper": 1, "unit": "rad"}}],
            }
        )


@settings(max_examples=30, deadline=None)
@given(kst.arm_specs(max_joints=5, trees=True, floating=True), kst.data())
def test_analytic_jacobian_of_a_floating_base_matches_finite_differences(spec, data):
    q = data.draw(kst.configuration_batches(spec, max_size=4))
    jac = geometric_jacobians(spec, frame_poses(spec, q), q)
    assert jac.shape[-1] == spec.nq
    fd = finite_difference_jacobians(lambda x: frame_poses(spec, x), q)
    assert np.abs(jac - fd).max() < 1e-6


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kst.arm_specs(max_joints=4, trees=True, floating=True).filter(lambda s: s.floating), kst.data())
def test_every_library_agrees_on_a_floating_base(spec, data):
    sources = ModelSources.from_spec(spec)
    q = data.draw(kst.configuration_batches(spec, max_size=4))
    backends = build_backends(sources)
    assert {b.name for b in backends} >= {"analytic", "pinocchio-urdf", "pinocchio-mjcf", "mujoco", "yourdfpy", "mujoco-urdf"}
    ref = backends[0].evaluate(q)
    for b in backends[1:]:
        ev = b.evaluate(q, with_jacobians=b.jacobian_method == "analytic")
        assert np.abs(ev.poses - ref.poses).max() < max(1e-9, pair_floor("fk.position", b), pair_floor("fk.rotation", b)), b.name
        if ev.jacobians is not None:
            floor = max(pair_floor("jacobian.linear", b), pair_floor("jacobian.angular", b))
            assert np.abs(ev.jacobians - ref.jacobians).max() < max(1e-9, floor), b.name
    pin = PinocchioDynamics(sources.urdf, sources.joint_names, [j.armature for j in spec.joints])
    mj = MujocoDynamics(sources.mjcf, sources.joint_names, rigid=True)
    # 1e-8 of the largest entry: at base pitch ±π/2 the two libraries' round-off in SᵀMS (the rate
    # matrix's entries there are cos(π/2) = 6e-17 and 1) was measured at 4e-9 of it
    rel = 1e-8
    for qk in q:
        m = pin.mass(qk)
        assert m.shape == (spec.nq, spec.nq) and np.allclose(m, m.T, atol=1e-12)
        assert np.abs(m - mj.mass(qk)).max() <= rel * max(1.0, np.abs(m).max())
        g = pin.gravity(qk)
        assert np.abs(g - mj.gravity(qk)).max() <= rel * max(1.0, np.abs(g).max())


def test_gravity_in_base_coordinates_is_the_gradient_of_the_potential_energy():
    import pinocchio

    spec = load_spec(MODELS / "space_arm.toml")
    sources = ModelSources.from_spec(spec)
    pin = PinocchioDynamics(sources.urdf, sources.joint_names, [0.0] * spec.dof)

    def energy(q):
        pinocchio.computePotentialEnergy(pin.model, pin.data, pin._q(q))
        return pin.data.potential_energy

    q = np.array([0.3, -0.2, 1.1, 0.4, -0.7, 2.0, 0.5, -1.0, 0.8])
    h = 1e-6
    gradient = np.array([(energy(q + h * e) - energy(q - h * e)) / (2 * h) for e in np.eye(len(q))])
    assert np.abs(gradient - pin.gravity(q)).max() < 1e-6
    assert pin.gravity(q)[2] == pytest.approx(
        sum(link.inertial.mass for link in (spec.base_link, *(j.link for j in spec.joints))) * 9.81
    )


@pytest.mark.parametrize("pitch", [math.pi / 2, -math.pi / 2, math.pi / 2 - 1e-12, -math.pi / 2 + 1e-10])
@pytest.mark.parametrize("turn", [0.0, 0.3])
def test_base_coordinates_of_a_pose_at_gimbal_lock_give_that_pose_back(pitch, turn):
    """At pitch ±π/2 only roll ∓ yaw is defined; the coordinates read back must still make the
    same pose, also after a conjugation's round-off (the entries that vanish there are ~1e-17)."""
    b = np.array([[0.1, -0.2, 0.3, 1.2, pitch, -0.7]])
    t = base_transforms(np.array([[0.0, 0.0, 0.42, turn, 0.2, -turn]]))[0]
    for pose in (base_transforms(b), t @ base_transforms(b) @ np.linalg.inv(t)):
        assert np.abs(base_transforms(base_coordinates(pose)) - pose).max() < 1e-12
