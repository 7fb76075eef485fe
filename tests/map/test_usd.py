"""``kinverify map`` reading USD: a shared URDF with its urdf-usd-converter USD (both orders and the
maps), and a small arm written as a USD (drive stiffness per degree) and an MJCF (kp per radian)
that agree, then one planted difference each."""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from types import SimpleNamespace

import pytest

from kinverify.cli import main
from kinverify.map.contract import MapOptions, map_files
from kinverify.filemode.pipeline import add_map
from tests.paths import REAL_ROBOTS

pytest.importorskip("pxr")

REAL = Path(os.environ.get("KINVERIFY_REAL_ROBOTS", REAL_ROBOTS))
ARM = ("shoulder", "elbow", "wrist")
K_PER_DEGREE = {"shoulder": 8.0, "elbow": 6.0, "wrist": 2.0}  # N·m/deg
D_PER_RADIAN = {"shoulder": 20.0, "elbow": 15.0, "wrist": 5.0}  # N·m·s/rad
EFFORT = {"shoulder": 80.0, "elbow": 60.0, "wrist": 12.0}
ARMATURE = 0.05
DEG = 180.0 / math.pi


def usda(k_scale: float = 1.0, armature: bool = True, d_scale: float = 1.0, wrist_mimics: bool = False) -> str:
    bodies = "".join(
        f'def Xform "l{i}" (prepend apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsMassAPI"])\n'
        f'{{ double3 xformOp:translate = (0, 0, {0.3 * i})\nuniform token[] xformOpOrder = ["xformOp:translate"]\n'
        "float physics:mass = 1\nfloat3 physics:diagonalInertia = (0.01, 0.01, 0.01)\n"
        "point3f physics:centerOfMass = (0, 0, 0)\n}\n"
        for i in range(4)
    )
    physx = ', "PhysxJointAPI"' if armature else ""
    mimic = {n: "" for n in ARM}
    if wrist_mimics:  # PhysX: wrist + gearing·elbow + offset = 0, so gearing −1 is wrist = elbow
        physx_mimic = ', "PhysxMimicJointAPI:rotY"'
        mimic["wrist"] = "rel physxMimicJoint:rotY:referenceJoint = </arm/elbow>\nfloat physxMimicJoint:rotY:gearing = -1\n"
    else:
        physx_mimic = ""
    joints = "".join(
        f'def PhysicsRevoluteJoint "{n}" (prepend apiSchemas = ["PhysicsDriveAPI:angular"{physx}{physx_mimic if n == "wrist" else ""}])\n'
        f'{{ rel physics:body0 = </arm/l{i}>\nrel physics:body1 = </arm/l{i + 1}>\nuniform token physics:axis = "Y"\n'
        "point3f physics:localPos0 = (0, 0, 0.3)\npoint3f physics:localPos1 = (0, 0, 0)\n"
        "float physics:lowerLimit = -114.59156\nfloat physics:upperLimit = 114.59156\n"
        f"float drive:angular:physics:stiffness = {K_PER_DEGREE[n] * k_scale!r}\n"
        f"float drive:angular:physics:damping = {D_PER_RADIAN[n] / DEG * d_scale!r}\n"
        f"float drive:angular:physics:maxForce = {EFFORT[n]}\n"
        + (f"float physxJoint:armature = {ARMATURE}\n" if armature else "")
        + mimic[n]
        + "}\n"
        for i, n in enumerate(ARM)
    )
    return (
        '#usda 1.0\n(\n upAxis = "Z"\n metersPerUnit = 1\n kilogramsPerUnit = 1\n)\n'
        'def Xform "arm" (prepend apiSchemas = ["PhysicsArticulationRootAPI"]) {\n'
        f'{bodies}def PhysicsFixedJoint "base" {{\nrel physics:body1 = </arm/l0>\n}}\n{joints}}}\n'
    )


def mjcf() -> str:
    bodies = "".join(
        f'<body name="l{i + 1}" pos="0 0 0.3"><joint name="{n}" axis="0 1 0" range="-2 2" armature="{ARMATURE}"/>'
        '<inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>'
        for i, n in enumerate(ARM)
    )
    actuators = "".join(
        f'<position name="act_{n}" joint="{n}" kp="{K_PER_DEGREE[n] * DEG!r}" kv="{D_PER_RADIAN[n]}" '
        f'forcerange="-{EFFORT[n]} {EFFORT[n]}"/>'
        for n in ARM
    )
    return (
        f'<mujoco model="arm"><compiler angle="radian"/><worldbody><body name="l0">'
        f'<inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>{bodies}{"</body>" * 3}</body>'
        f"</worldbody><actuator>{actuators}</actuator></mujoco>"
    )


