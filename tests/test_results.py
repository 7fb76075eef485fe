"""The verdict and its exit code: a kinverify bug (an internal error) outranks a failing check or
finding, which outranks a pass; each pinned by the smallest result where the order matters."""

from __future__ import annotations

import pytest

from kinverify.results import SCHEMA_VERSION, VerifyResult
from kinverify.suites.base import EXPLAINED, PERFORMANCE, Check, Finding, Section


def result(failing_check: bool = False, failing_finding: bool = False, internal: bool = False) -> VerifyResult:
    check = Check(
        "fk.position",
        "link3",
        ("pinocchio-urdf", "mujoco"),
        1e-3 if failing_check else 1e-12,
        0.0,
        1e-9,
        not failing_check,
        (0.0,),
        unit="m",
    )
    findings = [Finding("axis_direction", "error", "joint3: the axes differ", "joint3", "joint")] if failing_finding else []
    return VerifyResult(
        "arm3",
        "spec",
        0,
        1,
        ["joint3"],
        ["link3"],
        ["pinocchio-urdf", "mujoco"],
        [check],
        {},
        findings=findings,
        internal_errors=["suite inertia: ZeroDivisionError: division by zero"] if internal else [],
    )


@pytest.mark.parametrize(
    "kwargs, verdict, code",
    [
        ({}, "pass", 0),
        ({"failing_check": True}, "fail", 1),
        ({"failing_finding": True}, "fail", 1),
        ({"internal": True}, "error", 3),
        ({"internal": True, "failing_check": True}, "error", 3),  # a bug is not the models disagreeing
        ({"internal": True, "failing_finding": True}, "error", 3),
    ],
)
def test_the_verdict_and_its_exit_code(kwargs, verdict, code):
    r = result(**kwargs)
    assert (r.verdict, r.exit_code, r.passed) == (verdict, code, verdict == "pass")
    assert VerifyResult.from_dict(r.to_dict()).verdict == verdict


def test_an_accepted_error_finding_no_longer_fails():
    r = result(failing_finding=True)
    r.findings = [Finding("axis_direction", "error", "joint3: the axes differ", "joint3", "joint", accepted=True)]
    assert (r.verdict, r.exit_code) == ("pass", 0)


def fk(frame: str, error: float, backends=("pinocchio-urdf", "mujoco"), prop: str = "fk.position", **kw) -> Check:
    return Check(prop, frame, backends, error, error, 1e-9, error <= 1e-9, (0.1, 0.2), unit="m", **kw)


def chain(checks) -> VerifyResult:
    return VerifyResult(
        "arm3", "spec", 0, 2, ["joint1"], ["link1", "link2", "link3"], ["pinocchio-urdf", "mujoco"], list(checks), {}
    )


def test_the_first_failure_is_the_earliest_failing_frame_of_the_chain_per_property_and_pair():
    """Per (property, backend pair) the failing check on the earliest frame of the chain; frames off
    the chain (tools) come after it, and between equals the one listed first stays."""
    other = ("analytic", "mujoco")
    first_link2, second_link2 = fk("link2", 2e-3), fk("link2", 5e-3)
    r = chain(
        [
            fk("tool", 1e-3),
            fk("tool2", 1e-3),
            fk("link3", 1e-3),
            first_link2,
            second_link2,
            fk("link1", 0.0),
            fk("link3", 1e-3, other),
            fk("tool", 1e-3, prop="fk.rotation"),
            fk("tool2", 1e-3, prop="fk.rotation"),
        ]
    )
    assert [(c.property, c.frame, c.backends) for c in r.first_failures()] == [
        ("fk.position", "link2", ("pinocchio-urdf", "mujoco")),
        ("fk.position", "link3", other),
        ("fk.rotation", "tool", ("pinocchio-urdf", "mujoco")),
    ]
    assert r.first_failures()[0] is first_link2


def test_failed_missed_goals_and_explained_sort_the_failing_checks_by_kind():
    decisive, performance, gated = (
        fk("link1", 1e-3),
        fk("link2", 1e-3, kind=PERFORMANCE),
        fk("link3", 1e-3, kind=PERFORMANCE, gated=True),
    )
    explained, passing = fk("link3", 1e-3, kind=EXPLAINED), fk("link1", 0.0, kind=PERFORMANCE)
    r = chain([decisive, performance, gated, explained, passing])
    assert r.failed == [decisive, gated] and r.missed_goals == [performance] and r.explained == [explained]
    r.findings = [
        Finding("axis_direction", "error", "m", "j", "joint"),
        Finding("rounding", "info", "m", "j", "joint"),
        Finding("mass_difference", "error", "m", "l", "link", accepted=True),
    ]
    assert [f.kind for f in r.failing_findings] == ["axis_direction"]


def test_a_result_round_trips_through_its_dict_with_its_schema_version_and_verdict():
    r = chain([fk("link2", 1e-3), fk("link1", 0.0)])
    r.findings = [Finding("axis_direction", "error", "joint2: the axes differ", "joint2", "joint", magnitude=0.1, unit="rad")]
    r.sections = {"kinematics": Section("Kinematics", "2 checks", notes=["a note"], data={"k": [1, 2]})}
    r.notes, r.internal_errors, r.command = ["n"], ["suite x: E"], "kinverify verify m.toml"
    d = r.to_dict()
    assert (d["schema_version"], d["verdict"], d["model"], d["command"]) == (SCHEMA_VERSION, "error", "arm3", r.command)
    assert d["checks"][0]["frame"] == "link2" and d["findings"][0]["kind"] == "axis_direction"
    assert d["sections"]["kinematics"]["notes"] == ["a note"]
    back = VerifyResult.from_dict(d)
    assert back == r and back.to_dict() == d


def test_a_saved_result_under_an_old_property_name_reads_under_the_new_one():
    d = chain([fk("link1", 0.0, prop="ik.failure_rate"), fk("link2", 0.0)]).to_dict()
    d["checks"][0]["property"] = "ik.success_rate"
    d["findings"] = [{"kind": "rounding", "severity": "info", "message": "m"}, "not a finding"]
    d["sections"] = {"kinematics": {"title": "Kinematics"}, "broken": ["not", "a", "section"]}
    d["unknown_key"] = 1
    r = VerifyResult.from_dict(d)
    assert [c.property for c in r.checks] == ["ik.failure_rate", "fk.position"]
    assert [f.kind for f in r.findings] == ["rounding"] and list(r.sections) == ["kinematics"]
    assert r.sections["kinematics"].title == "Kinematics"
    bare = VerifyResult.from_dict(
        {k: d[k] for k in ("model", "source", "seed", "samples", "joint_names", "frames", "backends", "versions")}
    )
    assert (bare.checks, bare.findings, bare.sections, bare.verdict) == ([], [], {}, "pass")
