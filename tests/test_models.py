"""Every shipped model verifies (the models CI stands behind) and prints at 80 columns, including
the two that exercise the verdict's semantics: a 1-DOF prismatic lift (units in m and N; its
position servo sags under gravity, which is a controller's performance, not a disagreement) and
arm3 with Coulomb friction (modelled by MuJoCo only, so compared as a parameter). A friction
mismatch between the URDF and the MJCF is still caught."""

from __future__ import annotations

import dataclasses

import pytest

from kinverify.backends import ModelSources
from kinverify.model.specfile import load_spec
from kinverify.run import VerifyOptions, verify
from tests.paths import MODELS
from tests.report.terminal_checks import assert_fits, render

SHIPPED = sorted(p.stem for p in MODELS.glob("*.toml"))
# the suites that can disagree; tracking (a controller's performance) runs in the lift's own test
QUICK = dict(samples=40, fd_samples=10, extra={"ik_targets": 10}, suites=["kinematics", "limits", "inertia", "ik", "dynamics"])


def _verify(name: str, **kw):
    return verify(ModelSources.from_spec(load_spec(MODELS / f"{name}.toml")), VerifyOptions(**{**QUICK, **kw}))


@pytest.mark.parametrize("name", SHIPPED)
def test_every_shipped_model_passes_and_prints_at_80_columns(name):
    """Every check passes, IK's performance checks included (every solver on every backend
    solves every target: the space arm's floating base skips IK, as its spec says), no finding
    stands, and the result printed at 80 columns, as a terminal and as a log, keeps every row
    on one line and every number whole."""
    result = _verify(name)
    assert result.verdict == "pass", [(c.property, c.backends, c.frame, c.max_error) for c in result.failed]
    floating = load_spec(MODELS / f"{name}.toml").floating  # no IK or velocity terms for a floating base
    assert {c.property for c in result.checks} >= {"fk.position", "jacobian.linear", "dynamics.gravity"} | (
        set() if floating else {"dynamics.inverse", "ik.cross_fk", "ik.failure_rate"}
    )
    ik = [c for c in result.checks if c.property.startswith("ik.")]
    assert all(c.passed for c in ik) and not result.findings, [(c.property, c.backends, c.max_error) for c in ik if not c.passed]
    for terminal in (True, False):
        assert_fits(render(result, 80, terminal), result, 80)


def test_the_lift_reports_metres_and_newtons_and_passes_although_its_position_servo_sags():
    result = _verify("lift", suites=["dynamics", "tracking"])
    units = {c.property: c.unit for c in result.checks}
    assert units["dynamics.gravity"] == "N" and units["dynamics.mass_matrix"] == "kg"
    assert units["tracking.computed-torque"] == "m"
    sag = next(c for c in result.checks if c.property == "tracking.position")
    assert sag.kind == "performance" and not sag.counts
    assert result.verdict == "pass"
    gated = _verify("lift", suites=["tracking"], gates={"tracking.position": None})
    assert gated.verdict == ("pass" if sag.passed else "fail")  # a gate makes the goal count


def test_friction_is_compared_as_a_parameter_and_a_mismatch_fails():
    spec = load_spec(MODELS / "arm3_friction.toml")
    assert {j.friction for j in spec.joints} == {0.5}
    sources = ModelSources.from_spec(spec)
    ok = verify(sources, VerifyOptions(samples=20, suites=["dynamics"]))
    friction = next(c for c in ok.checks if c.property == "dynamics.friction")
    assert ok.verdict == "pass" and friction.max_error == 0.0
    assert any("frictionloss" in n for n in ok.sections["dynamics"].notes)
    mjcf = sources.mjcf.replace('frictionloss="0.5"', 'frictionloss="0.4"', 1)
    assert mjcf != sources.mjcf
    bad = verify(dataclasses.replace(sources, mjcf=mjcf), VerifyOptions(samples=20, suites=["dynamics"]))
    failed = {c.property: c for c in bad.failed}
    assert set(failed) == {"dynamics.friction"}  # the state comparisons are not confused by it
    assert failed["dynamics.friction"].max_error == pytest.approx(0.1, abs=1e-12)
