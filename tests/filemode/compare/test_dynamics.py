"""The dynamics of the two files compared as rigid bodies: what only MuJoCo adds is named and
left out, not reported as a residual nobody can place."""

from __future__ import annotations

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
