"""The batched analytic FK (one (N,3)@(3,16) product per joint) against the plain chain
``T_i = T_{i-1} @ origin_i @ motion_i(q_i)`` on random valid specs and configurations."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings

from kinverify import strategies as kst
from kinverify.kinematics import frame_poses, joint_motion, link_poses


def _plain_chain(spec, q):
    t = np.broadcast_to(spec.base_origin.transform, (len(q), 4, 4))
    out = [t]
    for i, joint in enumerate(spec.joints):
        t = (t @ joint.origin.transform) @ joint_motion(joint, q[:, i])
        out.append(t)
    links = np.stack(out, axis=1)
    tools = [links[:, spec.link_index(tool.parent)] @ tool.origin.transform for tool in spec.tools]
    return links, np.concatenate([links] + [tt[:, None] for tt in tools], axis=1)


@settings(max_examples=60, deadline=None)
@given(kst.arm_specs(max_joints=8), kst.data())
def test_batched_fk_equals_plain_chain(spec, data):
    q = data.draw(kst.configuration_batches(spec, 1, 30))
    links, frames = _plain_chain(spec, q)
    np.testing.assert_allclose(link_poses(spec, q), links, rtol=0, atol=1e-12)
    got = frame_poses(spec, q)
    assert got.shape == (len(q), len(spec.frame_names), 4, 4)
    np.testing.assert_allclose(got, frames, rtol=0, atol=1e-12)
    assert np.all(got[..., 3, :] == [0.0, 0.0, 0.0, 1.0])


def test_single_configuration_vector():
    from kinverify.specfile import load_spec

    spec = load_spec("models/panda.toml")
    q = np.array([0, -np.pi / 4, 0, -3 * np.pi / 4, 0, np.pi / 2, np.pi / 4])
    flange = frame_poses(spec, q)[0, -1, :3, 3]
    np.testing.assert_allclose(flange, [0.30689, 0.0, 0.59028], atol=5e-5)  # Franka "ready" pose (panda.toml)
