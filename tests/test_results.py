"""The verdict and its exit code: a kinverify bug (an internal error) outranks a failing check or
finding, which outranks a pass; each pinned by the smallest result where the order matters."""

from __future__ import annotations

import pytest

from kinverify.results import VerifyResult
from kinverify.suites.base import Check, Finding


def result(failing_check: bool = False, failing_finding: bool = False, internal: bool = False) -> VerifyResult:
    check = Check("fk.position", "link3", ("pinocchio-urdf", "mujoco"), 1e-3 if failing_check else 1e-12, 0.0, 1e-9,
                  not failing_check, (0.0,), unit="m")
    findings = [Finding("axis_direction", "error", "joint3: the axes differ", "joint3", "joint")] if failing_finding else []
    return VerifyResult("arm3", "spec", 0, 1, ["joint3"], ["link3"], ["pinocchio-urdf", "mujoco"], [check], {},
                        findings=findings, internal_errors=["suite inertia: ZeroDivisionError: division by zero"] if internal else [])


@pytest.mark.parametrize("kwargs, verdict, code", [
    ({}, "pass", 0),
    ({"failing_check": True}, "fail", 1),
    ({"failing_finding": True}, "fail", 1),
    ({"internal": True}, "error", 3),
    ({"internal": True, "failing_check": True}, "error", 3),  # a bug is not the models disagreeing
    ({"internal": True, "failing_finding": True}, "error", 3),
])
def test_the_verdict_and_its_exit_code(kwargs, verdict, code):
    r = result(**kwargs)
    assert (r.verdict, r.exit_code, r.passed) == (verdict, code, verdict == "pass")
    assert VerifyResult.from_dict(r.to_dict()).verdict == verdict


def test_an_accepted_error_finding_no_longer_fails():
    r = result(failing_finding=True)
    r.findings = [Finding("axis_direction", "error", "joint3: the axes differ", "joint3", "joint", accepted=True)]
    assert (r.verdict, r.exit_code) == ("pass", 0)
