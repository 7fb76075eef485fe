"""Unset is not different: a value one file leaves unset (its format's default) and the other
states is a warning naming the silent file; two stated values that differ stay an error, even when
one of them is the default written out. Each case pinned by a pair built for it."""

from __future__ import annotations

import math

import pytest

import tests.filemode.pairs as P
from kinverify.filemode.findings.accepted import apply, Entry
from kinverify.filemode.pipeline import verify_files
from kinverify.run import VerifyOptions

FAST = VerifyOptions(
    samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], extra={"dynamics_samples": 12}, suites=P.NO_PICTURES
)


def run(tmp_path, urdf, mjcf):
    return verify_files(*P.write_pair(tmp_path, urdf, mjcf), FAST)


def kinds(result) -> list:
    """Findings above information, but the armature arm3's MJCF gives and a URDF cannot express."""
    return sorted(
        (f.kind, f.severity)
        for f in result.findings
        if f.severity != "info" and not P.ignored_by_drake(f) and f.kind != "inexpressible"
    )


def without_dynamics(urdf: str) -> str:
    return P.re.sub(r"<dynamics [^>]*/>", "", urdf)


def mjcf_damping(mjcf: str, value: float) -> str:
    return P.re.sub(r' damping="0\.1"', f' damping="{value}"', mjcf)


def test_damping_the_urdf_leaves_unset_is_a_warning_naming_it(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    result = run(tmp_path, without_dynamics(urdf), mjcf_damping(mjcf, 1.0))
    (f,) = [f for f in result.findings if f.kind == "damping_unset"]
    assert f.severity == "warning" and f.values["unset_in"] == "URDF" and (f.values["urdf"], f.values["mjcf"]) == (0.0, 1.0)
    assert "the URDF leaves damping unset" in f.message and "the MJCF states 1" in f.message
    assert kinds(result) == [("damping_unset", "warning")] and result.passed  # its checks are explained, not failed


def test_damping_written_out_as_zero_against_one_is_an_error(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    urdf = P.re.sub(r'<dynamics damping="0\.1"', '<dynamics damping="0.0"', urdf)  # the default, written out
    result = run(tmp_path, urdf, mjcf_damping(mjcf, 1.0))
    (f,) = [f for f in result.findings if f.kind == "damping_difference"]
    assert f.severity == "error" and f.values["unset_in"] is None and result.verdict == "fail"


def test_damping_an_mjcf_default_class_states_is_stated(tmp_path):
    """The MJCF gives damping through <default><joint damping=...>: stated, so an error."""
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = P.re.sub(r' damping="0\.1"', "", mjcf)
    mjcf = P.sub_once(r"<default>", '<default><joint damping="2"/>', mjcf)
    result = run(tmp_path, urdf, mjcf)
    assert [f.kind for f in result.findings if "damping" in f.kind] == ["damping_difference"]


def test_limits_the_mjcf_leaves_unset_are_a_warning(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = P.re.sub(r'(<joint name="joint1"[^>]*?) range="[^"]*"', r"\1", mjcf)
    result = run(tmp_path, urdf, mjcf)
    (f,) = [f for f in result.findings if f.kind == "limit_unset"]
    assert f.severity == "warning" and f.values["unset_in"] == "MJCF" and f.subject == "joint1"
    assert kinds(result) == [("limit_unset", "warning")] and result.passed


def test_a_servo_without_a_force_bound_is_an_unset_effort(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = P.re.sub(
        r'<motor name="(\w+)_motor" joint="(\w+)" ctrlrange="[^"]*"/>', r'<position name="\1_servo" joint="\2" kp="10"/>', mjcf
    )
    result = run(tmp_path, urdf, mjcf)
    (f,) = [f for f in result.findings if f.kind == "effort_unset"]
    assert f.severity == "warning" and f.values["unset_in"] == "MJCF" and f.magnitude == math.inf
    assert kinds(result) == [("effort_unset", "warning")]


def test_unset_findings_take_part_in_the_accepted_differences(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    result = run(tmp_path, without_dynamics(urdf), mjcf_damping(mjcf, 1.0))
    (f,) = [f for f in result.findings if f.kind == "damping_unset"]
    (accepted,) = [x for x in apply([f], [Entry(f.kind, f.subject, f.magnitude, f.unit, "simulation damping")], lambda _: 1e-9)]
    assert accepted.accepted and accepted.severity == "warning"
    assert accepted.magnitude == pytest.approx(1.0)


def test_a_joint_with_no_actuator_in_the_mjcf_has_an_unset_force_bound(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = P.re.sub(r'<motor name="joint3_motor"[^>]*/>', "", mjcf)
    result = run(tmp_path, urdf, mjcf)
    (f,) = [f for f in result.findings if f.kind == "effort_unset"]
    assert f.severity == "warning" and f.values["unset_in"] == "MJCF" and f.subject == "joint3"
    assert "no actuator" in f.message and kinds(result) == [("effort_unset", "warning")]


def test_a_joint_spring_the_urdf_cannot_express_is_a_warning(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = P.re.sub(r'(<joint name="joint2" )', r'\1stiffness="5" ', mjcf)
    result = run(tmp_path, urdf, mjcf)
    (f,) = [f for f in result.findings if f.kind == "stiffness_inexpressible"]
    assert f.severity == "warning" and f.subject == "joint2" and f.magnitude == 5.0
    assert kinds(result) == [("stiffness_inexpressible", "warning")] and result.passed  # springs are off in the dynamics


def test_a_continuous_urdf_joint_states_no_limits_so_an_mjcf_range_on_it_is_an_error(tmp_path):
    """``continuous`` says the joint has no position limits (stated, not left unset): the MJCF's
    ±π on joint1 is a limit difference (an error), not a limit the URDF leaves unset."""
    urdf, mjcf = P.generated_pair("arm3")
    urdf = P.sub_once(
        r'<joint name="joint1" type="revolute">(.*?)<limit lower="[^"]*" upper="[^"]*"',
        lambda m: f'<joint name="joint1" type="continuous">{m[1]}<limit',
        urdf,
    )
    result = run(tmp_path, urdf, mjcf)
    assert kinds(result) == [("limit_difference", "error")] and result.verdict == "fail"
    (f,) = [f for f in result.findings if f.kind == "limit_difference"]
    assert f.subject == "joint1" and f.values.get("unset_in") is None
