"""The contract every registered property meets (in the spirit of qpsolvers' one test over all
solvers): perturbing one side's input by just over the tolerance fails the check, by just under
passes it, and the reported error is the perturbation's size. So a comparison of a side with
itself, a threshold off by a factor, a strict ``<`` where ``<=`` is meant, or two tolerances
swapped cannot survive. A new property needs a probe in ``probes.py``: this test says so."""

from __future__ import annotations

import pytest

from kinverify.suites.base import within
from kinverify.suites.registry import properties
from tests.suites.probes import MUST_CATCH, PROBES, QUANTIZED

ZERO_DEFAULT_PROBE = 1e-6  # a property whose default tolerance is 0 is also probed at this tolerance
OVER, UNDER = 1.01, 0.99


def test_an_error_equal_to_the_tolerance_passes_and_nan_never_does():
    assert within(1e-9, 1e-9) and within(0.0, 0.0) and not within(float("nan"), 1.0)
    assert not within(1e-9 * (1 + 1e-15), 1e-9)


@pytest.mark.parametrize("name", list(properties()))
def test_just_over_fails_and_just_under_passes(name):
    assert name in PROBES, f"{name} has no probe in tests/suites/probes.py"
    prop, probe = properties()[name], PROBES[name]
    tolerances = {}
    if name in QUANTIZED:
        tolerances = {name: QUANTIZED[name]}  # one item of the count: "just under" is exactly at it
    elif prop.tolerance == 0:
        tolerances = {name: ZERO_DEFAULT_PROBE}
    base = probe(0.0, tolerances)
    assert base.property == name and base.passed, base
    tol = base.tolerance  # in effect: the default or the override, times the magnitude where it scales
    assert tol > 0
    assert base.max_error <= tol / 10, f"{name}: the numerical noise {base.max_error:.3g} is within 10x of the tolerance"
    over, under = probe(OVER * tol, tolerances), probe(UNDER * tol, tolerances)
    assert not over.passed, over
    assert under.passed, under
    if name in QUANTIZED:
        assert under.max_error == pytest.approx(tol, rel=1e-12)  # an error equal to the tolerance passes
    else:
        assert over.max_error == pytest.approx(OVER * tol, rel=2e-3), over
        assert under.max_error == pytest.approx(UNDER * tol, rel=2e-3), under


@pytest.mark.parametrize("name", [n for n, p in properties().items() if p.tolerance == 0])
def test_a_zero_default_tolerance_fails_any_perturbation(name):
    smallest = QUANTIZED.get(name, 1e-9)
    assert PROBES[name](0.0, {}).passed
    assert not PROBES[name](smallest, {}).passed


@pytest.mark.parametrize("name", list(properties()))
def test_the_default_tolerance_catches_a_real_difference(name):
    assert name in MUST_CATCH, f"{name}: say in probes.MUST_CATCH what real difference it must catch"
    check = PROBES[name](MUST_CATCH[name], {})
    assert not check.passed, f"{name} at its default tolerance {check.tolerance:.3g} lets {MUST_CATCH[name]:.3g} through"


def test_every_probe_is_a_registered_property():
    assert set(PROBES) <= set(properties()), set(PROBES) - set(properties())
