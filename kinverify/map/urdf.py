"""A URDF (or a xacro file, compiled first) as a :class:`~kinverify.map.side.Side`.

Order: the URDF's declaration order of its movable joints (revolute, continuous, prismatic), the
order ``urdf_parser_py``/yourdfpy and most URDF-based training code list them in. A URDF states
effort and velocity limits (``<limit>``), ``<dynamics damping friction>`` and ``<mimic>``; it has no
default pose, no PD gains and no armature, and no actuators unless it has ``<transmission>``
elements (then their order is the actuator order, and Drake's extensions inside them are read:
``drake:rotor_inertia``·``drake:gear_ratio``² is the reflected inertia, an armature, and
``drake:controller_gains p d`` the PD gains). Without transmissions, which joints are driven is
not stated (each simulator decides)."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from kinverify.errors import library_reason
from kinverify.filemode.align.floating import fixed_urdf
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.filemode.read.loading import load_urdf
from kinverify.map.side import Actuator, Follows, MapJoint, Side

MOVABLE = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"}
EXPRESSES = frozenset({"effort", "velocity", "friction", "joint_damping"})


def read_urdf(path: str, options) -> Side:
    """The URDF's side; its description (Pinocchio's reading) is kept for matching joints."""
    loaded = load_urdf(path)
    root = loaded.tree
    joints = []
    for el in root.findall("joint"):
        if el.get("type") not in MOVABLE:
            continue
        j = MapJoint(el.get("name", ""), MOVABLE[el.get("type", "")])  # load_urdf refuses a nameless joint
        limit, dynamics, mimic = el.find("limit"), el.find("dynamics"), el.find("mimic")
        for name, element, attribute in (
            ("effort", limit, "effort"),
            ("velocity", limit, "velocity"),
            ("friction", dynamics, "friction"),
            ("joint_damping", dynamics, "damping"),
        ):
            if element is not None and (value := element.get(attribute)) is not None:
                setattr(j, name, float(value))
                j.how[name] = f"<{element.tag} {attribute}>"
        if mimic is not None and (leader := mimic.get("joint")):
            j.follows = Follows(leader, float(mimic.get("multiplier", 1.0)), float(mimic.get("offset", 0.0)), "<mimic>")
        joints.append(j)
    actuators = _transmissions(root, joints)
    expresses = EXPRESSES | ({"armature", "stiffness", "damping"} if actuators else frozenset())
    notes = list(loaded.warnings)
    try:
        desc = describe_urdf(fixed_urdf(loaded.text, keep_origin=True))
    except (ValueError, RuntimeError) as err:  # Pinocchio refuses it: joints matched by name only
        desc = None
        notes.append(f"Pinocchio cannot read it ({library_reason(err)}): joints matched to the other files by name")
    if actuators is None:
        notes.append("no <transmission>: which joints are driven is each simulator's choice (not compared)")
    return Side(path, path, "urdf", "URDF declaration order", joints, actuators, expresses, desc, notes)


def _tag(el: ET.Element) -> str:
    return el.tag.split("}")[-1].split(":")[-1]


def _transmissions(root: ET.Element, joints: list[MapJoint]) -> list[Actuator] | None:
    """The ``<transmission>`` elements in order, as actuators (None when the URDF has none); the
    joints they name are marked driven, the others not, and Drake's extensions read."""
    found = root.findall("transmission")
    if not found:
        return None
    by_name = {j.name: j for j in joints}
    actuators = []
    for tr in found:
        names = tuple(name for j in tr.findall("joint") if (name := j.get("name")) is not None and name in by_name)
        if not names:
            continue
        extras = {_tag(el): el for el in tr.iter()}
        actuators.append(Actuator(tr.get("name") or names[0], names, "transmission", direct=len(names) == 1))
        for name in names:
            j = by_name[name]
            j.driven, j.mode = True, "transmission"
            rotor, gear = extras.get("rotor_inertia"), extras.get("gear_ratio")
            if rotor is not None and (inertia := rotor.get("value")) is not None:
                ratio = float(value) if gear is not None and (value := gear.get("value")) is not None else 1.0
                j.armature = float(inertia) * ratio**2
                j.how["armature"] = "drake:rotor_inertia × drake:gear_ratio²"
            gains = extras.get("controller_gains")
            if gains is not None and (p := gains.get("p")) is not None:
                j.stiffness, j.damping = float(p), float(gains.get("d", 0.0))
                j.how["stiffness"] = j.how["damping"] = "drake:controller_gains"
    for j in joints:
        if j.driven is None:
            j.driven = False
    return actuators
