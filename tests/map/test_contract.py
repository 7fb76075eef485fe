"""``map_files`` on a small arm written twice (tests/map/robot.py): the files and an actuator table
that agree are one verdict, and each planted difference is one named finding with its size."""

from __future__ import annotations

import math

import pytest

from kinverify.errors import InputError
from kinverify.map.contract import MapOptions, map_files
from tests.map import robot


def run(tmp_path, table=None, **files):
    paths = robot.write(tmp_path, **files)
    options = MapOptions(actuators=robot.write(tmp_path, actuators_toml=table)[0] if table else None)
    return map_files(paths, options)


def serious(result):
    return [f for f in result.findings if f.severity != "info"]


def test_mjcf_gains_k_180_over_pi_agree_with_a_table_per_degree(tmp_path):
    result = run(tmp_path, robot.table(units="degree"), arm_urdf=robot.urdf(), arm_xml=robot.mjcf())
    assert serious(result) == [] and result.exit_code == 0
    table = result.sides[2]
    assert table.joint("shoulder").stiffness == pytest.approx(8.0 * 180 / math.pi)  # per radian inside
    assert result.sides[1].joint("shoulder").stiffness == pytest.approx(8.0 * 180 / math.pi)


def test_a_planted_permutation_is_one_joint_order_finding(tmp_path):
    result = run(tmp_path, arm_urdf=robot.urdf(order=("elbow", "shoulder", "wrist")), arm_xml=robot.mjcf())
    (f,) = serious(result)
    assert (f.kind, f.severity, f.magnitude, f.unit) == ("joint_order", "error", 2, "joints")
    assert set(f.subject.split(", ")) == {"shoulder", "elbow"}
    maps = {(m["from"], m["to"]): m["index"] for m in result.maps["joints"]}
    assert maps[("arm.urdf", "arm.xml")] == [1, 0, 2, 3, 4]  # q_xml = q_urdf[index]
    assert result.exit_code == 1


def test_a_gain_off_by_180_over_pi_is_one_units_finding(tmp_path):
    result = run(tmp_path, robot.table(units="radian", stiffness_per_degree=True), arm_xml=robot.mjcf())
    (f,) = serious(result)
    assert (f.kind, f.property, f.severity) == ("stiffness_units", "stiffness", "error")
    assert f.values["ratio"] == pytest.approx(math.pi / 180, rel=1e-9)
    assert f.magnitude == pytest.approx(8.0 * (180 / math.pi - 1))  # N·m/rad, the shoulder's
    assert "per radian read as per degree" in f.message


def test_a_dropped_armature_is_one_unset_warning_with_its_size(tmp_path):
    result = run(tmp_path, arm_xml=robot.mjcf(), dropped_xml=robot.mjcf(armature=False))
    (f,) = result.findings
    assert (f.kind, f.severity, f.magnitude, f.unit) == ("armature_unset", "warning", robot.ARMATURE, "kg·m² or kg")
    assert "dropped.xml leaves it unset" in f.message and len(f.subject.split(", ")) == 5
    assert result.exit_code == 0


def test_a_driven_mimic_follower_is_one_finding_in_a_file(tmp_path):
    result = run(tmp_path, arm_urdf=robot.urdf(), arm_xml=robot.mjcf(follower_actuator=True))
    (f,) = serious(result)
    assert (f.kind, f.subject, f.values["file"], f.magnitude) == ("driven_follower", "finger_b", "arm.xml", 100.0)


def test_a_table_regex_that_drives_the_mimic_follower_is_one_finding(tmp_path):
    result = run(tmp_path, robot.table(fingers="finger_.*"), arm_urdf=robot.urdf(), arm_xml=robot.mjcf())
    (f,) = serious(result)
    assert (f.kind, f.subject, f.values["file"]) == ("driven_follower", "finger_b", "actuators.toml")
    assert "arm.urdf" in f.message and "<mimic>" in f.message


def test_keyframe_is_the_default_pose_and_an_unknown_one_is_bad_input(tmp_path):
    paths = robot.write(tmp_path, arm_xml=robot.mjcf(), other_xml=robot.mjcf())
    result = map_files(paths, MapOptions(keyframe="home"))
    assert [j.default for j in result.sides[0].joints] == pytest.approx([0.1, -0.2, 0.3, 0.01, 0.01])
    with pytest.raises(InputError, match="no such keyframe; keyframes: home"):
        map_files(paths, MapOptions(keyframe="stand"))


def test_mjcf_actuator_order_and_the_joint_to_actuator_map(tmp_path):
    text = robot.mjcf().replace('<position name="act_shoulder"', '<position name="act_zz"', 1)
    moved = text[text.index('<position name="act_zz"') : text.index('<position name="act_elbow"')]
    text = text.replace(moved, "").replace('<position name="act_finger"', moved + '<position name="act_finger"')
    result = run(tmp_path, arm_xml=robot.mjcf(), moved_xml=text)
    (f,) = serious(result)
    assert (f.kind, f.magnitude) == ("actuator_order", 3)
    to_ctrl = {(m["from"], m["to"]): m["index"] for m in result.maps["joints_to_actuators"]}
    assert to_ctrl[("arm.xml", "moved.xml")] == [1, 2, 0, 3]  # ctrl_moved = q_arm[index]


def test_an_inactive_equality_is_no_coupling(tmp_path):
    text = robot.mjcf(follower_actuator=True).replace('joint2="finger_a"/>', 'joint2="finger_a" active="false"/>')
    result = run(tmp_path, arm_urdf=robot.urdf(), arm_xml=text)
    assert [(f.kind, f.severity, f.subject) for f in serious(result)] == [("coupling_one_file", "warning", "finger_b")]
    assert result.sides[1].joint("finger_b").follows is None
