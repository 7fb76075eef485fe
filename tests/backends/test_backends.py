"""Every backend against the analytic reference on random valid specs and configurations,
including edge configurations (limits, zero, ±π/2)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings

from kinverify import load_spec
from kinverify.testing import strategies as kst
from kinverify.backends import FunctionBackend, ModelSources, available_backends, build_backends
from kinverify.backends import default_backend_names
from kinverify.backends.base import pair_floor
from kinverify.backends.pinocchio_ import PinocchioBackend
from kinverify.backends.yourdfpy_ import YourdfpyBackend
from kinverify.errors import KinverifyError, UnknownNameError
from kinverify.pipeline.sampling import spec_samples
from tests.paths import MODELS

TOL = 1e-9


def _agree(spec, q, float32=True):
    """Every backend against the first, each at its agreement floor (float32: Newton computes in it, a
    USD stores its joint frames in it); Newton only when ``float32`` (random specs leave it to
    tests/backends/test_newton.py: each build costs ~1 s)."""
    sources = ModelSources.from_spec(spec)
    backends = [
        b
        for b in build_backends(
            sources, [n for n in default_backend_names(sources) if float32 or available_backends()[n].extra != "newton"]
        )
    ]
    assert {b.name for b in backends} >= {"analytic", "pinocchio-urdf", "pinocchio-mjcf", "mujoco", "yourdfpy"}
    ref = backends[0].evaluate(q)
    for b in backends[1:]:
        ev = b.evaluate(q, with_jacobians=b.jacobian_method == "analytic")
        pos = np.abs(ev.poses - ref.poses).max()
        tol = max(TOL, pair_floor("fk.position", b), pair_floor("fk.rotation", b))
        assert pos < tol, f"{b.name}: FK differs by {pos:.3e} at q={q.tolist()}"
        if ev.jacobians is not None:
            jac = np.abs(ev.jacobians - ref.jacobians).max()
            tol = max(TOL, pair_floor("jacobian.linear", b), pair_floor("jacobian.angular", b))
            assert jac < tol, f"{b.name}: Jacobian differs by {jac:.3e}"


@settings(max_examples=40, deadline=None)
@given(kst.arm_specs(trees=True, floating=True), kst.data())
def test_all_backends_agree_on_random_specs(spec, data):
    q = data.draw(kst.configuration_batches(spec, max_size=8))
    _agree(spec, q, float32=False)


@pytest.mark.parametrize("path", sorted(str(p) for p in MODELS.glob("*.toml")))
def test_shipped_models_agree_at_edges_and_random_samples(path):
    spec = load_spec(path)
    _agree(spec, spec_samples(spec, 30, seed=1))


@pytest.mark.slow
@settings(max_examples=300, deadline=None)
@given(kst.arm_specs(trees=True), kst.data())
def test_all_backends_agree_on_random_specs_sweep(spec, data):
    _agree(spec, data.draw(kst.configuration_batches(spec, max_size=20)), float32=False)


def test_yourdfpy_follows_tiny_joint_changes():
    """trimesh skips transform updates below 1e-8 (backends/quirks.py); the adapter must not."""
    spec = load_spec("models/arm3.toml")
    sources = ModelSources.from_spec(spec)
    yd = YourdfpyBackend.from_urdf(sources.urdf, spec.joint_names, spec.frame_names)
    pn = PinocchioBackend.from_urdf(sources.urdf, spec.joint_names, spec.frame_names)
    for batch in ([[0.0, 0.0, 0.0], [0.0, 1e-9, 0.0]], [[0.3, 0.3, 0.3], [0.3, 0.3 + 1e-10, 0.3]], [[2e-9, 0.0, 0.0]]):
        q = np.array(batch)
        assert np.abs(yd.poses(q) - pn.poses(q)).max() < 1e-15
    # the raw library, by contrast, keeps the stale transform:
    yd.robot.update_cfg(np.zeros(3))
    yd.robot.update_cfg(np.array([0.0, 1e-9, 0.0]))
    assert yd.robot.get_transform("link2", "world")[0, 2] == 0.0


def test_seed_closed_form_as_a_user_backend():
    """The seed tutorial's hand-derived FK, plugged in as one more backend."""
    spec = load_spec("models/arm3.toml")

    def seed_fk(q):
        q1, q2, q3 = q.T
        r = 0.25 * np.sin(q2) + 0.05 * np.sin(q2 + q3)
        z = 0.42 + 0.1 + 0.3 + 0.25 * np.cos(q2) + 0.05 * np.cos(q2 + q3)
        return np.stack([r * np.cos(q1), r * np.sin(q1), z], axis=-1)

    user = FunctionBackend("seed-closed-form", seed_fk, spec.joint_names, ["end_effector"])
    assert not user.has_rotation
    q = spec_samples(spec, 200)
    ref = build_backends(ModelSources.from_spec(spec), ["analytic"])[0].poses(q)[:, -1, :3, 3]
    assert np.abs(user.poses(q)[:, 0, :3, 3] - ref).max() < 1e-12
    np.testing.assert_allclose(
        user.poses(np.array([[0, np.pi / 4, -np.pi / 4]]))[0, 0, :3, 3], [0.1767767, 0.0, 1.0467767], atol=5e-8
    )


