"""Committed test pairs for file mode: a generated URDF/MJCF pair and deliberate mutations of it.

Each mutation is a text edit of one file and the finding kind kinverify must report for it.
Generated in the test (nothing large is committed).
"""

from __future__ import annotations

import math
import re
from pathlib import Path

from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import load_spec
from tests.paths import MODELS


def generated_pair(model: str = "panda") -> tuple[str, str]:
    spec = load_spec(MODELS / f"{model}.toml")
    return generate_urdf(spec), generate_mjcf(spec)


def _sub_once(pattern: str, repl, text: str) -> str:
    new, n = re.subn(pattern, repl, text, count=1, flags=re.S)
    assert n == 1, f"mutation pattern not found: {pattern}"
    return new


def _body_attr(mjcf: str, body: str, attr: str, fn) -> str:
    return _sub_once(rf'(<body name="{body}"[^>]*? {attr}=")([^"]*)(")', lambda m: m[1] + fn(m[2]) + m[3], mjcf)


def _joint_attr(text: str, joint: str, attr: str, fn) -> str:
    return _sub_once(rf'(<joint name="{joint}"[^>]*? {attr}=")([^"]*)(")', lambda m: m[1] + fn(m[2]) + m[3], text)


def _nums(fn):
    return lambda s: " ".join(repr(v) for v in fn([float(x) for x in s.split()]))


def base_rotation(urdf, mjcf):
    """The MJCF mounts the arm turned 45° about z (inside the zero-pose mount body)."""
    q = f'quat="{math.cos(math.pi / 8)!r} 0 0 {math.sin(math.pi / 8)!r}"'
    return urdf, _sub_once(r'(<body name="panda_link0" pos="[^"]*")', lambda m: f"{m[1]} {q}", mjcf)


def axis_flip(urdf, mjcf):
    return urdf, _joint_attr(mjcf, "panda_joint3", "axis", _nums(lambda v: [-x for x in v]))


def offset_1mm(urdf, mjcf):
    return urdf, _body_attr(mjcf, "panda_link3", "pos", _nums(lambda v: [v[0] + 1e-3, v[1], v[2]]))


def degrees_as_radians(urdf, mjcf):
    return urdf, _joint_attr(mjcf, "panda_joint1", "range", _nums(lambda v: [round(math.degrees(x), 4) for x in v]))


def swapped_inertia(urdf, mjcf):
    """fullinertia="ixx iyy izz ixy ixz iyz" with x and y exchanged (same tensor, axes swapped)."""
    def swap(v):
        ixx, iyy, izz, ixy, ixz, iyz = v
        return [iyy, ixx, izz, ixy, iyz, ixz]
    return urdf, _sub_once(r'(<body name="panda_link3".*?fullinertia=")([^"]*)(")',
                           lambda m: m[1] + _nums(swap)(m[2]) + m[3], mjcf)


def extra_joint(urdf, mjcf):
    gripper = ('<body name="gripper_finger" pos="0 0 0.05"><joint name="gripper_joint" type="slide" axis="0 1 0" '
               'range="0 0.04"/><inertial pos="0 0 0" mass="0.001" diaginertia="1e-7 1e-7 1e-7"/></body>')
    return urdf, _sub_once(r'(<body name="panda_link7"[^>]*>)', lambda m: m[1] + gripper, mjcf)


def rounded_rpy(urdf, mjcf):
    """The URDF writes 1.5708 for π/2 in one joint origin."""
    return _sub_once(r'(<joint name="panda_joint3".*?<origin [^>]*rpy=")([^"]*)(")',
                     lambda m: m[1] + m[2].replace("1.5707963267948966", "1.5708") + m[3], urdf), mjcf


def zero_offset(urdf, mjcf):
    """The MJCF joint's zero is 0.1 rad away (``ref``)."""
    return urdf, _sub_once(r'(<joint name="panda_joint4" )', lambda m: m[1] + 'ref="0.1" ', mjcf)


def type_change(urdf, mjcf):
    """The MJCF makes the last joint prismatic."""
    return urdf, _joint_attr(mjcf, "panda_joint7", "type", lambda t: "slide")


def _urdf_link_mass(urdf: str, link: str, fn) -> str:
    return _sub_once(rf'(<link name="{link}">.*?<mass value=")([^"]*)(")', lambda m: m[1] + repr(fn(float(m[2]))) + m[3], urdf)


def heavier_urdf_link(urdf, mjcf):
    """The URDF's panda_link4 is 20 % heavier (its inertia tensor unchanged)."""
    return _urdf_link_mass(urdf, "panda_link4", lambda m: 1.2 * m), mjcf


def upper_limit_further(urdf, mjcf):
    """The URDF lets panda_joint2 go 0.2 rad further up."""
    return _sub_once(r'(<joint name="panda_joint2".*?<limit [^>]*upper=")([^"]*)(")',
                     lambda m: m[1] + repr(float(m[2]) + 0.2) + m[3], urdf), mjcf


def friction_added(urdf, mjcf):
    """The MJCF gives panda_joint5 0.3 N·m of Coulomb friction (frictionloss) the URDF lacks."""
    return urdf, _joint_attr(mjcf, "panda_joint5", "frictionloss", lambda v: "0.3")


# mutation, expected finding kind, joint/link/frame it must name (URDF names)
MUTATIONS = [
    (base_rotation, "base_transform", None),
    (axis_flip, "axis_sign_flip", "panda_joint3"),
    (offset_1mm, "axis_position", "panda_joint3"),
    (degrees_as_radians, "limits_degrees_as_radians", "panda_joint1"),
    (swapped_inertia, "inertia_rotated", "panda_link3"),
    (extra_joint, "unmatched_joint", "gripper_joint"),
    (rounded_rpy, "rounding", "panda_joint3"),
    (zero_offset, "zero_offset", "panda_joint4"),
    (type_change, "type_difference", "panda_joint7"),
    (heavier_urdf_link, "mass_difference", "panda_link4"),
    (upper_limit_further, "limit_difference", "panda_joint2"),
    (friction_added, "friction_difference", "panda_joint5"),
]
