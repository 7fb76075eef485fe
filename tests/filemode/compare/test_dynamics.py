"""The dynamics of the two files compared as rigid bodies: what only MuJoCo adds is named and
left out, not reported as a residual nobody can place."""

from __future__ import annotations

from dataclasses import replace

import tests.filemode.pairs as P
from kinverify.filemode.pipeline import verify_files
from kinverify.run import VerifyOptions

OPTIONS = VerifyOptions(
    samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], extra={"dynamics_samples": 12}, suites=P.NO_PICTURES
)


def test_gravity_compensation_is_named_and_left_out_of_the_rigid_body_comparison(tmp_path):
    """The MJCF cancels the weight of panda_link3 and panda_link4 (gravcomp="1"), which a URDF
    cannot say: one warning naming it, and the gravity, inverse and forward dynamics agree."""
    urdf, mjcf = P.generated_pair("panda")
    for body in ("panda_link3", "panda_link4"):
        mjcf = P.sub_once(rf'(<body name="{body}")', r'\1 gravcomp="1"', mjcf)
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), OPTIONS)
    above = [f for f in result.findings if f.severity != "info" and not P.ignored_by_drake(f)]
    gravcomp = [f for f in above if "gravcomp" in f.message]
    assert len(gravcomp) == 1 and gravcomp[0].severity == "warning"
    assert gravcomp[0].values["mjcf_gravcomp"] == {"panda_link3": 1.0, "panda_link4": 1.0}
    assert not [f for f in above if f.kind == "dynamics_difference"], [f.message for f in above]
    dynamics = {c.property: c.passed for c in result.checks if c.property.startswith("dynamics.")}
    assert dynamics["dynamics.gravity"] and dynamics["dynamics.inverse"] and dynamics["dynamics.forward"]
    assert result.passed


def joint2(mjcf: str, attr: str, value: str) -> str:
    return P.sub_once(rf'(<joint name="joint2"[^>]*? {attr}=")[^"]*(")', rf"\g<1>{value}\g<2>", mjcf)


def dynamics_findings(result) -> list:
    return [f for f in result.findings if f.kind.startswith(("damping", "friction"))]


def test_a_friction_difference_names_both_formats_words(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    result = verify_files(*P.write_pair(tmp_path, urdf, joint2(mjcf, "frictionloss", "0.5")), OPTIONS)
    (f,) = dynamics_findings(result)
    assert (f.kind, f.severity) == ("friction_difference", "error")
    assert f.message == "friction (URDF friction, MJCF frictionloss) 0 in the URDF, 0.5 in the MJCF on 1 joint: joint2"


def test_a_damping_difference_within_the_users_tolerance_is_not_reported(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    # 1e-4 N·m·s/rad apart, under a damping tolerance of 1e-3 (a difference the default 1e-12 reports)
    changed = joint2(mjcf, "damping", "0.1001")
    loose = replace(OPTIONS, tolerances={"dynamics.damping": 1e-3})
    assert 'damping="0.1001"' in changed and dynamics_findings(verify_files(*P.write_pair(tmp_path, urdf, changed), loose)) == []
