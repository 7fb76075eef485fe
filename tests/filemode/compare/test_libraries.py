"""Every library's reading of each file compared like with like: given the same joint values; which
library reads which side, through which frames and constants, and what a refusal says."""

from __future__ import annotations

import math

import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.backends import names_reading
from kinverify.backends.mujoco_ import MujocoBackend
from kinverify.backends.sources import ModelSources
from kinverify.errors import InputError
from kinverify.filemode.align.result import FrameFit
from kinverify.filemode.compare.context import FileModeInfo
from kinverify.filemode.compare.libraries import _readable_frames, build_backends, rebuild_mjcf, side_names
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.model import Coupling
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


# --- build_backends on the generated arm3 pair, read by each library directly -----------------------

FRAMES = ("base", "link1", "link2", "link3", "end_effector")


@pytest.fixture(scope="module")
def arm3() -> tuple[str, str]:
    return P.generated_pair("arm3")


def view(arm3) -> FileModeInfo:
    """Spec mode's view of the pair: same names, the identity alignment."""
    urdf, mjcf = arm3
    names = ("joint1", "joint2", "joint3")
    return FileModeInfo.from_sources(ModelSources("arm3", names, (), (-1.0,) * 3, (1.0,) * 3, (True,) * 3, urdf=urdf, mjcf=mjcf))


def tight(_frame):
    return 1e-6, 1e-6


def built(info, arm3, wanted, texts=None):
    findings: list = []
    out = build_backends(info, *(texts or arm3), wanted, tight, findings)
    return out, findings


def test_each_library_reads_its_side_through_the_alignment(arm3):
    info = view(arm3)
    turn = np.eye(4)
    turn[:3, :3] = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]
    turn[:3, 3] = [0.1, 0.0, 0.2]
    info.alignment.T = turn
    out, findings = built(info, arm3, ["pinocchio-urdf", "mujoco", "pinocchio-mjcf", "analytic"])
    assert list(out) == ["pinocchio-urdf", "mujoco", "pinocchio-mjcf"] and findings == []  # analytic reads neither
    assert [(b.mode, b.frames, b.inner.name) for b in out.values()] == [
        ("urdf", FRAMES, "pinocchio-urdf"),
        ("mjcf", FRAMES, "mujoco"),
        ("mjcf", FRAMES, "pinocchio-mjcf"),
    ]
    assert out["pinocchio-urdf"].inner.joint_names == ("joint1", "joint2", "joint3") and out["pinocchio-urdf"].cols is None
    np.testing.assert_allclose(out["mujoco"].left, np.linalg.inv(turn), atol=1e-15)
    np.testing.assert_array_equal(out["pinocchio-urdf"].left, np.eye(4))
    np.testing.assert_array_equal(out["mujoco"].constants, np.broadcast_to(np.eye(4), (5, 4, 4)))
    assert out["pinocchio-urdf"].constants is None
    assert info.notes == []
    q = np.array([[0.3, -0.4, 0.5]])
    np.testing.assert_allclose(
        out["mujoco"].inner.poses(q)[0][:, :3, 3], out["pinocchio-urdf"].inner.poses(q)[0][:, :3, 3], atol=1e-9
    )


def test_a_frame_a_library_lacks_is_left_out_of_its_comparison(arm3):
    info = view(arm3)
    info.matching.frames = [("link2", "link2", "name"), ("link3", "ghost", "name"), ("end_effector", "end_effector", "name")]
    out, findings = built(info, arm3, ["pinocchio-urdf", "mujoco"])
    assert findings == []
    assert out["pinocchio-urdf"].frames == ("link2", "link3", "end_effector")
    assert out["mujoco"].frames == ("link2", "end_effector") and out["mujoco"].inner.frames == ("link2", "end_effector")
    assert len(out["mujoco"].constants) == 2
    assert info.notes == ["mujoco has no frame for ghost (compared on the other frames)"]


def test_the_readable_frames_are_those_the_library_knows(arm3):
    joints = ["joint1", "joint2", "joint3"]
    assert _readable_frames(MujocoBackend.from_mjcf, arm3[1], joints, ["link1", "ghost", "link3"], "mujoco") == [0, 2]
    assert _readable_frames(MujocoBackend.from_mjcf, arm3[1], joints, ["link1", "link3"], "mujoco") == [0, 1]


def fit(frame, position=0.0, rotation=0.0, residual=(0.0, 0.0), constant=None):
    constant = np.diag([-1.0, -1.0, 1.0, 1.0]) if constant is None else constant
    return FrameFit(frame, frame, "name", position, rotation, constant, residual[0], residual[1], True)


