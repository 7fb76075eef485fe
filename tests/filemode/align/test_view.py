"""A file seen through the alignment: posed at the independent joints (followers computed from their
leaders), the other file's joints at ``s·q + o``, its world brought into the URDF's and each
frame's convention removed, gives the URDF's poses and Jacobians where the files are one robot;
its Jacobians are the derivatives of its poses (checked here by central differences), a floating
base's coordinates carried into the other world."""

from __future__ import annotations

import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.backends.base import finite_difference_jacobians
from kinverify.backends.function import FunctionBackend
from kinverify.backends.mujoco_ import MujocoBackend
from kinverify.backends.pinocchio_ import PinocchioBackend
from kinverify.backends.yourdfpy_ import YourdfpyBackend
from kinverify.filemode.align.result import Alignment, JointMap
from kinverify.filemode.align.view import AlignedBackend
from kinverify.filemode.read.model import Coupling
from kinverify.model.floating import BASE_COORDINATES, base_transforms
from kinverify.model.transforms import rpy_to_matrix
from tests.filemode.align.test_fit import move_world, remap_joint
from tests.filemode.align.test_floating import floating_arm3

URDF, MJCF = P.generated_pair("arm3")
JOINTS = ["joint1", "joint2", "joint3"]
FRAMES = ["base", "link1", "link2", "link3", "end_effector"]
Q = np.array([[0.3, -0.4, 0.7], [-1.0, 0.5, 0.2]])


def pose(rot, xyz) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = rot, xyz
    return t


def numeric(view, q) -> np.ndarray:
    """Central differences of the view's own poses (an independent derivative)."""
    return finite_difference_jacobians(view.poses, q, 1e-6)


@pytest.fixture(scope="module")
def urdf_side():
    return PinocchioBackend.from_urdf(URDF, JOINTS, FRAMES)


def coupled() -> Alignment:
    """joint3 follows joint2: q3 = 2·q2 + 0.1."""
    joints = [JointMap(j, j, "revolute") for j in JOINTS]
    return Alignment(np.eye(4), joints, {"joint3": Coupling("joint3", "joint2", 2.0, 0.1, "<equality joint>")}, JOINTS[:2])


def test_a_view_is_posed_at_the_independent_joints_with_followers_from_their_leaders(urdf_side):
    view = AlignedBackend(urdf_side, coupled(), FRAMES, "urdf")
    assert view.joint_names == ("joint1", "joint2") and view.frames == tuple(FRAMES) and view.name == "pinocchio-urdf"
    assert not view.floating and view.has_rotation and view.jacobian_method == "analytic" and not view.slow
    q = np.array([[0.3, -0.4], [-1.0, 0.5]])
    full = np.array([[0.3, -0.4, -0.7], [-1.0, 0.5, 1.1]])
    assert view.poses(q) == pytest.approx(urdf_side.poses(full), abs=1e-12)
    ev = view.evaluate(q)
    assert ev.backend == "pinocchio-urdf" and ev.frames == tuple(FRAMES)
    assert ev.poses == pytest.approx(urdf_side.poses(full), abs=1e-12)
    wanted = urdf_side.jacobians(full) @ np.array([[1.0, 0.0], [0.0, 1.0], [0.0, 2.0]])
    assert ev.jacobians == pytest.approx(wanted, abs=1e-12)
    assert view.jacobians(q) == pytest.approx(wanted, abs=1e-12)
    assert ev.jacobians == pytest.approx(numeric(view, q), abs=1e-7)
    assert view.evaluate(q, with_jacobians=False).jacobians is None
    with pytest.raises(ValueError, match=r"expected q of shape \(N, 2\)"):
        view.poses(Q)


# the MJCF: its world turned and shifted, joint 2 reversed with a zero 0.3 rad on, the end
# effector placed 1 cm further out and turned 0.4 rad about y (a frame convention)
T = pose(rpy_to_matrix([0.1, -0.2, 0.5]), [0.1, 0.2, 0.3])
OTHER = remap_joint(move_world(MJCF, [0.1, 0.2, 0.3], [0.1, -0.2, 0.5]), "joint2", -1, 0.3)
OTHER = P.sub_once(r'(<site name="end_effector" pos=")0.0 0.0 0.05"', r'\g<1>0.01 0.0 0.05" quat="0.98006658 0 0.19866933 0"', OTHER)  # fmt: skip


