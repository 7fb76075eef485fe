"""Assertion helpers: they pass on agreeing real backends, and fail with a message that names the
property, frame, backends, error, tolerance and a configuration ready to paste."""

from __future__ import annotations

import re
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings

from kinverify import load_spec
from kinverify.testing import strategies as kst
from kinverify.testing.assertions import (
    assert_files_agree,
    assert_fk_agree,
    assert_ik_valid,
    assert_jacobians_agree,
    assert_matches_baseline,
    resolve_backends,
)
from kinverify.backends import ModelSources, build_backend
from kinverify.generate import generate_urdf
from kinverify.model.kinematics import frame_poses
from kinverify.model.spec import Origin
from kinverify.model.transforms import geodesic_distance
from tests.paths import MODELS

ARM3 = load_spec(MODELS / "arm3.toml")


def longer_link2(spec, dz=0.001):
    joints = list(spec.joints)
    o = joints[2].origin
    joints[2] = replace(joints[2], origin=Origin((o.xyz[0], o.xyz[1], o.xyz[2] + dz), o.rpy))
    return replace(spec, joints=tuple(joints))


def pasted_q(message: str) -> np.ndarray:
    """The ``q = [...]`` line of a failure message, evaluated as Python."""
    (line,) = [ln.strip() for ln in message.splitlines() if ln.strip().startswith("q = [")]
    namespace: dict = {}
    exec(line, namespace)
    return np.array(namespace["q"])


def no_tiny_site_offsets(spec) -> bool:
    """MuJoCo quirk (found by the test below; not yet in kinverify.backends.quirks): a site whose
    offset from its body is below about 1e-6 m, or whose rotation is below about 2e-6 rad, is
    placed at the body frame (checked on mujoco 4.0 with one-site models). Tools are sites in the generated MJCF, so such specs disagree by
    the offset itself."""
    return not any(0 < abs(x) < 1e-5 for t in spec.tools for x in t.origin.xyz + t.origin.rpy)


@settings(max_examples=15, deadline=None)
@given(kst.data())
def test_real_backends_agree_on_random_arms(data):
    spec = data.draw(kst.arm_specs(max_joints=4).filter(no_tiny_site_offsets))
    q = data.draw(kst.configuration_batches(spec, max_size=5))
    assert_fk_agree(spec, q)
    assert_jacobians_agree(spec, q)


@settings(max_examples=15, deadline=None)
@given(kst.data())
def test_ik_valid_for_reachable_targets_in_every_backend(data):
    spec = data.draw(kst.arm_specs(max_joints=4))
    target = data.draw(kst.reachable_targets(spec))
    assert_ik_valid(spec, target.q, target.pose, target.frame)
    assert_ik_valid(spec, target.q, target.position, target.frame)


def test_ik_misses_and_limits_are_reported():
    q = np.array([0.3, -0.4, 1.1])
    target = kst.ReachableTarget("end_effector", q, frame_poses(ARM3, q)[0, -1])
    moved = target.pose.copy()
    moved[0, 3] += 1e-3
    with pytest.raises(AssertionError) as info:
        assert_ik_valid(ARM3, target.q, moved, target.frame)
    message = str(info.value)
    assert "ik.position" in message and "'end_effector'" in message and "1.000e-03 m > tolerance 1e-06 m" in message
    assert np.array_equal(pasted_q(message), target.q)
    with pytest.raises(AssertionError, match=r"ik.limits: joint 'joint2' at 2.0 is outside"):
        assert_ik_valid(ARM3, [0.0, 2.0, 0.0], target.pose)


def wrong_backends(name: str):
    """The analytic reference of arm3 and a real backend built from arm3 with link2 1 mm longer."""
    reference = resolve_backends(ARM3, ["analytic"])[0]
    return [reference, build_backend(name, ModelSources.from_spec(longer_link2(ARM3)))]


@pytest.mark.parametrize("backend", ["pinocchio-urdf", "mujoco"])
def test_fk_disagreement_names_the_first_frame_and_the_configuration(backend):
    q = np.array([[0.1, 0.2, 0.3], [0.4, -0.5, 1.2]])
    with pytest.raises(AssertionError) as info:
        assert_fk_agree(wrong_backends(backend), q)
    message = str(info.value)
    first = message.splitlines()[0]
    assert first == f"kinverify: fk.position disagrees at frame 'link3' (first along the chain): analytic vs {backend}"
    err = float(re.search(r"error (\S+) m > tolerance 1e-09 m", message).group(1))
    assert err == pytest.approx(1e-3, rel=1e-6)
    assert "(joint1, joint2, joint3)" in message
    assert any(np.array_equal(pasted_q(message), row) for row in q)
    assert "also failing: fk.position at 'end_effector'" in message


def test_jacobian_disagreement_is_reported():
    with pytest.raises(AssertionError) as info:
        assert_jacobians_agree(wrong_backends("pinocchio-urdf"), [0.3, 0.2, 0.1])
    message = str(info.value)
    assert "jacobian.linear disagrees at frame 'link3'" in message and "analytic vs pinocchio-urdf" in message
    assert np.array_equal(pasted_q(message), [0.3, 0.2, 0.1])


