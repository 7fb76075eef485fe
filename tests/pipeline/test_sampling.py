"""Samples: reproducible, inside the limits, edges included."""

from __future__ import annotations

import pickle

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify.testing import strategies as kst
from kinverify.pipeline.sampling import Samples, edge_configurations, sample_configurations, spec_samples


@settings(max_examples=50, deadline=None)
@given(kst.arm_specs(), st.integers(0, 2**31))
def test_samples_lie_inside_limits_and_repeat_with_the_seed(spec, seed):
    q = spec_samples(spec, 20, seed)
    assert np.all(q >= spec.lower) and np.all(q <= spec.upper)
    np.testing.assert_array_equal(q, spec_samples(spec, 20, seed))


def test_edges_cover_limits_zero_and_half_pi():
    q = edge_configurations([-2.0, -0.1], [2.0, 0.3], [True, False])
    assert any(np.allclose(row, [-2.0, 0.0]) for row in q)
    assert any(np.allclose(row, [2.0, 0.0]) for row in q)
    assert any(np.allclose(row, [np.pi / 2, 0.0]) for row in q)
    assert any(np.allclose(row, [-np.pi / 2, 0.0]) for row in q)
    assert any(np.allclose(row, [0.0, 0.3]) for row in q)
    assert not any(np.isclose(row[1], np.pi / 2) for row in q)  # prismatic: no ±π/2
    assert len({tuple(r) for r in q}) == len(q)


def test_home_is_mid_range_when_zero_is_outside():
    q = edge_configurations([0.5], [1.5], [True])
    np.testing.assert_allclose(q[0], [1.0])


@settings(max_examples=40, deadline=None)
@given(kst.arm_specs(max_joints=5), st.integers(0, 300), st.integers(0, 2**32 - 1), st.integers(1, 97), st.booleans())
def test_chunks_equal_the_full_array(spec, n, seed, size, edges):
    revolute = [j.type == "revolute" for j in spec.joints]
    full = sample_configurations(spec.lower, spec.upper, revolute, n, seed, edges)
    s = Samples(spec.lower, spec.upper, revolute, n, seed, edges)
    assert s.shape == full.shape and len(s) == len(full)
    parts = [s.rows(a, b) for a, b in s.chunks(size)]
    assert np.array_equal(np.concatenate(parts) if parts else np.empty((0, spec.dof)), full)
    assert np.array_equal(np.asarray(s), full)
    if len(full):
        k = seed % len(full)
        assert np.array_equal(s[k], full[k]) and np.array_equal(s[-1], full[-1])
        assert np.array_equal(s[k:], full[k:]) and np.array_equal(s[::3], full[::3])
    restored = pickle.loads(pickle.dumps(s))
    assert np.array_equal(np.asarray(restored), full)


def test_rows_inside_limits():
    s = Samples([-1.0, 0.0], [1.0, 0.2], [True, False], 5000, seed=4)
    q = s.rows(1000, 4000)
    assert q.shape == (3000, 2)
    assert np.all(q >= [-1.0, 0.0]) and np.all(q <= [1.0, 0.2])
