"""MJCF text from a spec: the arm plus the seed tutorial's scene (floor, table, lights, target
marker, sensors, actuators), with the seed's defects fixed:

- one actuator per joint and one control loop: ``motor`` actuators (``ctrl`` is torque [N·m] or
  force [N], ``ctrlrange`` = ±effort) by default, or ``position`` actuators with a built-in PD
  (``kp``, ``kv``) whose ``ctrlrange`` is the joint range in radians (MuJoCo reads ``ctrlrange``
  in radians even under ``angle="degree"``; we always write ``angle="radian"``);
- no contacts on the arm (``contype``/``conaffinity`` 0): Pinocchio models none, so contacts
  would make the two libraries' dynamics differ for reasons that are not the model's;
- explicit inertials (``inertiafromgeom="false"``) so MuJoCo uses the spec's mass properties;
- ``Euler`` integrator: torques held over a step match Pinocchio's semi-implicit Euler.
"""

from __future__ import annotations

from kinverify.model.floating import FLOATING_JOINT
from kinverify.model.kinematics import home_tool_position
from kinverify.model.spec import ArmSpec, Geometry, Link
from kinverify.model.transforms import matrix_to_quat, rpy_to_matrix
from kinverify.generate._fmt import attr, colour, nums

TIMESTEP = 0.001  # s, the seed's


def _placement(xyz, rpy) -> str:
    text = f'pos="{nums(xyz)}"'
    if any(rpy):
        text += f' quat="{nums(matrix_to_quat(rpy_to_matrix(rpy)))}"'
    return text


def geom_shape_attributes(geom: Geometry) -> str:
    """MJCF placement and size attributes of a spec geometry (box ``size`` is half-extents)."""
    if geom.shape in ("capsule", "cylinder"):
        return f'fromto="{nums(geom.fromto)}" size="{nums([geom.radius])}"'
    if geom.shape == "sphere":
        return f'pos="{nums(geom.pos)}" size="{nums([geom.radius])}"'
    assert geom.size is not None  # a box states its size
    return f'pos="{nums(geom.pos)}" size="{nums([s / 2 for s in geom.size])}"'


def _geom(name: str, geom: Geometry, rgba: str) -> str:
    return f'<geom name={attr(name + "_geom")} type="{geom.shape}" {geom_shape_attributes(geom)} rgba="{rgba}"/>'


def _inertial(link: Link) -> str:
    i = link.inertial
    return f'<inertial pos="{nums(i.com)}" mass="{nums([i.mass])}" fullinertia="{nums(i.inertia)}"/>'


def _body_contents(spec: ArmSpec, link: Link, index: int, indent: str) -> list[str]:
    lines = [indent + _inertial(link)]
    if link.geometry is not None:
        lines.append(indent + _geom(link.name, link.geometry, colour(index)))
    for tool in spec.tools:
        if tool.parent == link.name:
            lines.append(
                f'{indent}<site name={attr(tool.name)} {_placement(tool.origin.xyz, tool.origin.rpy)} size="0.01" rgba="1 0 0 1"/>'
            )
    return lines


def _actuator(joint, kind: str, gains: dict | None) -> str:
    lim = joint.limits
    if kind == "motor":
        return (
            f'<motor name={attr(joint.name + "_motor")} joint={attr(joint.name)} ctrlrange="{nums([-lim.effort, lim.effort])}"/>'
        )
    kp, kv = (gains or {}).get(joint.name, (100.0, 20.0))
    return (
        f'<position name={attr(joint.name + "_position")} joint={attr(joint.name)} kp="{nums([kp])}" kv="{nums([kv])}" '
        f'ctrlrange="{nums([lim.lower, lim.upper])}" forcerange="{nums([-lim.effort, lim.effort])}"/>'
    )


def _child_bodies(spec: ArmSpec, link: int, indent: str) -> list[str]:
    """The bodies of the joints hanging from link ``link`` (0 = base), nested as the tree is."""
    out = []
    for i, (joint, parent) in enumerate(zip(spec.joints, spec.parent_indices, strict=True)):
        if parent != link:
            continue
        kind = "hinge" if joint.type == "revolute" else "slide"
        lim = joint.limits
        out += [
            f"{indent}<body name={attr(joint.link.name)} {_placement(joint.origin.xyz, joint.origin.rpy)}>",
            f'{indent}  <joint name={attr(joint.name)} type="{kind}" axis="{nums(joint.axis)}" range="{nums([lim.lower, lim.upper])}" '
            f'damping="{nums([joint.damping])}" frictionloss="{nums([joint.friction])}" armature="{nums([joint.armature])}"/>',
        ]
        out += _body_contents(spec, joint.link, i + 1, indent + "  ")
        out += _child_bodies(spec, i + 1, indent + "  ")
        out.append(f"{indent}</body>")
    return out