def run(tmp_path, usd_text: str):
    (tmp_path / "arm.xml").write_text(mjcf())
    (tmp_path / "arm.usda").write_text(usd_text)
    return map_files([str(tmp_path / "arm.xml"), str(tmp_path / "arm.usda")], MapOptions())


def serious(result):
    return [f for f in result.findings if f.severity != "info"]


def test_usd_stiffness_per_degree_agrees_with_mjcf_kp_per_radian(tmp_path):
    result = run(tmp_path, usda())
    assert serious(result) == [] and result.exit_code == 0
    usd = result.sides[1]
    assert usd.format == "usd" and usd.names == list(ARM)
    assert usd.joint("shoulder").stiffness == pytest.approx(8.0 * DEG, rel=1e-6)  # per radian inside
    assert usd.joint("elbow").damping == pytest.approx(15.0, rel=1e-6)
    assert usd.joint("wrist").effort == 12.0 and usd.joint("wrist").armature == pytest.approx(ARMATURE)


def test_a_usd_drive_off_by_180_over_pi_is_one_units_finding(tmp_path):
    result = run(tmp_path, usda(k_scale=DEG))  # the per-radian gain written where USD reads per degree
    (f,) = serious(result)
    assert (f.kind, f.property, f.severity) == ("stiffness_units", "stiffness", "error")
    assert f.values["ratio"] == pytest.approx(DEG, rel=1e-6)
    assert "per degree read as per radian" in f.message and len(f.subject.split(", ")) == 3
    assert result.exit_code == 1


def test_a_dropped_armature_on_the_usd_side_is_one_finding(tmp_path):
    result = run(tmp_path, usda(armature=False))
    (f,) = result.findings
    assert (f.kind, f.severity, f.magnitude) == ("armature_unset", "warning", pytest.approx(ARMATURE))
    assert "arm.usda leaves it unset" in f.message and len(f.subject.split(", ")) == 3


def test_a_driven_physx_mimic_follower_is_one_finding(tmp_path):
    result = run(tmp_path, usda(wrist_mimics=True))  # the wrist follows the elbow and keeps its own drive
    wrist = result.sides[1].joint("wrist")
    assert (wrist.follows.leader, wrist.follows.multiplier, wrist.follows.source) == ("elbow", 1.0, "PhysxMimicJointAPI")
    errors = [f for f in result.findings if f.severity == "error"]
    assert [(f.kind, f.subject) for f in errors] == [("driven_follower", "wrist")] and "arm.usda drives 1" in errors[0].message
    assert [f.kind for f in result.findings if f.severity == "warning"] == ["coupling_one_file"]  # the MJCF has no coupling


def test_a_drive_with_zero_gains_is_torque_control_and_its_gains_are_not_compared(tmp_path):
    result = run(tmp_path, usda(k_scale=0.0, d_scale=0.0))  # Isaac Lab's explicit actuators: the gains in the controller
    assert serious(result) == [] and result.exit_code == 0
    shoulder = result.sides[1].joint("shoulder")
    assert shoulder.driven and shoulder.stiffness is None and "force (torque) drive" in shoulder.apart["stiffness"]
    assert shoulder.effort == 80.0  # maxForce still bounds the torque


def test_file_mode_map_section_reads_a_usd_side(tmp_path):
    result = run(tmp_path, usda(k_scale=DEG))
    report = SimpleNamespace(sections={}, notes=[], internal_errors=[])
    add_map(report, [side.path for side in result.sides])
    section = report.sections["map"]
    assert section.data["maps"]["joints"][0]["index"] == [0, 1, 2] and not report.internal_errors
    assert [n.split(":")[0] for n in section.notes] == ["error stiffness_units"]


def test_a_shared_urdf_and_its_converted_usd_print_both_orders_and_the_maps(tmp_path, capsys):
    folder = REAL / "go2"
    if not (folder / "go2_urdf-usd-converter.usda").is_file():
        pytest.skip(f"{folder} absent")
    out = tmp_path / "map.json"
    code = main(["map", str(folder / "go2_erd.urdf"), str(folder / "go2_urdf-usd-converter.usda"), "--json", str(out)])
    printed = capsys.readouterr().out
    for text in ("URDF declaration order", "breadth-first articulation order", "go2_erd.urdf -> go2_urdf-usd-converter.usda"):
        assert text in printed
    data = json.loads(out.read_text())
    legs = ("FL", "FR", "RL", "RR")
    assert data["sides"][1]["joints"] == [f"{leg}_{part}_joint" for part in ("hip", "thigh", "calf") for leg in legs]
    (to_usd,) = [m for m in data["maps"]["joints"] if m["from"] == "go2_erd.urdf"]
    assert to_usd["index"] == [0, 3, 6, 9, 1, 4, 7, 10, 2, 5, 8, 11]
    assert [f["kind"] for f in data["findings"] if f["severity"] == "error"] == ["joint_order"] and code == 1


