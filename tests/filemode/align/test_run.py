"""Which world the alignment keeps: a fixed base that MuJoCo merges into its world leaves nothing but
the first joint to place that world by, so a first body moved or turned is that joint's frame (one
finding on it), while an MJCF that keeps the base link as a body of its own and places it elsewhere
is a world transform (:func:`kinverify.filemode.align.run.unmoved_world`)."""

from __future__ import annotations

import math

import mujoco
import pytest

from kinverify.filemode.pipeline import verify_files
from kinverify.run import VerifyOptions

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
