"""Every library's reading of each file compared like with like: given the same joint values."""

from __future__ import annotations

import tests.filemode.pairs as P
from kinverify.filemode.pipeline import verify_files
from kinverify.run import VerifyOptions

OPTIONS = VerifyOptions(samples=12, fd_samples=4, backends=["pinocchio-urdf", "yourdfpy", "mujoco"], suites=["kinematics"])


def read_alike(tmp_path, urdf: str, mjcf: str):
    """File mode with yourdfpy among the readers: it reads the URDF, and as Pinocchio does."""
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), OPTIONS)
    assert "yourdfpy" in result.backends
    assert not [f for f in result.findings if f.kind in ("parser_disagreement", "parser_refused")]
    assert not result.failed
    return result


def test_a_coupling_only_the_mjcf_states_is_given_to_yourdfpy_too(tmp_path):
    """The gripper's MJCF couples finger_right to finger_left (an <equality joint>); the URDF has
    no <mimic>. yourdfpy drives only the URDF's own <mimic> followers: it is given finger_right's
    value like every other library, so it reads the URDF as Pinocchio does, inside and outside
    the limits."""
    urdf, mjcf = P.generated_pair("gripper")
    mjcf = P.sub_once(
        r"</mujoco>",
        '<equality><joint joint1="finger_right" joint2="finger_left" polycoef="0 1 0 0 0"/></equality></mujoco>',
        mjcf,
    )
    result = read_alike(tmp_path, urdf, mjcf)
    assert [f.kind for f in result.findings if f.kind.startswith("coupling")] == ["coupling_one_file"]


def test_a_coupling_group_is_driven_through_the_joint_the_urdf_leaves_free(tmp_path):
    """The URDF's finger_left mimics finger_right (listed after it), and the MJCF states the same
    coupling: yourdfpy takes only the URDF's free joints as inputs, so the group is driven through
    finger_right, and yourdfpy reads the URDF as Pinocchio does."""
    urdf, mjcf = P.generated_pair("gripper")
    urdf = P.sub_once(
        r'(<joint name="finger_left" type="prismatic">)',
        lambda m: m[1] + '<mimic joint="finger_right" multiplier="1" offset="0"/>',
        urdf,
    )
    mjcf = P.sub_once(
        r"</mujoco>",
        '<equality><joint joint1="finger_left" joint2="finger_right" polycoef="0 1 0 0 0"/></equality></mujoco>',
        mjcf,
    )
    result = read_alike(tmp_path, urdf, mjcf)
    assert not [f for f in result.findings if f.kind.startswith("coupling")]


def test_a_frame_turned_by_a_constant_is_compared_through_it(tmp_path):
    # the MJCF's end_effector site turned 90° about z (another convention for the same frame): the
    # libraries' frames are compared through that constant, so nothing disagrees
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = P.sub_once(
        r'(<site name="end_effector" pos="0.0 0.0 0.05")', r'\1 quat="0.7071067811865476 0 0 0.7071067811865476"', mjcf
    )
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), OPTIONS)
    assert result.exit_code == 0 and result.passed
    assert not [f for f in result.findings if f.severity == "error"]
