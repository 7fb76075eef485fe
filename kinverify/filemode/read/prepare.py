"""The texts the libraries load in file mode, prepared so that both files are compared at the same
state, by editing the XML tree (never re-printing numbers):

- a URDF ``continuous`` joint becomes an unlimited ``revolute`` one (Pinocchio gives a continuous
  joint two coordinates, cos and sin; the kinematics and dynamics are the same);
- an MJCF free base (``<freejoint/>`` or ``<joint type="free">`` of a top-level body) is fixed at
  the world origin, as the URDF's root link is: both free bases at the same pose (the identity).
  MuJoCo's initial base pose (``qpos0``, the body's ``pos``/``quat``) is the free joint's initial
  value, not a property of the robot. Keyframes (whose ``qpos`` would no longer fit) go too;
- joints present in one file only, and joints with several coordinates (a URDF ``floating`` or
  ``planar`` joint, an MJCF ``ball``), are locked at zero for the dynamics comparison (URDF: the
  joint becomes ``fixed``; MJCF: the joint and what refers to it are removed).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

POSE_ATTRS = ("pos", "quat", "euler", "axisangle", "xyaxes", "zaxis")


def continuous_joints(urdf_text: str) -> set[str]:
    return {j.get("name") for j in ET.fromstring(urdf_text).iter("joint") if j.get("type") == "continuous"}  # type: ignore[misc]  # a URDF's names are checked on reading


def prepare_urdf(urdf_text: str) -> str:
    """Continuous joints as revolute ones with limits Pinocchio reads as unbounded."""
    root = ET.fromstring(urdf_text)
    changed = False
    for joint in root.iter("joint"):
        if joint.get("type") != "continuous":
            continue
        joint.set("type", "revolute")
        limit = joint.find("limit")
        if limit is None:
            limit = ET.SubElement(joint, "limit", effort="0", velocity="0")
        limit.set("lower", "-1e308")
        limit.set("upper", "1e308")
        changed = True
    return ET.tostring(root, encoding="unicode") if changed else urdf_text


def _free_joints(body: ET.Element) -> list[ET.Element]:
    return [c for c in body if c.tag == "freejoint" or (c.tag == "joint" and c.get("type") == "free")]


def fix_free_bases(mjcf_text: str) -> tuple[str, list[str]]:
    """The MJCF with each top-level free body fixed at the world origin, and those bodies' names."""
    root = ET.fromstring(mjcf_text)
    fixed = []
    for world in root.iter("worldbody"):
        for body in world.findall("body"):
            joints = _free_joints(body)
            if not joints:
                continue
            for joint in joints:
                body.remove(joint)
            for attr in POSE_ATTRS:
                body.attrib.pop(attr, None)
            fixed.append(body.get("name") or "(unnamed body)")
    if not fixed:
        return mjcf_text, []
    for parent in list(root.iter()):
        for child in list(parent):
            if child.tag == "keyframe":
                parent.remove(child)
    return ET.tostring(root, encoding="unicode"), fixed


def lock_urdf_joints(urdf_text: str, names) -> str:
    """The URDF with ``names`` turned into fixed joints (locked at zero)."""
    names = set(names)
    if not names:
        return urdf_text
    root = ET.fromstring(urdf_text)
    for joint in root.iter("joint"):
        if joint.get("name") in names:
            joint.set("type", "fixed")
            for tag in ("mimic", "limit", "axis", "dynamics"):
                for el in joint.findall(tag):
                    joint.remove(el)
    return ET.tostring(root, encoding="unicode")


def lock_mjcf_joints(mjcf_text: str, names) -> str:
    """The MJCF without the joints ``names`` (their bodies held at ``qpos = ref``, which is zero
    unless the joint has a ``ref``), nor the actuators, sensors, equalities, tendon entries and
    keyframes that refer to them."""
    names = set(names)
    if not names:
        return mjcf_text
    root = ET.fromstring(mjcf_text)
    parents = {child: parent for parent in root.iter() for child in parent}
    for joint in [j for j in root.iter("joint") if j.get("name") in names and parents[j].tag == "body"]:
        parents[joint].remove(joint)
    gone_tendons = set()
    for tendon in root.iter("tendon"):
        for fixed in list(tendon):
            for entry in [e for e in fixed if e.tag == "joint" and e.get("joint") in names]:
                fixed.remove(entry)
            if fixed.tag == "fixed" and not [e for e in fixed if e.tag == "joint"]:
                tendon.remove(fixed)
                gone_tendons.add(fixed.get("name"))
    refs = ("joint", "joint1", "joint2", "jointinparent")
    for section in ("actuator", "sensor", "equality"):
        for holder in root.iter(section):
            for el in list(holder):
                if any(el.get(r) in names for r in refs) or (el.get("tendon") is not None and el.get("tendon") in gone_tendons):
                    holder.remove(el)
    for parent in list(root.iter()):
        for child in [c for c in parent if c.tag == "keyframe"]:
            parent.remove(child)
    return ET.tostring(root, encoding="unicode")