def mapped() -> Alignment:
    joints = [JointMap("joint1", "joint1", "revolute"), JointMap("joint2", "joint2", "revolute", -1, 0.3)]
    return Alignment(T, joints + [JointMap("joint3", "joint3", "revolute")], {}, JOINTS)


@pytest.fixture(scope="module")
def mjcf_side():
    return MujocoBackend.from_mjcf(OTHER, JOINTS, FRAMES)


def constants(urdf_side, mjcf_side) -> np.ndarray:
    """Each frame's constant: the URDF's pose at the zero, from the MJCF's brought into its world."""
    al = mapped()
    zero = np.zeros((1, 3))
    pm = np.linalg.inv(T) @ mjcf_side.poses(al.to_mjcf(zero))[0]
    return np.linalg.inv(pm) @ urdf_side.poses(zero)[0]


def test_the_other_file_seen_through_the_alignment_is_the_urdfs_poses_and_jacobians(urdf_side, mjcf_side):
    c = constants(urdf_side, mjcf_side)
    assert np.linalg.norm(c[-1][:3, 3]) == pytest.approx(0.01, abs=1e-8) and not np.allclose(c[-1][:3, :3], np.eye(3), atol=0.1)
    view = AlignedBackend(mjcf_side, mapped(), FRAMES, "mjcf", np.linalg.inv(T), list(c))
    assert view.joint_names == tuple(JOINTS) and view.name == "mujoco"
    ev = view.evaluate(Q)
    assert ev.poses == pytest.approx(urdf_side.poses(Q), abs=1e-7)
    assert view.poses(Q) == pytest.approx(urdf_side.poses(Q), abs=1e-7)
    assert ev.jacobians == pytest.approx(urdf_side.jacobians(Q), abs=1e-7)
    assert view.jacobians(Q) == pytest.approx(urdf_side.jacobians(Q), abs=1e-7)
    # without the constants: the MJCF's own frames, brought into the URDF's world
    bare = AlignedBackend(mjcf_side, mapped(), FRAMES, "mjcf", np.linalg.inv(T))
    assert bare.poses(Q) == pytest.approx(np.linalg.inv(T) @ mjcf_side.poses(Q * [1, -1, 1] + [0, 0.3, 0]), abs=1e-12)
    assert bare.evaluate(Q).jacobians == pytest.approx(numeric(bare, Q), abs=1e-7)


def test_a_library_that_drives_a_coupling_itself_is_given_the_other_joints_only(urdf_side):
    mimic = P.sub_once(
        r'(<joint name="joint3" type="revolute">.*?)(</joint>)',
        r'\1<mimic joint="joint2" multiplier="2.0" offset="0.1"/>\2',
        URDF,
    )
    inner = YourdfpyBackend.from_urdf(mimic, ["joint1", "joint2"], FRAMES)
    view = AlignedBackend(inner, coupled(), FRAMES, "urdf", pick=["joint1", "joint2"])
    assert view.slow and view.jacobian_method == "finite-difference" and view.joint_names == ("joint1", "joint2")
    q = np.array([[0.3, -0.4]])
    pinned = AlignedBackend(urdf_side, coupled(), FRAMES, "urdf")
    assert view.poses(q) == pytest.approx(pinned.poses(q), abs=1e-9)
    assert view.evaluate(q).jacobians == pytest.approx(pinned.jacobians(q), abs=1e-6)
    assert view.jacobians(q) == pytest.approx(pinned.jacobians(q), abs=1e-6)
    assert view.evaluate(q, with_jacobians=False).jacobians is None


def test_a_views_library_traits_are_its_inners(urdf_side):
    inner = PinocchioBackend.from_urdf(URDF, JOINTS, FRAMES)
    inner.fd_step, inner.agreement_floor, inner.slow = 3e-5, {"fk.position": 1e-6}, True
    view = AlignedBackend(inner, coupled(), FRAMES, "urdf")
    assert (view.fd_step, view.agreement_floor, view.slow) == (3e-5, {"fk.position": 1e-6}, True)
    assert view.constants is None and np.array_equal(view.left, np.eye(4)) and view.cols is None


