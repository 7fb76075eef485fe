"""Streaming error statistics: exact max/worst q, percentiles within the stated bound of numpy's,
bounded memory, and merges that do not depend on order where the module says so."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify.pipeline.stats import BINS_PER_OCTAVE, HIST_EDGES, PERCENTILE_RTOL, ErrorStats

PERCENTS = (0.0, 1.0, 25.0, 50.0, 90.0, 99.0, 99.9, 100.0)

errors_lists = st.lists(
    st.one_of(
        st.just(0.0), st.floats(1e-300, 1e10, allow_nan=False, allow_infinity=False), st.floats(0.0, 1e-6, allow_subnormal=True)
    ),
    min_size=1,
    max_size=400,
)


def _stats(values: np.ndarray, splits) -> ErrorStats:
    st_ = ErrorStats()
    for part, idx in zip(np.split(values, splits), np.split(np.arange(values.size), splits), strict=True):
        st_.update(part, idx[:, None].astype(float))
    return st_


def _assert_close(got: float, expected: float) -> None:
    assert abs(got - expected) <= PERCENTILE_RTOL * expected * (1 + 1e-9) + 1e-300, (got, expected)


@settings(max_examples=150, deadline=None)
@given(errors_lists, st.lists(st.integers(0, 400), max_size=5))
def test_streamed_percentiles_within_stated_bound_of_numpy(values, cuts):
    x = np.array(values)
    splits = sorted(c for c in cuts if c <= x.size)
    s = _stats(x, splits)
    assert s.count == x.size
    assert s.max_error == x.max()
    assert s.worst_q[0] == int(np.argmax(x))  # first occurrence of the max, like one pass
    for p in PERCENTS:
        _assert_close(s.percentile(p), float(np.percentile(x, p)))


@pytest.mark.parametrize("dist", ["lognormal", "uniform", "ties"])
def test_large_random_data_matches_numpy(dist):
    rng = np.random.default_rng(3)
    x = {
        "lognormal": np.exp(rng.normal(-30, 5, 200_000)),
        "uniform": rng.uniform(0, 1e-9, 200_000),
        "ties": np.repeat([0.0, 1e-15, 3e-12, 7e-10], 50_000),
    }[dist]
    s = _stats(x, list(range(7919, x.size, 7919)))
    for p in PERCENTS:
        _assert_close(s.percentile(p), float(np.percentile(x, p)))


def test_nan_and_inf_count_as_worst():
    s = ErrorStats()
    s.update(np.array([1e-12, np.nan, 2e-12]), np.arange(3.0)[:, None])
    assert s.max_error == np.inf and s.worst_q[0] == 1.0
    assert s.percentile(100) == np.inf
    _assert_close(s.percentile(0), 1e-12)


def test_memory_does_not_grow_with_count():
    """200 chunks of 10,000 errors over six decades: the bins held are bounded by the range."""
    rng = np.random.default_rng(0)
    s = ErrorStats()
    sizes = []
    for _ in range(200):
        s.update(10.0 ** rng.uniform(-16, -10, 10_000), np.zeros((10_000, 1)))
        sizes.append(np.count_nonzero(s._bins))
    assert s.count == 2_000_000
    assert s._bins.size <= 6 * np.log2(10) * BINS_PER_OCTAVE + 2  # the range, not the count
    assert sizes[-1] - sizes[len(sizes) // 2] <= 10  # saturated: no growth with N


def test_coarse_histogram_matches_numpy_histogram():
    rng = np.random.default_rng(1)
    x = np.concatenate([10 ** rng.uniform(-20, 3, 50_000), [0.0, 1e-18, 1e2, np.inf]])
    s = _stats(x, [10_000, 30_000])
    expected = np.histogram(np.clip(x, HIST_EDGES[0], HIST_EDGES[-1] * 0.999), bins=HIST_EDGES)[0]
    assert s.histogram.tolist() == expected.tolist()


@settings(max_examples=60, deadline=None)
@given(errors_lists, st.lists(st.integers(0, 400), max_size=4), st.randoms(use_true_random=False))
def test_merge_is_order_independent(values, cuts, rnd):
    x = np.array(values)
    splits = sorted(c for c in cuts if c <= x.size)
    parts = []
    for part, idx in zip(np.split(x, splits), np.split(np.arange(x.size), splits), strict=True):
        st_ = ErrorStats()
        st_.update(part, idx[:, None].astype(float))
        parts.append(st_)
    in_order, shuffled = ErrorStats(), ErrorStats()
    for p in parts:
        in_order.merge(p)
    order = list(range(len(parts)))
    rnd.shuffle(order)
    for i in order:
        shuffled.merge(parts[i])
    one_pass = _stats(x, splits)
    for a in (in_order, shuffled):
        assert a.count == one_pass.count and a.max_error == one_pass.max_error
        assert a.histogram.tolist() == one_pass.histogram.tolist()
        assert [a.percentile(p) for p in PERCENTS] == [one_pass.percentile(p) for p in PERCENTS]
    # worst_q: merging in chunk order reproduces one pass exactly, ties included
    assert in_order.worst_q.tolist() == one_pass.worst_q.tolist()
    if np.count_nonzero(x == x.max()) == 1:
        assert shuffled.worst_q.tolist() == one_pass.worst_q.tolist()
