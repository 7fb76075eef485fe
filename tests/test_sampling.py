"""``Samples``: any chunk of rows generated on demand equals the same rows of the full array."""

from __future__ import annotations

import pickle

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify import strategies as kst
from kinverify.sampling import Samples, sample_configurations


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