def test_mjc_actuator_prims_of_a_converted_mjcf_give_its_gains():
    """Apollo's USD (mujoco-usd-converter) keeps Menagerie's actuators as MjcActuator prims: the same
    kp per radian on all 32 joints; only the order differs (breadth-first against MuJoCo's depth-first)."""
    folder = REAL / "apollo"
    if not (folder / "apptronik_apollo.usda").is_file():
        pytest.skip(f"{folder} absent")
    result = map_files([str(folder / "apollo_menagerie.xml"), str(folder / "apptronik_apollo.usda")], MapOptions())
    assert [f.kind for f in serious(result)] == ["joint_order"]
    usd = result.sides[1]
    assert all(j.driven and j.stiffness > 0 for j in usd.joints) and len(usd.joints) == 32
    assert usd.joint("torso_roll").stiffness == pytest.approx(result.sides[0].joint("torso_roll").stiffness)


def _generated(tmp_path, name: str = "gripper"):
    """A shipped spec's USD and MJCF (generated: every joint driven, a force drive and a motor)."""
    from kinverify import load_spec
    from kinverify.generate import generate_mjcf
    from kinverify.generate.usd import generate_usd

    spec = load_spec(Path("models") / f"{name}.toml")
    usd, xml = tmp_path / f"{name}.usda", tmp_path / f"{name}.xml"
    usd.write_text(generate_usd(spec))
    xml.write_text(generate_mjcf(spec))
    return usd, xml


def test_a_generated_usd_states_its_driven_joints_as_actuators_in_articulation_order(tmp_path):
    usd, xml = _generated(tmp_path)
    result = map_files([str(usd), str(xml)], MapOptions())
    side = result.sides[0]
    assert [a.joints for a in side.actuators] == [(n,) for n in side.names] and len(side.names) == 6
    assert {a.kind for a in side.actuators} == {"force drive (torque)"}
    assert not serious(result)
    maps = {(m["from"], m["to"]): m["index"] for m in result.maps["joints_to_actuators"]}
    u, x = side.label, result.sides[1].label
    assert maps[(u, u)] == maps[(u, x)] == list(range(6))
    assert result.maps["actuators"][0]["index"] == list(range(6))


def test_a_planted_actuator_permutation_against_a_generated_usd_is_one_finding(tmp_path):
    usd, xml = _generated(tmp_path)
    text = xml.read_text()
    left, right = (next(line for line in text.splitlines() if f'name="finger_{s}_motor"' in line) for s in ("left", "right"))
    xml.write_text(text.replace(left, "@@").replace(right, left).replace("@@", right))
    result = map_files([str(usd), str(xml)], MapOptions())
    assert [(f.kind, f.magnitude) for f in serious(result)] == [("actuator_order", 2)]
    (to_ctrl,) = [
        m for m in result.maps["joints_to_actuators"] if m["from"] == result.sides[0].label and m["to"].endswith(".xml")
    ]
    assert to_ctrl["index"] == [0, 1, 2, 3, 5, 4]  # data.ctrl[:] = action[index], the action in the USD's joint order


def test_a_joint_without_a_drive_is_no_actuator_of_the_usd(tmp_path):
    from pxr import Usd, UsdPhysics

    usd, xml = _generated(tmp_path)
    stage = Usd.Stage.Open(str(usd))
    (prim,) = [p for p in stage.Traverse() if p.GetName() == "elbow"]
    prim.RemoveAPI(UsdPhysics.DriveAPI, "angular")
    stage.GetRootLayer().Save()
    result = map_files([str(usd), str(xml)], MapOptions())
    side = result.sides[0]
    assert [a.name for a in side.actuators] == [n for n in side.names if n != "elbow"] and not side.joint("elbow").driven
    (to_ctrl,) = [m for m in result.maps["actuators"] if m["from"] == side.label]
    assert to_ctrl["index"] == [0, 1, None, 2, 3, 4]  # the MJCF's elbow motor has no USD control
