"""Samples: reproducible, inside the limits, edges included."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify import strategies as kst
from kinverify.sampling import edge_configurations, spec_samples


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