def test_a_frame_convention_is_a_constant_the_mjcf_side_is_read_through(arm3):
    info = view(arm3)
    turned = fit("end_effector", rotation=math.pi)
    info.alignment.frames = [
        turned,
        fit("link3", position=1e-3),  # moved by a constant
        fit("link2", rotation=math.pi, residual=(1e-5, 0.0)),  # a constant does not explain it
        fit("link1", position=1e-7, rotation=1e-7),  # within the tolerance: nothing to take out
        fit("base", rotation=math.pi, residual=(0.0, 1e-5)),
    ]
    out, _ = built(info, arm3, ["pinocchio-urdf", "mujoco"])
    constants = out["mujoco"].constants
    np.testing.assert_array_equal(constants[4], turned.constant)
    np.testing.assert_array_equal(constants[3], turned.constant)
    for k in (0, 1, 2):
        np.testing.assert_array_equal(constants[k], np.eye(4))
    # at the tolerance itself: no convention; a residual at it: one
    info.alignment.frames = [fit("link3", position=1e-6), fit("end_effector", rotation=1.0, residual=(1e-6, 1e-6))]
    constants = built(info, arm3, ["mujoco"])[0]["mujoco"].constants
    np.testing.assert_array_equal(constants[3], np.eye(4))
    np.testing.assert_array_equal(constants[4], np.diag([-1.0, -1.0, 1.0, 1.0]))


def test_the_base_coordinates_lead_when_both_files_float(arm3):
    info = view(arm3)
    info.base_coordinates = True  # a fixed pair asked for a floating base: each library says it cannot
    out, findings = built(info, arm3, ["pinocchio-urdf", "mujoco"])
    assert out == {}
    assert [(f.kind, f.values) for f in findings] == [
        ("parser_refused", {"file": "URDF", "backend": "pinocchio-urdf"}),
        ("parser_refused", {"file": "MJCF", "backend": "mujoco"}),
    ]
    # each library is named once, before what it says
    assert findings[0].message.startswith("pinocchio-urdf refuses the URDF: the configuration has a floating base")
    assert findings[1].message.startswith("mujoco refuses the MJCF: the configuration has a floating base")


def test_a_library_that_raises_anything_refuses_the_file(arm3):
    out, findings = built(view(arm3), arm3, ["pinocchio-urdf", "mujoco"], (arm3[0], None))
    assert list(out) == ["pinocchio-urdf"]
    (f,) = findings
    assert (f.kind, f.severity, f.values) == ("parser_refused", "warning", {"file": "MJCF", "backend": "mujoco"})
    assert f.message.startswith("mujoco refuses the MJCF: TypeError: ")


def test_yourdfpy_drives_only_the_urdfs_own_mimic_followers(arm3):
    info = view(arm3)
    info.alignment.couplings = {"joint3": Coupling("joint3", "joint2", 1.0, 0.0, "<mimic>")}
    info.alignment.independent = ["joint1", "joint2"]
    out, findings = built(info, arm3, ["pinocchio-urdf", "yourdfpy"])
    assert findings == []
    assert out["yourdfpy"].inner.joint_names == ("joint1", "joint2") and out["yourdfpy"].cols == [0, 1]
    assert out["yourdfpy"].mode == "urdf" and out["yourdfpy"].frames == FRAMES
    assert out["pinocchio-urdf"].inner.joint_names == ("joint1", "joint2", "joint3") and out["pinocchio-urdf"].cols is None
    # a coupling only the other file states is given to yourdfpy like to every library
    info.alignment.couplings = {"joint3": Coupling("joint3", "joint2", 1.0, 0.0, "<equality joint>")}
    out, _ = built(info, arm3, ["yourdfpy"])
    assert out["yourdfpy"].inner.joint_names == ("joint1", "joint2", "joint3") and out["yourdfpy"].cols == [0, 1, 2]


def test_a_rebuilt_mjcf_reading_keeps_all_but_its_left_transform(arm3):
    info = view(arm3)
    info.alignment.frames = [fit("end_effector", rotation=math.pi)]
    out, _ = built(info, arm3, ["mujoco"])
    old = out["mujoco"]
    left = np.eye(4)
    left[:3, 3] = [0.0, 0.0, 0.5]
    new = rebuild_mjcf(old, left)
    assert new.inner is old.inner and new.alignment is old.alignment and new.frames == old.frames
    assert new.mode == "mjcf"
    np.testing.assert_array_equal(new.left, left)
    np.testing.assert_array_equal(new.constants, old.constants)


# --- which libraries --------------------------------------------------------------------------------


def test_every_library_of_either_side_unless_some_are_asked_for():
    assert side_names(VerifyOptions(backends=None)) == list(names_reading("urdf") + names_reading("mjcf"))
    assert side_names(VerifyOptions(backends=["mujoco", "analytic", "yourdfpy"])) == ["mujoco", "yourdfpy"]
    assert side_names(VerifyOptions(backends=["drake-sdf", "mujoco"]), ("sdf", "mjcf")) == ["drake-sdf", "mujoco"]


def test_each_side_needs_a_library():
    with pytest.raises(InputError) as err:
        side_names(VerifyOptions(backends=["pinocchio-urdf", "analytic"]))
    first, second = ", ".join(names_reading("urdf")), ", ".join(names_reading("mjcf"))
    assert str(err.value) == (
        f"--backends: file mode needs a URDF backend ({first}) and an MJCF backend ({second}); got pinocchio-urdf, analytic"
    )
    with pytest.raises(InputError, match=r"needs a URDF backend .* and an MJCF backend .*; got mujoco$"):
        side_names(VerifyOptions(backends=["mujoco"]))
    with pytest.raises(
        InputError, match=r"needs an SDF backend \(drake-sdf\) and a USD backend \(usd, newton-usd\); got pinocchio-urdf$"
    ):
        side_names(VerifyOptions(backends=["pinocchio-urdf"]), ("sdf", "usd"))
