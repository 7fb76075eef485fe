"""The heat map: every check in exactly one cell, columns named by the backend under test, colours
ordered by error ÷ tolerance, short numbers that stay faithful."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify.backends import ModelSources
from kinverify.model.specfile import load_spec
from kinverify.report import matrix
from kinverify.run import VerifyOptions, verify
from kinverify.suites.base import Check
from tests.paths import MODELS


@pytest.fixture(scope="module")
def result():
    opts = VerifyOptions(samples=10, suites=["kinematics", "ik", "dynamics"], extra={"ik_targets": 5})
    return verify(ModelSources.from_spec(load_spec(MODELS / "arm3.toml")), opts)


def test_every_check_is_in_one_cell_grouped_by_suite_in_registry_order(result):
    groups = matrix.groups(result)
    assert [g.suite for g in groups] == ["kinematics", "ik", "dynamics"]
    cells = [c for g in groups for r in g.rows for cell in r.cells.values() for c in cell.checks]
    assert sorted(map(id, cells)) == sorted(map(id, result.checks))
    kin = groups[0]
    assert kin.columns[0] == "analytic" and set(kin.columns) == set(result.backends)  # analytic: its FD column
    assert {r.property: r.against for r in kin.rows}["fk.position"] == "vs analytic"
    assert {r.property: r.against for r in kin.rows}["jacobian.fd"] == "vs finite-difference"
    assert groups[2].single  # dynamics: one pair per row, collapsed to one column


@pytest.mark.parametrize(
    "pair, column, against",
    [
        (("analytic", "mujoco"), "mujoco", "analytic"),  # the reference is never the one tested
        (("mujoco", "analytic"), "mujoco", "analytic"),
        (("mujoco", "finite-difference"), "mujoco", "finite-difference"),
        (("plan", "mujoco"), "mujoco", "plan"),
        (("mujoco", "mujoco"), "mujoco", "goal"),
        (("pinocchio-urdf", "mujoco"), "pinocchio-urdf", "mujoco"),
        (("urdf", "mjcf"), "urdf", "mjcf"),
    ],
)
def test_column_of_a_pair(pair, column, against):
    assert matrix.column_of(pair, ["analytic", "pinocchio-urdf", "mujoco"], "analytic") == (column, against)


def _check(err: float, tol: float = 1e-9, kind: str = "agreement") -> Check:
    from kinverify.suites.base import within

    return Check("p", "f", ("a", "b"), err, err, tol, within(err, tol), (), "m", 10, (), "", kind)


def _luminance(hex_colour: str) -> float:
    r, g, b = (int(hex_colour[i : i + 2], 16) for i in (1, 3, 5))
    return 0.2126 * r + 0.7152 * g + 0.0722 * b


@settings(max_examples=60, deadline=None)
@given(st.floats(1e-15, 1.0), st.floats(1e-15, 1.0))
def test_passing_cells_lighten_towards_the_tolerance(a, b):
    lo, hi = sorted((a, b))

    def colour(r):
        return matrix.colour(r, True, False)[0]

    assert _luminance(colour(lo)) <= _luminance(colour(hi)) + 1.0  # rounding of the interpolated channels
    assert colour(hi) != matrix.colour(2.0, False, False)[0]


def test_failing_and_missed_goal_colours():
    fail, _ = matrix.colour(math.inf, False, False)
    missed, _ = matrix.colour(3.0, False, True, counts=False)
    gated, _ = matrix.colour(3.0, False, True, counts=True)
    assert fail == gated == "#%02x%02x%02x" % matrix.FAIL_COLOUR and missed == "#%02x%02x%02x" % matrix.BELOW_GOAL_COLOUR
    assert matrix.ratio(_check(0.0, 0.0)) == 0 and matrix.ratio(_check(1e-3, 0.0)) == math.inf
    assert math.isnan(matrix.ratio(_check(math.nan)))


@settings(max_examples=200, deadline=None)
@given(st.one_of(st.floats(0, 1e300), st.just(0.0)))
def test_short_numbers_fit_a_cell_and_stay_within_their_rounding(x):
    text = matrix.short(x)  # errors are never negative
    assert len(text) <= 6, text
    if x == 0:
        assert text == "0"
    else:
        assert abs(float(text) - x) <= 0.5 * abs(x)  # one significant digit at least