def test_matches_baseline_missing_update_and_moved(tmp_path):
    path = tmp_path / "baselines" / "arm3.json"
    with pytest.raises(AssertionError, match="--kinverify-update-baselines"):
        assert_matches_baseline(ARM3, path)
    assert assert_matches_baseline(ARM3, path, update=True) is None
    assert assert_matches_baseline(ARM3, path).passed
    with pytest.raises(AssertionError) as info:
        assert_matches_baseline(longer_link2(ARM3), path)
    message = str(info.value)
    # 4 kinematic quantities (FK and Jacobian of link3 and end_effector), plus dynamics and IK ones
    assert message.startswith(f"kinverify: arm3 does not match baseline {path}: ")
    assert "dynamics.mass_matrix at frame 'joint2'" in message and "ik.q at frame 'end_effector'" in message
    assert "fk.position at frame 'link3'" in message and "delta 1.000e-03 m > tolerance 1e-09" in message
    assert "why: the spec changed: joint joint3: origin.xyz [0, 0, 0.25] -> [0, 0, 0.251]" in message
    assert pasted_q(message).shape == (3,)
    assert assert_matches_baseline(longer_link2(ARM3), path, tolerance=0.1).passed  # IK moves ~0.03 rad


def test_yourdfpy_is_evaluated_fresh_at_each_configuration():
    q = np.array(
        [
            [0.5, -1.5707963267948966, -2.356194490192345],
            [0.0, -1.5707963267948966, -2.356194490192345],
            [1e-9, -1.5707963267948966, -2.356194490192345],
        ]
    )  # rows 2, 3 found by hypothesis
    reference, yourdfpy = resolve_backends(ARM3, ["analytic", "yourdfpy"])
    # trimesh alone would keep q[1]'s pose at q[2] (backends/quirks.py); the adapter must not
    assert geodesic_distance(reference.poses(q)[2, 2, :3, :3], yourdfpy.poses(q)[2, 2, :3, :3]) < 1e-15
    assert_fk_agree(ARM3, q, rotation_tol=1e-15, position_tol=1e-15)
    assert_jacobians_agree(ARM3, q)
    wrong = build_backend("yourdfpy", ModelSources.from_spec(longer_link2(ARM3)))
    with pytest.raises(AssertionError, match="fk.position disagrees at frame 'link3'.*analytic vs yourdfpy"):
        assert_fk_agree([reference, wrong], q)


@pytest.mark.parametrize("position, rotation", [(1e-6, 0.0), (0.0, 1e-6)])
def test_each_fk_tolerance_governs_its_own_measure(position, rotation):
    """A frame off by 1e-6 m (or turned by 1e-6 rad) fails under a tight tolerance for that
    measure whatever the other one is, and passes when only the other one is tight."""
    from tests.suites.probes import Perturbed, analytic

    backends = [analytic(), Perturbed(position=position, rotation=rotation)]
    q = np.array([[0.1, 0.2, 0.3], [0.4, -0.5, 1.2]])
    prop = "fk.position" if position else "fk.rotation"
    tight, loose = 1e-9, 1e-3
    with pytest.raises(AssertionError, match=f"{prop} disagrees at frame 'link2'"):
        if position:
            assert_fk_agree(backends, q, position_tol=tight, rotation_tol=loose)
        else:
            assert_fk_agree(backends, q, position_tol=loose, rotation_tol=tight)
    if position:
        assert_fk_agree(backends, q, position_tol=loose, rotation_tol=tight)
    else:
        assert_fk_agree(backends, q, position_tol=tight, rotation_tol=loose)


def test_files_agree_fails_listing_each_error_finding_and_passes_once_it_is_accepted(tmp_path):
    """A URDF and the MJCF MuJoCo writes from it, one mass then edited in the MJCF: the assertion
    lists that finding with its size; accepted in kinverify-accepted.toml beside the URDF, it passes."""
    urdf = kst.mesh_free_urdf(generate_urdf(load_spec(MODELS / "arm3.toml")))
    (tmp_path / "arm.urdf").write_text(urdf)
    mjcf = kst.mujoco_mjcf(urdf).replace('mass="0.763407"', 'mass="0.8"')
    (tmp_path / "arm.xml").write_text(mjcf)
    fast = dict(backends=["pinocchio-urdf", "mujoco"], samples=4)
    with pytest.raises(AssertionError) as failed:
        assert_files_agree(tmp_path / "arm.urdf", tmp_path / "arm.xml", **fast)
    lines = str(failed.value).splitlines()
    assert lines[0].endswith("arm.urdf and " + str(tmp_path / "arm.xml") + " disagree (fail)")
    assert lines[1:3] == [
        "  1 error finding:",
        "    mass_difference link2 (0.036593 kg): link2: mass 0.763407 kg (URDF) vs 0.8 kg (MJCF)",
    ]
    (tmp_path / "kinverify-accepted.toml").write_text(
        '[[accepted]]\nkind = "mass_difference"\nsubject = "link2"\nmagnitude = 0.036593\nunit = "kg"\n'
        'reason = "the MJCF\'s link2 carries a cable"\n'
    )
    result = assert_files_agree(tmp_path / "arm.urdf", tmp_path / "arm.xml", **fast)
    assert [(f.kind, f.accepted) for f in result.findings if f.severity == "error"] == [("mass_difference", True)]