FLOATING_URDF, FLOATING_MJCF = floating_arm3()
B = np.array([[0.1, -0.2, 0.3, 0.2, -0.1, 0.4, 0.3, -0.4, 0.7], [0.0, 0.5, -0.1, -0.3, 0.2, 0.1, -1.0, 0.5, 0.2]])


@pytest.fixture(scope="module")
def floating_mjcf():
    return MujocoBackend.from_mjcf(FLOATING_MJCF, BASE_COORDINATES + tuple(JOINTS), FRAMES)


def test_a_floating_base_leads_the_coordinates_as_they_are_in_its_own_world(floating_mjcf):
    al = Alignment(np.eye(4), [JointMap(j, j, "revolute") for j in JOINTS], {}, JOINTS)
    for mode in ("urdf", "mjcf"):
        view = AlignedBackend(floating_mjcf, al, FRAMES, mode)
        assert view.floating and view.joint_names == BASE_COORDINATES + tuple(JOINTS)
        assert view.poses(B) == pytest.approx(floating_mjcf.poses(B), abs=1e-12)
        assert view.evaluate(B).jacobians == pytest.approx(floating_mjcf.jacobians(B), abs=1e-12)
    # the URDF's world kept (mode urdf): no conjugation, even under a transform
    urdf_view = AlignedBackend(floating_mjcf, al, FRAMES, "urdf", np.linalg.inv(T))
    assert urdf_view.poses(B) == pytest.approx(np.linalg.inv(T) @ floating_mjcf.poses(B), abs=1e-12)


def test_a_floating_base_in_another_world_is_given_the_base_pose_there(floating_mjcf):
    # the MJCF side in a world T away: its base at T·B·T⁻¹, brought back by T⁻¹: B·T⁻¹ for its base body
    al = Alignment(T, [JointMap(j, j, "revolute") for j in JOINTS], {}, JOINTS)
    view = AlignedBackend(floating_mjcf, al, FRAMES, "mjcf", np.linalg.inv(T))
    poses = view.poses(B)
    base = np.linalg.inv(floating_mjcf.poses(np.zeros((1, 9)))[0, 0])  # the base body's own offset at the zero
    assert poses[:, 0] == pytest.approx(base_transforms(B[:, :6]) @ np.linalg.inv(T) @ np.linalg.inv(base), abs=1e-9)
    ev = view.evaluate(B)
    assert ev.poses == pytest.approx(poses, abs=1e-12)
    assert ev.jacobians == pytest.approx(numeric(view, B), abs=1e-6)
    # the joints' columns are as without the base's conjugation (a turn of the whole world)
    assert ev.jacobians[..., 6:] == pytest.approx(numeric(view, B)[..., 6:], abs=1e-6)


def test_a_library_given_some_joints_only_differentiates_through_those(urdf_side):
    # an analytic library given joints 1 and 2 (joint 3 held at its zero): its Jacobian's column
    # for joint 3 is zero, the others its own
    al = Alignment(np.eye(4), [JointMap(j, j, "revolute") for j in JOINTS], {}, JOINTS)
    inner = PinocchioBackend.from_urdf(URDF, JOINTS[:2], FRAMES)
    view = AlignedBackend(inner, al, FRAMES, "urdf", pick=JOINTS[:2])
    assert view.cols == [0, 1] and view.joint_names == tuple(JOINTS)
    assert view.poses(Q) == pytest.approx(urdf_side.poses(Q * [1, 1, 0]), abs=1e-12)
    jac = view.evaluate(Q).jacobians
    assert jac[..., :2] == pytest.approx(inner.jacobians(Q[:, :2]), abs=1e-12)
    assert np.array_equal(jac[..., 2], np.zeros_like(jac[..., 2]))
    assert jac == pytest.approx(numeric(view, Q), abs=1e-7)


def test_a_library_that_says_nothing_of_a_floating_base_has_none(urdf_side):
    inner = FunctionBackend("by hand", urdf_side.poses, JOINTS, FRAMES, jacobians=True)  # no ``floating`` of its own
    view = AlignedBackend(inner, coupled(), FRAMES, "urdf")
    assert not view.floating and view.joint_names == ("joint1", "joint2") and view.jacobian_method == "finite-difference"
    q = np.array([[0.3, -0.4]])
    assert view.poses(q) == pytest.approx(urdf_side.poses(np.array([[0.3, -0.4, -0.7]])), abs=1e-12)