def generate_mjcf(spec: ArmSpec, actuators: str = "motor", position_gains: dict | None = None, target=None) -> str:
    """The MJCF of ``spec`` as text; the same arguments always give the same bytes.

    Args:
        actuators: ``"motor"`` (torque) or ``"position"`` (PD servo per joint).
        position_gains: ``{joint name: (kp, kv)}`` for position actuators.
        target: world position [m] of the ``target`` marker site (default: the tool at q = 0).
    """
    if actuators not in ("motor", "position"):
        raise ValueError(f"actuators must be 'motor' or 'position', got {actuators!r}")
    target = home_tool_position(spec) if target is None else target
    g = spec.gravity
    out = [
        f"<mujoco model={attr(spec.name)}>",
        "  <!-- Generated by kinverify. Units: m, rad, kg. Same names as the URDF. -->",
        '  <compiler angle="radian" autolimits="true" inertiafromgeom="false"/>',
        f'  <option timestep="{nums([TIMESTEP])}" gravity="{nums(g)}" integrator="Euler"/>',
        '  <visual><global offwidth="640" offheight="480"/></visual>',
        '  <default><geom contype="0" conaffinity="0"/></default>',
        "  <worldbody>",
        '    <light name="key" pos="2 2 3" dir="-1 -1 -1.5" diffuse="0.9 0.9 0.9"/>',
        '    <light name="fill" pos="-2 2 2" dir="1 -1 -1" diffuse="0.4 0.4 0.4"/>',
        '    <geom name="floor" type="plane" size="2 2 0.1" rgba="0.8 0.8 0.8 1"/>',
    ]
    base_z = spec.base_origin.xyz[2]
    if base_z > 0.05:
        x, y = spec.base_origin.xyz[:2]
        out.append(
            f'    <geom name="tabletop" type="box" pos="{nums([x, y, base_z - 0.02])}" size="0.6 0.4 0.02" rgba="0.6 0.4 0.2 1"/>'
        )
    out += [
        f'    <site name="target" pos="{nums(target)}" size="0.03" rgba="0 1 0 0.5"/>',
    ]
    if spec.floating:  # a free joint belongs to a top-level body; its pose there is only qpos0
        out += [
            f"    <body name={attr(spec.base_link.name)} {_placement(spec.base_origin.xyz, spec.base_origin.rpy)}>",
            f'      <freejoint name="{FLOATING_JOINT}"/>',
        ]
        out += _body_contents(spec, spec.base_link, 0, " " * 6)
        out += _child_bodies(spec, 0, " " * 6)
        out += ["    </body>", "  </worldbody>", "  <actuator>"]
    else:
        out += [
            "    <!-- Pinocchio's MJCF parser ignores the pose of a top-level body: the arm hangs from a",
            "         zero-pose mount body so that the base pose is read by every parser. -->",
            '    <body name="world_mount">',
            '      <inertial pos="0 0 0" mass="1" diaginertia="0.001 0.001 0.001"/>',
            f"      <body name={attr(spec.base_link.name)} {_placement(spec.base_origin.xyz, spec.base_origin.rpy)}>",
        ]
        out += _body_contents(spec, spec.base_link, 0, " " * 8)
        out += _child_bodies(spec, 0, " " * 8)
        out += ["      </body>", "    </body>", "  </worldbody>", "  <actuator>"]
    out += [f"    {_actuator(j, actuators, position_gains)}" for j in spec.joints]
    out += ["  </actuator>", "  <sensor>"]
    out += [f"    <jointpos name={attr(j.name + '_pos')} joint={attr(j.name)}/>" for j in spec.joints]
    out += [f"    <jointvel name={attr(j.name + '_vel')} joint={attr(j.name)}/>" for j in spec.joints]
    for tool in spec.tools:
        out.append(f'    <framepos name={attr(tool.name + "_pos")} objtype="site" objname={attr(tool.name)}/>')
        out.append(f'    <framequat name={attr(tool.name + "_quat")} objtype="site" objname={attr(tool.name)}/>')
    out += ["  </sensor>", "</mujoco>"]
    return "\n".join(out) + "\n"
