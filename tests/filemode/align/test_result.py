"""What an alignment holds: the joint map applied to configurations (couplings expanded from their
leaders, the other file's values ``s·q + o``), its derivative, each frame's constant convention;
and both files' poses, each read by the library its kind (and the URDF's reader) calls for."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.filemode.align.match import match
from kinverify.filemode.align.result import Alignment, FrameFit, JointMap, PairPoses
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.filemode.read.model import Coupling
from kinverify.generate.sdf import generate_sdf
from kinverify.generate.usd import generate_usd
from kinverify.model.specfile import load_spec
from tests.paths import MODELS


def coupled() -> Alignment:
    """Joints a, b, c, d (URDF order): b = 2·a + 0.1, d = −b + 0.5 (a coupling of a follower), c
    independent; the MJCF's b reversed, its c offset by 0.3."""
    joints = [JointMap("a", "A", "revolute"), JointMap("b", "B", "revolute", -1, 0.0), JointMap("c", "C", "prismatic", 1, 0.3)]
    joints.append(JointMap("d", "D", "revolute"))
    couplings = {"b": Coupling("b", "a", 2.0, 0.1, "<mimic>"), "d": Coupling("d", "b", -1.0, 0.5, "<mimic>")}
    return Alignment(np.eye(4), joints, couplings, ["a", "c"])


def test_the_independent_joints_expand_to_every_matched_joint_through_the_couplings():
    al = coupled()
    full = al.expand(np.array([[1.0, 2.0], [3.0, -4.0]]))
    assert full == pytest.approx(np.array([[1.0, 2.1, 2.0, -1.6], [3.0, 6.1, -4.0, -5.6]]), abs=1e-15)
    assert al.expand([0.5, 0.0]) == pytest.approx(np.array([[0.5, 1.1, 0.0, -0.6]]), abs=1e-15)  # one configuration
    assert al.expansion() == pytest.approx(np.array([[1.0, 0.0], [2.0, 0.0], [0.0, 1.0], [-2.0, 0.0]]), abs=1e-15)


def test_the_other_files_joint_values_are_sign_times_value_plus_offset():
    al = coupled()
    assert al.signs.dtype == float and al.signs.tolist() == [1.0, -1.0, 1.0, 1.0]
    assert al.offsets.tolist() == [0.0, 0.0, 0.3, 0.0]
    assert al.to_mjcf(np.array([[1.0, 2.0, 3.0, 4.0]])) == pytest.approx(np.array([[1.0, -2.0, 3.3, 4.0]]), abs=1e-15)
    assert al.joint("c") is al.joints[2]
    assert (al.residual, al.candidate, al.unexplained, al.frames, al.axis_errors, al.attribution) == (
        (0.0, 0.0),
        "",
        0,
        [],
        {},
        {},
    )


def test_a_frames_constant_convention_or_none():
    al = coupled()
    turned = np.diag([1.0, -1.0, -1.0, 1.0])
    al.frames.append(FrameFit("tool", "tool_site", "same name", 0.0, np.pi, turned, 0.0, 0.0, True))
    assert al.frame_constant("tool") is turned
    assert np.array_equal(al.frame_constant("tool_site"), np.eye(4))  # URDF names only
    assert Alignment(np.eye(4), [], {}, []).frames == [] and coupled().frames == []  # each alignment its own list


SPEC = load_spec(MODELS / "arm3.toml")
URDF, MJCF = P.generated_pair("arm3")
Q = np.array([[0.3, -0.4, 0.7], [-1.0, 0.5, 0.2]])


@pytest.fixture(scope="module")
def descs():
    u, m = describe_urdf(URDF), describe_mjcf(MJCF)
    return u, m, match(u, m)


@pytest.fixture(scope="module")
def reference(descs):
    """The MJCF's frames the URDF has too, posed by MuJoCo at Q."""
    u, m, matching = descs
    poses = PairPoses(u, m, matching, URDF, MJCF)
    return poses.mjcf(Q)[:, [poses.mi[f] for f in ("base", "link1", "link2", "link3", "end_effector")]]


def robot(desc) -> dict:
    """The frames of the robot itself (USD has no URDF world link)."""
    return {f: t for f, t in desc.frames.items() if f != "world"}


def urdf_side(poses: PairPoses, q) -> np.ndarray:
    return poses.urdf(q)[:, [poses.ui[f] for f in ("base", "link1", "link2", "link3", "end_effector")]]


@pytest.mark.parametrize(
    "kind, library, backend",
    [
        ("urdf", "pinocchio", "pinocchio-urdf"),
        ("urdf", "mujoco", "mujoco-urdf"),
        ("urdf", "drake", "drake-urdf"),
        ("sdf", "pinocchio", "drake-sdf"),
        ("usd", "pinocchio", "usd"),
    ],
)
def test_each_side_is_posed_by_the_library_its_kind_calls_for(descs, reference, kind, library, backend):
    u, m, matching = descs
    text = {"urdf": URDF, "sdf": generate_sdf(SPEC), "usd": generate_usd(SPEC)}[kind]
    first = dataclasses.replace(u, kind=kind, frames=robot(u))
    poses = PairPoses(first, m, matching, text, MJCF, library)
    assert poses.ub.name == backend and poses.mb.name == "mujoco"
    assert poses.ujoints == poses.mjoints == ["joint1", "joint2", "joint3"]
    assert poses.uframes == list(robot(u)) and poses.ui == {f: i for i, f in enumerate(robot(u))}
    assert urdf_side(poses, Q) == pytest.approx(reference, abs=1e-9)
    assert urdf_side(poses, Q[0]) == pytest.approx(reference[:1], abs=1e-9)  # one configuration


@pytest.mark.parametrize("kind, backend", [("sdf", "drake-sdf"), ("usd", "usd")])
def test_the_second_side_is_posed_by_its_kinds_library(descs, reference, kind, backend):
    u, m, matching = descs
    text = {"sdf": generate_sdf(SPEC), "usd": generate_usd(SPEC)}[kind]
    second = dataclasses.replace(u, kind=kind, frames=robot(u))  # the second file's frames, named as the URDF's
    poses = PairPoses(u, second, matching, URDF, text)
    assert poses.mb.name == backend and poses.mframes == list(robot(u))
    assert poses.ub.name == "pinocchio-urdf"  # the URDF's reader unless told otherwise
    assert poses.mi == {f: i for i, f in enumerate(robot(u))}
    assert poses.mjcf(Q[1])[0, [poses.mi[f] for f in ("base", "link1", "link2", "link3", "end_effector")]] == pytest.approx(
        reference[1], abs=1e-9
    )
