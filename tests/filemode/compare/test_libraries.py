"""Every library's reading of each file compared like with like: given the same joint values."""

from __future__ import annotations

import tests.filemode.pairs as P
from kinverify.filemode.pipeline import verify_files
from kinverify.run import VerifyOptions


def test_a_coupling_only_the_mjcf_states_is_given_to_yourdfpy_too(tmp_path):
    """The gripper's MJCF couples finger_right to finger_left (an <equality joint>); the URDF has
    no <mimic>. yourdfpy drives only the URDF's own <mimic> followers: it is given finger_right's
    value like every other library, so it reads the URDF as Pinocchio does, inside and outside
    the limits."""
    urdf, mjcf = P.generated_pair("gripper")
    mjcf = P.sub_once(r"</mujoco>", '<equality><joint joint1="finger_right" joint2="finger_left" polycoef="0 1 0 0 0"/>'
                      "</equality></mujoco>", mjcf)
    options = VerifyOptions(samples=12, fd_samples=4, backends=["pinocchio-urdf", "yourdfpy", "mujoco"],
                            suites=["kinematics"])
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), options)
    assert "yourdfpy" in result.backends
    assert not [f for f in result.findings if f.kind in ("parser_disagreement", "parser_refused")]
    assert [f.kind for f in result.findings if f.kind.startswith("coupling")] == ["coupling_one_file"]
    assert not result.failed
