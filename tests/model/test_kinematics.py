"""The analytic FK and geometric Jacobians (kinverify.kinematics), and the DH path."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify import load_spec, spec_from_dict
from kinverify.testing import strategies as kst
from kinverify.backends import finite_difference_jacobians
from kinverify.backends.analytic import AnalyticDHBackend
from kinverify.model.kinematics import frame_poses, geometric_jacobians, joint_motion, link_poses
from kinverify.pipeline.sampling import spec_samples


def test_seed_figure_for_arm3():
    spec = load_spec("models/arm3.toml")
    ee = frame_poses(spec, [0.0, np.pi / 4, -np.pi / 4])[0, spec.frame_names.index("end_effector"), :3, 3]
    np.testing.assert_allclose(ee, [0.1767767, 0.0, 1.0467767], atol=5e-8)
    exact = [0.25 * np.sin(np.pi / 4), 0.0, 0.42 + 0.1 + 0.3 + 0.25 * np.cos(np.pi / 4) + 0.05]
    assert np.abs(ee - exact).max() < 1e-15


@settings(max_examples=40, deadline=None)
@given(kst.arm_specs(trees=True), kst.data())
def test_geometric_jacobian_matches_finite_differences(spec, data):
    q = data.draw(kst.configuration_batches(spec, max_size=5))
    jac = geometric_jacobians(spec, frame_poses(spec, q))
    fd = finite_difference_jacobians(lambda x: frame_poses(spec, x), q)
    assert np.abs(jac - fd).max() < 1e-6


@settings(max_examples=20, deadline=None)
@given(kst.arm_specs(trees=True), kst.data())
def test_fk_is_batched_consistently(spec, data):
    q = data.draw(kst.configuration_batches(spec, min_size=2, max_size=6))
    batch = frame_poses(spec, q)
    single = np.stack([frame_poses(spec, qk)[0] for qk in q])
    assert np.abs(batch - single).max() < 1e-14
    rot = batch[..., :3, :3]
    assert np.abs(rot @ np.swapaxes(rot, -1, -2) - np.eye(3)).max() < 1e-12


_row = st.fixed_dictionaries(
    {
        "a": st.floats(-0.5, 0.5),
        "alpha": st.sampled_from([0, 90, -90, 180]) | st.floats(-180, 180),
        "d": st.floats(-0.5, 0.5),
        "theta": st.floats(-180, 180),
    }
)


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(["standard", "modified"]), st.lists(st.tuples(_row, st.booleans()), min_size=1, max_size=7), st.data())
def test_dh_matrices_agree_with_the_converted_chain(convention, rows, data):
    joints = [
        {
            "type": "prismatic" if p else "revolute",
            "dh": row,
            "limits": {"lower": -0.2, "upper": 0.2, "unit": "m"} if p else {"lower": -3, "upper": 3, "unit": "rad"},
        }
        for row, p in rows
    ]
    spec = spec_from_dict(
        {
            "name": "dh",
            "dh": {"convention": convention, "angle_unit": "deg"},
            "joints": joints,
            "tools": [{"name": "tcp", "xyz": [0, 0, 0.1]}],
        }
    )
    q = data.draw(kst.configuration_batches(spec, max_size=5))
    dh = AnalyticDHBackend(spec).poses(q)
    assert np.abs(dh - frame_poses(spec, q)).max() < 1e-12


def test_ur5e_home_pose_matches_the_published_dh_figure():
    spec = load_spec("models/ur5e.toml")
    tool = frame_poses(spec, np.zeros(6))[0, spec.frame_names.index("tool0"), :3, 3]
    # x = a2 + a3, y = -(d4 + d6), z = d1 - d5 (Universal Robots' DH table)
    np.testing.assert_allclose(tool, [-0.425 - 0.3922, -(0.1333 + 0.0996), 0.1625 - 0.0997], atol=1e-12)


def test_panda_flange_at_franka_ready_pose():
    spec = load_spec("models/panda.toml")
    q = [0, -np.pi / 4, 0, -3 * np.pi / 4, 0, np.pi / 2, np.pi / 4]
    flange = frame_poses(spec, q)[0, spec.frame_names.index("flange"), :3, 3]
    # Franka's ready pose puts the flange 0.107 m below link 7 at (0.307, 0, 0.59); the usual
    # (0.307, 0, 0.487) end-effector point adds the hand's 0.1034 m.
    np.testing.assert_allclose(flange, [0.30689, 0.0, 0.59028], atol=2e-5)


def test_edge_samples_are_inside_the_limits():
    for path in ("models/arm3.toml", "models/scara.toml", "models/panda.toml"):
        spec = load_spec(path)
        q = spec_samples(spec, 50, seed=3)
        assert np.all(q >= spec.lower) and np.all(q <= spec.upper)
        np.testing.assert_array_equal(q, spec_samples(spec, 50, seed=3))


def _plain_chain(spec, q):
    out = [np.broadcast_to(spec.base_origin.transform, (len(q), 4, 4))]
    for i, (joint, parent) in enumerate(zip(spec.joints, spec.parent_indices, strict=True)):
        out.append((out[parent] @ joint.origin.transform) @ joint_motion(joint, q[:, i]))
    links = np.stack(out, axis=1)
    tools = [links[:, spec.link_index(tool.parent)] @ tool.origin.transform for tool in spec.tools]
    return links, np.concatenate([links] + [tt[:, None] for tt in tools], axis=1)


@settings(max_examples=60, deadline=None)
@given(kst.arm_specs(max_joints=8, trees=True), kst.data())
def test_batched_fk_equals_plain_chain(spec, data):
    q = data.draw(kst.configuration_batches(spec, 1, 30))
    links, frames = _plain_chain(spec, q)
    np.testing.assert_allclose(link_poses(spec, q), links, rtol=0, atol=1e-12)
    got = frame_poses(spec, q)
    assert got.shape == (len(q), len(spec.frame_names), 4, 4)
    np.testing.assert_allclose(got, frames, rtol=0, atol=1e-12)
    assert np.all(got[..., 3, :] == [0.0, 0.0, 0.0, 1.0])


def test_single_configuration_vector():
    from kinverify.model.specfile import load_spec

    spec = load_spec("models/panda.toml")
    q = np.array([0, -np.pi / 4, 0, -3 * np.pi / 4, 0, np.pi / 2, np.pi / 4])
    flange = frame_poses(spec, q)[0, -1, :3, 3]
    np.testing.assert_allclose(flange, [0.30689, 0.0, 0.59028], atol=5e-5)  # Franka "ready" pose (panda.toml)
