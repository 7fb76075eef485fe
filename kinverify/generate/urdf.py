"""URDF text from a spec.

A ``world`` link holds the base on the fixed joint ``world_to_base`` at the spec's base origin;
capsules become cylinders (URDF has no capsule); tools are links on fixed ``<tool>_mount`` joints.
URDF cannot carry joint armature: it is left out here and reported by the dynamics checks.
"""

from __future__ import annotations

from kinverify.model.floating import FLOATING_JOINT
from kinverify.model.spec import ArmSpec, Geometry, Link, Origin
from kinverify.generate._fmt import attr, colour, nums, segment_placement


def _origin(origin: Origin) -> str:
    return f'<origin xyz="{nums(origin.xyz)}" rpy="{nums(origin.rpy)}"/>'


def _geometry(geom: Geometry) -> tuple[str, str]:
    """(origin element, geometry element) for one shape."""
    if geom.shape in ("capsule", "cylinder"):
        centre, rpy, length = segment_placement(geom.fromto)
        return _origin(Origin(tuple(centre), tuple(rpy))), f'<cylinder radius="{nums([geom.radius])}" length="{nums([length])}"/>'
    if geom.shape == "sphere":
        return _origin(Origin(geom.pos)), f'<sphere radius="{nums([geom.radius])}"/>'
    return _origin(Origin(geom.pos)), f'<box size="{nums(geom.size)}"/>'


def _link(link: Link, index: int) -> list[str]:
    inertial = link.inertial
    ixx, iyy, izz, ixy, ixz, iyz = inertial.inertia
    lines = [
        f"  <link name={attr(link.name)}>",
        "    <inertial>",
        f"      {_origin(Origin(inertial.com))}",
        f'      <mass value="{nums([inertial.mass])}"/>',
        f'      <inertia ixx="{nums([ixx])}" ixy="{nums([ixy])}" ixz="{nums([ixz])}" iyy="{nums([iyy])}" iyz="{nums([iyz])}" izz="{nums([izz])}"/>',
        "    </inertial>",
    ]
    if link.geometry is not None:
        origin, shape = _geometry(link.geometry)
        for tag in ("visual", "collision"):
            lines += [f"    <{tag}>", f"      {origin}", f"      <geometry>{shape}</geometry>"]
            if tag == "visual":
                lines.append(f'      <material name="{link.name}_mat"><color rgba="{colour(index)}"/></material>')
            lines.append(f"    </{tag}>")
    lines.append("  </link>")
    return lines


def generate_urdf(spec: ArmSpec) -> str:
    """The URDF of ``spec`` as text; the same spec always gives the same bytes."""
    out = ['<?xml version="1.0"?>', f"<robot name={attr(spec.name)}>", '  <link name="world"/>']
    if spec.floating:  # the base's pose is the configuration's first six coordinates: origin at identity
        out += [
            f'  <joint name="{FLOATING_JOINT}" type="floating">',
            '    <parent link="world"/>',
            f"    <child link={attr(spec.base_link.name)}/>",
            f"    {_origin(Origin())}",
            "  </joint>",
        ]
    else:
        out += [
            '  <joint name="world_to_base" type="fixed">',
            '    <parent link="world"/>',
            f"    <child link={attr(spec.base_link.name)}/>",
            f"    {_origin(spec.base_origin)}",
            "  </joint>",
        ]
    out += _link(spec.base_link, 0)
    for i, (joint, parent) in enumerate(zip(spec.joints, spec.parent_indices, strict=True)):
        parent_name = spec.link_names[parent]
        lim = joint.limits
        out += [
            f"  <joint name={attr(joint.name)} type={attr(joint.type)}>",
            f"    <parent link={attr(parent_name)}/>",
            f"    <child link={attr(joint.link.name)}/>",
            f"    {_origin(joint.origin)}",
            f'    <axis xyz="{nums(joint.axis)}"/>',
            f'    <limit lower="{nums([lim.lower])}" upper="{nums([lim.upper])}" effort="{nums([lim.effort])}" velocity="{nums([lim.velocity])}"/>',
            f'    <dynamics damping="{nums([joint.damping])}" friction="{nums([joint.friction])}"/>',
            "  </joint>",
        ]
        out += _link(joint.link, i + 1)
    for tool in spec.tools:
        out += [
            f'  <joint name={attr(tool.name + "_mount")} type="fixed">',
            f"    <parent link={attr(tool.parent)}/>",
            f"    <child link={attr(tool.name)}/>",
            f"    {_origin(tool.origin)}",
            "  </joint>",
            f"  <link name={attr(tool.name)}/>",
        ]
    out.append("</robot>")
    return "\n".join(out) + "\n"
