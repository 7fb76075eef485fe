"""A small arm written twice for the map's tests: three revolute joints and a two-finger gripper
whose second finger follows the first (URDF ``<mimic>``, MJCF ``<equality joint>``), with gains,
limits, armature and friction the two files agree on; each test plants one difference."""

from __future__ import annotations

import math
from pathlib import Path

ARM = ("shoulder", "elbow", "wrist")
STIFFNESS_PER_DEGREE = {"shoulder": 8.0, "elbow": 6.0, "wrist": 2.0}  # N·m/deg, as a USD drive states it
DAMPING = {"shoulder": 20.0, "elbow": 15.0, "wrist": 5.0}  # N·m·s/rad
EFFORT = {"shoulder": 80.0, "elbow": 60.0, "wrist": 12.0}
ARMATURE = 0.05
FRICTION = 0.1
DEG = 180.0 / math.pi


def urdf(order=ARM) -> str:
    links = "".join(
        f'<link name="l{i}"><inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" '
        'ixz="0" iyz="0"/></inertial></link>'
        for i in range(6)
    )
    joints = {
        name: f'<joint name="{name}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
        f'<origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="{EFFORT[name]}" '
        f'velocity="3"/><dynamics damping="0.5" friction="{FRICTION}"/></joint>'
        for i, name in enumerate(ARM)
    }
    fingers = "".join(
        f'<joint name="finger_{s}" type="prismatic"><parent link="l3"/><child link="l{4 + k}"/>'
        f'<origin xyz="0 {0.02 * (1 - 2 * k)} 0.05"/><axis xyz="0 {1 - 2 * k} 0"/><limit lower="0" '
        f'upper="0.04" effort="20" velocity="0.2"/><dynamics damping="0.5" friction="{FRICTION}"/>'
        + ('<mimic joint="finger_a"/>' if s == "b" else "")
        + "</joint>"
        for k, s in enumerate("ab")
    )
    return f'<robot name="arm">{links}{"".join(joints[n] for n in order)}{fingers}</robot>'


def mjcf(armature: bool = True, follower_actuator: bool = False, kp_scale: float = DEG) -> str:
    arm_armature = f' armature="{ARMATURE}"' if armature else ""
    bodies = "".join(
        f'<body name="l{i + 1}" pos="0 0 0.3"><joint name="{name}" axis="0 1 0" range="-2 2" damping="0.5" '
        f'frictionloss="{FRICTION}"{arm_armature}/><inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>'
        for i, name in enumerate(ARM)
    )
    fingers = "".join(
        f'<body name="l{4 + k}" pos="0 {0.02 * (1 - 2 * k)} 0.05"><joint name="finger_{s}" type="slide" '
        f'axis="0 {1 - 2 * k} 0" range="0 0.04" damping="0.5" frictionloss="{FRICTION}"{arm_armature}/>'
        '<inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/></body>'
        for k, s in enumerate("ab")
    )
    actuators = "".join(
        f'<position name="act_{n}" joint="{n}" kp="{STIFFNESS_PER_DEGREE[n] * kp_scale!r}" kv="{DAMPING[n]}" '
        f'forcerange="-{EFFORT[n]} {EFFORT[n]}"/>'
        for n in ARM
    )
    actuators += '<position name="act_finger" joint="finger_a" kp="100" forcerange="-20 20"/>'
    if follower_actuator:
        actuators += '<position name="act_finger_b" joint="finger_b" kp="100" forcerange="-20 20"/>'
    return (
        f'<mujoco model="arm"><compiler angle="radian"/><worldbody><body name="l0">'
        f'<inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>{bodies}{fingers}{"</body>" * 3}</body>'
        '</worldbody><equality><joint joint1="finger_b" joint2="finger_a"/></equality>'
        f"<actuator>{actuators}</actuator>"
        '<keyframe><key name="home" qpos="0.1 -0.2 0.3 0.01 0.01"/></keyframe></mujoco>'
    )


def table(units: str = "degree", stiffness_per_degree: bool = True, fingers: str = "finger_a") -> str:
    """An Isaac Lab-style table (TOML) for the arm: stiffness per degree, or written per radian."""
    scale = 1.0 if units == "degree" else DEG if not stiffness_per_degree else 1.0
    damping_scale = 1 / DEG if units == "degree" else 1.0  # damping stated per rad·s in the MJCF
    stiff = ", ".join(f"{n} = {STIFFNESS_PER_DEGREE[n] * scale!r}" for n in ARM)
    damp = ", ".join(f"{n} = {DAMPING[n] * damping_scale!r}" for n in ARM)
    effort = ", ".join(f"{n} = {EFFORT[n]}" for n in ARM)
    return (
        f'units = "{units}"\n[actuators.arm]\njoint_names_expr = ["shoulder", "elbow", "wrist"]\n'
        f"stiffness = {{{stiff}}}\ndamping = {{{damp}}}\neffort_limit = {{{effort}}}\narmature = {ARMATURE}\n"
        f'friction = {FRICTION}\n[actuators.gripper]\njoint_names_expr = ["{fingers}"]\nstiffness = 100.0\ndamping = 0.0\neffort_limit = 20.0\narmature = {ARMATURE}\n'
        f"friction = {FRICTION}\n"
    )


def write(folder: Path, **files: str) -> list[str]:
    """Each ``name=text`` written in ``folder`` (``arm_urdf`` -> ``arm.urdf``); the paths."""
    out = []
    for key, text in files.items():
        stem, _, suffix = key.rpartition("_")
        path = folder / f"{stem}.{suffix}"
        path.write_text(text)
        out.append(str(path))
    return out