def test_unknown_frame_lists_the_available_ones():
    spec = load_spec("models/arm3.toml")
    urdf = ModelSources.from_spec(spec).urdf
    with pytest.raises(UnknownNameError, match="unknown frame 'hand'; available frames: .*end_effector"):
        PinocchioBackend.from_urdf(urdf, spec.joint_names, ["hand"])


def test_backend_errors_are_kinverify_errors():
    with pytest.raises(KinverifyError, match="pinocchio-urdf: cannot load URDF"):
        PinocchioBackend.from_urdf("<robot name='x'><link name='a'/><joint name='j' type='revolute'/></robot>", ["j"], ["a"])


def test_registry_reports_every_backend():
    registry = available_backends()
    assert set(registry) >= {
        "analytic",
        "analytic-dh",
        "pinocchio-urdf",
        "pinocchio-mjcf",
        "mujoco",
        "yourdfpy",
        "drake-urdf",
        "drake-mjcf",
        "drake-sdf",
    }
    assert all(info.available for info in registry.values() if not info.extra)  # the core libraries always import
    for info in registry.values():  # an optional library: available, or says which extra brings it
        assert info.available or f"pip install 'kinverify[{info.extra}]'" in info.reason, info


@pytest.mark.parametrize("joint_type", ["revolute", "prismatic"])
def test_single_joint_arm(joint_type):
    # one DOF: some libraries return Jacobians as (6,) vectors rather than (6, 1) matrices
    from kinverify import spec_from_dict

    unit = "rad" if joint_type == "revolute" else "m"
    spec = spec_from_dict(
        {
            "name": "one",
            "joints": [
                {"type": joint_type, "axis": [0, 1, 0], "xyz": [0, 0, 0.1], "limits": {"lower": -0.5, "upper": 0.5, "unit": unit}}
            ],
            "tools": [{"name": "tip", "xyz": [0.2, 0, 0]}],
        }
    )
    _agree(spec, spec_samples(spec, 10))


def test_capabilities_are_declared_once_on_each_backend_class():
    """Jacobian method and cost come from the adapter class, the library from its registry line
    (read from the installed metadata, importing nothing): the report's versions and file mode's
    readers of each file are derived from the registry, not kept in side lists."""
    from kinverify.backends import available_backends, names_reading
    from kinverify.versions import library_versions
    from importlib import metadata

    versions = library_versions()
    for name, info in available_backends().items():
        if not info.available:  # an optional library not installed (its reason names the extra)
            continue
        cls = info.backend_class
        assert info.library and versions[info.library] == metadata.version(info.library), name
        assert cls.jacobian_method in ("analytic", "finite-difference", None)
    assert [n for n, i in available_backends().items() if i.available and i.backend_class.slow] == ["yourdfpy"]
    assert names_reading("urdf") == ("pinocchio-urdf", "yourdfpy", "mujoco-urdf", "drake-urdf", "newton-urdf")
    assert names_reading("mjcf") == ("mujoco", "pinocchio-mjcf", "drake-mjcf", "newton-mjcf")
    assert names_reading("sdf") == ("drake-sdf",)


@settings(max_examples=15, deadline=None)
@given(kst.arm_specs(max_joints=7), kst.data())
def test_one_frame_ik_paths_equal_the_full_evaluation(spec, data):
    """``frame_kinematics`` (IK's per-configuration path: one frame, one library call) gives the
    pose and Jacobian ``evaluate`` gives for that frame, on Pinocchio and MuJoCo."""
    q = data.draw(kst.configuration_batches(spec, 1, 3))
    sources = ModelSources.from_spec(spec)
    for backend in build_backends(sources, ["pinocchio-urdf", "pinocchio-mjcf", "mujoco", "mujoco-urdf"]):
        ev = backend.evaluate(q)
        for f in range(len(backend.frames)):
            fk, log3 = backend.frame_kinematics(f)
            for k in range(len(q)):
                rot, pos, jac = fk(q[k])
                np.testing.assert_allclose(rot, ev.poses[k, f, :3, :3], atol=1e-12)
                np.testing.assert_allclose(pos, ev.poses[k, f, :3, 3], atol=1e-12)
                np.testing.assert_allclose(jac, ev.jacobians[k, f], atol=1e-12)
                np.testing.assert_allclose(log3(rot), log3(ev.poses[k, f, :3, :3]), atol=1e-12)
