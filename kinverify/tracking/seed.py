"""The seed tutorial's MJCF and PID loop, reproduced faithfully as the negative example.

The seed writes (``create_3dof_arm_xml``): the default ``compiler angle="degree"``, an ``RK4``
integrator, colliding geoms (``contype="1" conaffinity="1"``: neighbouring link geoms touch at
every joint), ``position`` actuators ``kp=100`` whose ``ctrlrange`` is in degrees (MuJoCo does not
convert ``ctrlrange``: ±180 is read as ±180 rad), and ``velocity`` actuators ``kv=10`` on the same
joints. Its loop writes a PID law (kp 2, ki 0.1, kd 0.5, on the joint-angle error) into
``ctrl[:n]``, i.e. as the *set-point* of the position servos; the velocity actuators keep
``ctrl = 0`` and act as a second, braking loop. kinverify's own MJCF fixes all of this.
"""

from __future__ import annotations

import math

import numpy as np

from kinverify.model.spec import ArmSpec
from kinverify.generate._fmt import attr, nums
from kinverify.generate.mjcf import geom_shape_attributes
from kinverify.model.transforms import matrix_to_quat, rpy_to_matrix

SEED_PID = {"kp": 2.0, "ki": 0.1, "kd": 0.5}


def _geom(link, name: str) -> str:
    g = link.geometry
    if g is None:
        return ""
    return f'<geom name={attr(name)} type="{g.shape}" {geom_shape_attributes(g)}/>'


def _joint_geom(joint) -> str:
    """The seed's grey joint cylinder (radius 1.2 × link radius, half-height 0.02) along the axis."""
    g = joint.link.geometry
    radius = 1.2 * (g.radius if g is not None and g.shape in ("capsule", "cylinder") else 0.03)
    return f'<geom name={attr(joint.name + "_geom")} type="cylinder" size="{nums([radius, 0.02])}" zaxis="{nums(joint.axis)}"/>'


def _deg(x: float) -> float:
    return math.degrees(x)


def _quat(rpy) -> str:
    """URDF fixed-axis roll-pitch-yaw as an MJCF ``quat`` (MuJoCo's default ``euler`` sequence is
    intrinsic x-y-z, not URDF's)."""
    return nums(matrix_to_quat(rpy_to_matrix(rpy)))


def seed_mjcf(spec: ArmSpec) -> str:
    """The seed's MJCF pattern for ``spec`` (same bodies, masses and joints as kinverify's MJCF)."""
    base = spec.base_origin
    out = [
        f"<mujoco model={attr(spec.name + '_seed')}>",
        "  <!-- seed-style: angle=degree (MuJoCo's default), RK4, collisions on, PID into position ctrl -->",
        '  <compiler angle="degree"/>',
        f'  <option timestep="0.001" gravity="{nums(spec.gravity)}" integrator="RK4"/>',
        "  <default>",
        '    <geom contype="1" conaffinity="1" friction="1 0.1 0.1" solref="0.02 1"/>',
        "  </default>",
        "  <worldbody>",
        '    <geom name="floor" type="plane" size="2 2 0.1"/>',
        f'    <body name="table" pos="{nums([base.xyz[0], base.xyz[1], base.xyz[2] - 0.02])}">',
        '      <geom name="tabletop" type="box" size="0.6 0.4 0.02"/>',
        "    </body>",
        f'    <body name={attr(spec.base_link.name)} pos="{nums(base.xyz)}" quat="{_quat(base.rpy)}">',
    ]
    if spec.base_link.geometry is not None:
        out.append("      " + _geom(spec.base_link, spec.base_link.name + "_geom"))
    indent = "      "
    for joint in spec.joints:
        lim = joint.limits
        kind = "hinge" if joint.type == "revolute" else "slide"
        rng = [_deg(lim.lower), _deg(lim.upper)] if joint.type == "revolute" else [lim.lower, lim.upper]
        out += [
            f'{indent}<body name={attr(joint.link.name)} pos="{nums(joint.origin.xyz)}" quat="{_quat(joint.origin.rpy)}">',
            f'{indent}  <joint name={attr(joint.name)} type="{kind}" axis="{nums(joint.axis)}" range="{nums(rng)}" '
            f'damping="{nums([joint.damping])}" armature="{nums([joint.armature])}"/>',
            f"{indent}  {_joint_geom(joint)}",
        ]
        if joint.link.geometry is not None:
            out.append(f"{indent}  {_geom(joint.link, joint.link.name + '_geom')}")
        indent += "  "
    for _ in spec.joints:
        indent = indent[:-2]
        out.append(f"{indent}</body>")
    out += ["    </body>", "  </worldbody>", "  <actuator>"]
    for joint in spec.joints:  # the seed's ctrlrange: the joint limits in degrees, read as radians
        lim = joint.limits
        rng = [_deg(lim.lower), _deg(lim.upper)] if joint.type == "revolute" else [lim.lower, lim.upper]
        out.append(f'    <position name={attr(joint.name + "_pos")} joint={attr(joint.name)} kp="100" ctrlrange="{nums(rng)}"/>')
    for joint in spec.joints:
        out.append(f'    <velocity name={attr(joint.name + "_vel")} joint={attr(joint.name)} kv="10"/>')
    out += ["  </actuator>", "</mujoco>"]
    return "\n".join(out) + "\n"


class SeedPID:
    """The seed's ``pid_control``: ``u = kp·e + ki·∫e dt + kd·(e − e_prev)/dt`` with ``e`` the
    angle error, written into the position actuators' ``ctrl``. ``e_prev`` starts at 0, as in the
    seed (so the first derivative term is ``kd·e₀/dt``)."""

    def __init__(self, n: int, dt: float) -> None:
        self.dt = dt
        self.integral = np.zeros(n)
        self.last = np.zeros(n)

    def __call__(self, q_des: np.ndarray, q: np.ndarray) -> np.ndarray:
        error = q_des - q
        self.integral += error * self.dt
        derivative = (error - self.last) / self.dt
        self.last = error.copy()
        return SEED_PID["kp"] * error + SEED_PID["ki"] * self.integral + SEED_PID["kd"] * derivative
