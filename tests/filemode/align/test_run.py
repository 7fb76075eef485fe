"""Which world the alignment keeps: a fixed base that MuJoCo merges into its world leaves nothing but
the first joint to place that world by, so a first body moved or turned is that joint's frame (one
finding on it), while an MJCF that keeps the base link as a body of its own and places it elsewhere
is a world transform (:func:`kinverify.filemode.align.run.unmoved_world`)."""

from __future__ import annotations

import dataclasses
import math

import mujoco
import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.filemode.align.fit import align
from kinverify.filemode.align.match import match
from kinverify.filemode.align.result import PairPoses
from kinverify.filemode.align.run import (
    add_frames,
    base_in_both,
    identity_alignment,
    run_alignment,
    sample_ranges,
    unmoved_world,
    zero_poses,
)
from kinverify.filemode.compare.context import FileModeInfo
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.filemode.read.model import Coupling, JointDesc, ModelDesc
from kinverify.filemode.read.precision import Floors
from kinverify.model.transforms import rpy_to_matrix
from kinverify.run import VerifyOptions
from tests.filemode.align.test_fit import move_world, remap_joint

ARM = """<robot name="arm">
  <link name="base_link"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="link1"><inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="link2"><inertial><origin xyz="0.1 0 0"/><mass value="0.5"/><inertia ixx="0.002" iyy="0.004" izz="0.004" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="joint1" type="revolute"><parent link="base_link"/><child link="link1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
  <joint name="joint2" type="revolute"><parent link="link1"/><child link="link2"/><origin xyz="0 0 0.2"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="1"/></joint>
</robot>"""
FIRST = '<body name="link1" pos="0 0 0.1">'
OPTIONS = VerifyOptions(samples=4, fd_samples=1, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics", "inertia"])


@pytest.fixture
def written(tmp_path):
    """The arm's URDF and the MJCF MuJoCo writes from it (base_link merged into the world)."""
    urdf = tmp_path / "arm.urdf"
    urdf.write_text(ARM)
    mujoco.mj_saveLastXML(str(tmp_path / "arm.xml"), mujoco.MjModel.from_xml_path(str(urdf)))
    text = (tmp_path / "arm.xml").read_text()
    assert FIRST in text and "base_link" not in text

    def run(mjcf: str):
        path = tmp_path / "edited.xml"
        path.write_text(mjcf)
        result = verify_files(str(urdf), str(path), OPTIONS)
        assert not result.internal_errors
        return [f for f in result.findings if f.severity == "error"]

    return text, run


def test_the_first_body_moved_where_the_mjcf_merges_the_base_is_that_joints_frame(written):
    text, run = written
    (f,) = run(text.replace(FIRST, '<body name="link1" pos="0.003 -0.004 0.1">'))
    assert (f.kind, f.subject, f.severity) == ("joint_origin_moved", "joint1", "error")
    assert f.magnitude == pytest.approx(0.005, abs=1e-12)
    assert f.values["xyz"] == pytest.approx([0.003, -0.004, 0.0], abs=1e-12)
    assert "base link base_link, which the MJCF merges into its world" in f.message


def test_the_first_body_turned_where_the_mjcf_merges_the_base_is_that_joints_frame(written):
    text, run = written
    half = 0.025  # a turn of 0.05 rad about x
    (f,) = run(text.replace(FIRST, f'<body name="link1" pos="0 0 0.1" quat="{math.cos(half)!r} {math.sin(half)!r} 0 0">'))
    assert (f.kind, f.subject, f.severity) == ("joint_origin_turned", "joint1", "error")
    assert f.magnitude == pytest.approx(0.05, abs=1e-9)
    assert f.values["axis"] == pytest.approx([1.0, 0.0, 0.0], abs=1e-9)


def test_a_base_link_body_the_mjcf_places_elsewhere_is_the_world_transform(written):
    text, run = written
    base = '<body name="base_link" pos="0.003 -0.004 0"><inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>'
    (f,) = run(text.replace(FIRST, base + FIRST).replace("</worldbody>", "</body></worldbody>"))
    assert (f.kind, f.severity) == ("base_transform", "error")
    assert f.magnitude == pytest.approx(0.005, abs=1e-12)
    assert f.values["xyz"] == pytest.approx([0.003, -0.004, 0.0], abs=1e-12)


def test_a_urdf_placing_the_merged_base_elsewhere_is_one_finding_that_says_both_readings(written, tmp_path):
    """The URDF's world places base_link 0.5 m along x, the MJCF (written from the URDF without that
    placement) merges base_link into its world: the first joint's frame moved, or equally the base
    placed elsewhere; one finding that says both, never two."""
    text, _ = written
    placed = ARM.replace(
        '<link name="base_link">',
        '<link name="world"/><joint name="place" type="fixed"><parent link="world"/><child link="base_link"/>'
        '<origin xyz="0.5 0 0"/></joint><link name="base_link">',
    )
    (tmp_path / "placed.urdf").write_text(placed)
    (tmp_path / "arm.xml").write_text(text)
    result = verify_files(str(tmp_path / "placed.urdf"), str(tmp_path / "arm.xml"), OPTIONS)
    (f,) = [f for f in result.findings if f.severity == "error"]
    assert (f.kind, f.subject, f.severity) == ("joint_origin_moved", "joint1", "error")
    assert f.magnitude == pytest.approx(0.5, abs=1e-12)
    assert "equally, where the URDF places that base link in its world" in f.message


# --- each step of the alignment stage, called directly on small pairs ---------------------------

ARM3 = P.generated_pair("arm3")
Q3 = np.array([[0.3, -0.4, 0.7], [-0.6, 0.2, -0.3], [1.2, 0.5, 0.1]])


def joint(name: str, kind: str, lower: float, upper: float) -> JointDesc:
    return JointDesc(name, kind, None, name + "_link", "base", np.array([0.0, 0.0, 1.0]), np.zeros(3), lower, upper)


def test_the_sampled_range_of_each_joint_is_its_limits_or_an_open_range():
    desc = ModelDesc("urdf", "pinocchio", [], {}, {}, {}, [])
    desc.joints = [
        joint("limited", "revolute", -0.5, 1.5),
        joint("continuous", "revolute", -math.inf, math.inf),
        joint("half", "prismatic", 0.0, math.inf),
        joint("stuck", "prismatic", 0.2, 0.2),
        joint("reversed", "revolute", 1.0, -1.0),
    ]
    lower, upper, revolute = sample_ranges(desc, ["continuous", "limited", "half", "stuck", "reversed"])
    assert lower == [-math.pi, -0.5, -0.5, -0.5, -math.pi]
    assert upper == [math.pi, 1.5, 0.5, 0.5, math.pi]
    assert revolute == [True, True, False, False, True]
    lower, upper, _ = sample_ranges(desc, [])
    assert (lower, upper) == ([], [])
    desc.joints[2] = joint("half", "prismatic", -math.inf, 0.3)
    assert sample_ranges(desc, ["half"])[:2] == ([-0.5], [0.5])


def pair(urdf: str, mjcf: str):
    u, m = describe_urdf(urdf), describe_mjcf(mjcf)
    matching = match(u, m)
    return u, m, matching


def test_the_identity_alignment_maps_each_matched_joint_as_it_is():
    u, _, matching = pair(*ARM3)
    matching.couplings = {"joint3": Coupling("joint3", "joint2", 2.0, 0.1, "<mimic>")}
    al = identity_alignment(u, matching)
    assert np.array_equal(al.T, np.eye(4)) and al.couplings is matching.couplings and al.independent == ["joint1", "joint2"]
    assert [(j.urdf, j.mjcf, j.type, j.sign, j.offset) for j in al.joints] == [(j, j, "revolute", 1, 0.0) for j in ("joint1", "joint2", "joint3")]  # fmt: skip


MOVED = move_world(ARM3[1], [0.1, 0.2, 0.3], [0.0, 0.0, 0.5])
T_MOVED = np.eye(4)
T_MOVED[:3, :3], T_MOVED[:3, 3] = rpy_to_matrix([0.0, 0.0, 0.5]), [0.1, 0.2, 0.3]


def test_the_alignment_stage_fits_and_says_nothing_when_it_succeeds():
    # the MJCF's world moved, its end effector 1 cm further out: the fit takes the world transform
    ee = P.sub_once(r'(<site name="end_effector" pos=")0.0 0.0 0.05', r"\g<1>0.0 0.0 0.06", MOVED)
    u, m, matching = pair(ARM3[0], ee)
    internal: list = []
    al, poses = run_alignment(u, m, matching, ARM3[0], ee, "pinocchio", Floors(), Q3, internal)
    assert al.T == pytest.approx(T_MOVED, abs=1e-9) and al.unexplained == 1 and internal == []
    assert isinstance(poses, PairPoses) and poses.ub.name == "pinocchio-urdf" and poses.u is u and poses.m is m
    # both floating: the base frames are kept when a world transform leaves anything unexplained
    al, poses = run_alignment(u, m, matching, ARM3[0], ee, "mujoco", Floors(), Q3, internal, base_fixes_frame=True)
    assert al.candidate == "base frames" and np.array_equal(al.T, np.eye(4)) and internal == []
    assert poses.ub.name == "mujoco-urdf"


def test_an_alignment_that_fails_is_said_and_the_files_are_compared_unaligned():
    u, m, matching = pair(ARM3[0], MOVED)
    internal: list = []
    al, poses = run_alignment(u, m, matching, ARM3[0], MOVED, "pinocchio", Floors(), np.zeros((2, 5)), internal)
    assert len(internal) == 1 and internal[0].startswith("alignment: ValueError: ")
    assert np.array_equal(al.T, np.eye(4)) and [(j.sign, j.offset) for j in al.joints] == [(1, 0.0)] * 3
    assert al.candidate == "" and isinstance(poses, PairPoses)


def test_every_frame_at_the_aligned_zero_the_other_file_in_its_own_world():
    u, m, matching = pair(ARM3[0], remap_joint(ARM3[1], "joint2", 1, 0.3))
    poses = PairPoses(u, m, matching, ARM3[0], remap_joint(ARM3[1], "joint2", 1, 0.3))
    al = identity_alignment(u, matching)
    al.joints[1].offset = 0.3
    pu, pm = zero_poses(poses, al)
    assert list(pu) == list(u.frames) and list(pm) == list(m.frames)
    for frame in ("base", "link1", "link2", "link3", "end_effector"):
        assert pu[frame] == pytest.approx(u.frames[frame], abs=1e-12) and pm[frame] == pytest.approx(pu[frame], abs=1e-12)
    # a follower at the zero of its leader: its coupling's offset (joint 3 turned 0.1 rad about y)
    al.couplings = {"joint3": Coupling("joint3", "joint2", 2.0, 0.1, "<mimic>")}
    al.independent = ["joint1", "joint2"]
    pu, _ = zero_poses(poses, al)
    tool = pu["link3"] @ np.array([0.0, 0.0, 0.05, 1.0])
    assert tool[:3] == pytest.approx([0.05 * math.sin(0.1), 0.0, 1.07 + 0.05 * math.cos(0.1)], abs=1e-12)


def test_frames_matched_after_the_alignment_coincide():
    u, _, matching = pair(*ARM3)
    al = identity_alignment(u, matching)
    add_frames(al, [("tool0", "tool_site", "same place")])
    (f,) = al.frames
    assert (f.urdf, f.mjcf, f.why, f.position, f.rotation, f.residual_position, f.residual_rotation, f.in_fit) == (
        "tool0", "tool_site", "same place", 0.0, 0.0, 0.0, 0.0, False,
    )  # fmt: skip
    assert np.array_equal(f.constant, np.eye(4))


def info_of(urdf: str, mjcf: str, samples=Q3):
    u, m, matching = pair(urdf, mjcf)
    poses = PairPoses(u, m, matching, urdf, mjcf)
    al = align(poses, matching, Floors(), samples)
    info = FileModeInfo(u, m, matching, al, Floors(), notes=["a note"])
    info.poses_u, info.poses_m = zero_poses(poses, al)
    return info, poses


def test_a_world_the_fit_moved_is_kept_where_the_base_has_a_frame_in_both_files():
    info, poses = info_of(ARM3[0], MOVED)
    assert base_in_both(info)
    assert unmoved_world(info, poses, Q3) is info
    same, poses = info_of(*ARM3)
    assert unmoved_world(same, poses, Q3) is same


TWO = ARM.replace(
    "</robot>",
    '<link name="link1b"><inertial><origin xyz="0 0.05 0"/><mass value="0.5"/>'
    '<inertia ixx="0.002" iyy="0.002" izz="0.002" ixy="0" ixz="0" iyz="0"/></inertial></link>'
    '<joint name="joint1b" type="revolute"><parent link="base_link"/><child link="link1b"/><origin xyz="0.2 0 0.1"/>'
    '<axis xyz="1 0 0"/><limit lower="-2" upper="2" effort="10" velocity="1"/></joint></robot>',
)
SECOND = '<body name="link1b" pos="0.2 0 0.1">'


@pytest.fixture(scope="module")
def merged(tmp_path_factory):
    """The MJCF MuJoCo writes from ARM and from TWO (ARM with a second chain on its base link)."""
    out = []
    for name, urdf in (("arm", ARM), ("two", TWO)):
        path = tmp_path_factory.mktemp(name) / f"{name}.urdf"
        path.write_text(urdf)
        mujoco.mj_saveLastXML(str(path.with_suffix(".xml")), mujoco.MjModel.from_xml_path(str(path)))
        out.append(path.with_suffix(".xml").read_text())
    return out


def test_a_world_the_fit_moved_where_the_mjcf_merges_the_base_is_the_first_joints_frame(merged):
    q = np.array([[0.3, -0.4], [1.0, 0.5]])
    info, poses = info_of(ARM, merged[0].replace(FIRST, '<body name="link1" pos="0.003 -0.004 0.1">'), q)
    assert not base_in_both(info) and info.alignment.T[:3, 3] == pytest.approx([0.003, -0.004, 0.0], abs=1e-9)
    kept = unmoved_world(info, poses, q)
    assert kept is not info and np.array_equal(kept.alignment.T, np.eye(4)) and kept.alignment.candidate == "identity"
    assert kept.notes == ["a note"] and kept.notes is not info.notes and kept.u is info.u
    assert kept.poses_u["link1"][:3, 3] == pytest.approx([0.0, 0.0, 0.1], abs=1e-12)
    assert kept.poses_m["link1"][:3, 3] == pytest.approx([0.003, -0.004, 0.1], abs=1e-12)
    assert info.alignment.attribution == {}  # counting the findings leaves the alignment as it was
    # the same files, nothing moved: nothing to weigh
    same, poses = info_of(ARM, merged[0], q)
    assert unmoved_world(same, poses, q) is same


def test_a_world_that_explains_what_the_first_joints_frames_would_each_say_is_kept(merged):
    # two chains on the merged base, both first bodies moved alike: one world transform rather
    # than two first joints' frames moved
    shift = merged[1].replace(FIRST, '<body name="link1" pos="0.003 -0.004 0.1">')
    shift = shift.replace(SECOND, '<body name="link1b" pos="0.203 -0.004 0.1">')
    q = np.array([[0.3, -0.4, 0.5], [1.0, 0.5, -0.2]])
    info, poses = info_of(TWO, shift, q)
    assert not base_in_both(info) and info.alignment.T[:3, 3] == pytest.approx([0.003, -0.004, 0.0], abs=1e-9)
    assert unmoved_world(info, poses, q) is info


def test_only_a_frame_no_joint_moves_in_either_file_is_a_base_of_its_own():
    u, m, matching = pair(*ARM3)
    info = FileModeInfo(u, m, matching, identity_alignment(u, matching))

    def framed(*frames):
        return dataclasses.replace(info, matching=dataclasses.replace(matching, frames=list(frames)))

    assert base_in_both(info)
    assert not base_in_both(framed(("ghost", "ghost", "same name")))  # a frame a file does not know is no base
    assert not base_in_both(framed(("ghost", "base", "same name")))
    assert not base_in_both(framed(("base", "ghost", "same name")))
    assert not base_in_both(framed(("base", "link1", "x"), ("link1", "base", "x")))
    assert base_in_both(framed(("link1", "link1", "x"), ("base", "base", "x")))
