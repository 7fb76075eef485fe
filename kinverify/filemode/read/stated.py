"""What each file states, and what it leaves to its format's default.

A value one file leaves unset (a URDF without ``<dynamics>``, an MJCF joint without ``damping``
in itself or in its default classes, a servo without ``forcerange``) is read as the format's
default by the libraries, so the readings can differ without the files disagreeing: one file is
silent. File mode calls that a warning saying which file leaves it unset and what the other states;
two stated values that differ stay an error (docs/file-mode.md, "Unset is not different").

MJCF attributes come from the element, else from its default class: its ``class``, else the
nearest enclosing ``childclass``, else the top-level ``<default>`` ("main"), each class inheriting
from the classes it is nested in, as MuJoCo resolves them.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

JOINT_VALUES = ("damping", "friction", "armature", "range", "effort")
MJCF_ATTRIBUTES = {
    "damping": ("damping",),
    "friction": ("frictionloss",),
    "armature": ("armature",),
    "range": ("range", "limited"),
}


def class_defaults(root: ET.Element, tag: str) -> dict[str, list[dict]]:
    """Default class name -> the attributes of ``tag`` it and its enclosing classes set, nearest first."""
    out: dict[str, list[dict]] = {}

    def walk(el: ET.Element, inherited: list[dict]) -> None:
        own = el.find(tag)
        chain = ([dict(own.attrib)] if own is not None else []) + inherited
        out[el.get("class", "main")] = chain
        for child in el.findall("default"):
            walk(child, chain)

    for top in root.findall("default"):
        walk(top, [])
    return out


def default_chain(el: ET.Element, parents: dict, defaults: dict[str, list[dict]]) -> list[dict]:
    """The attribute sets an MJCF element inherits, nearest first (its class, else the nearest
    enclosing ``childclass``, else "main")."""
    cls, up = el.get("class"), el
    while cls is None and up in parents:
        up = parents[up]
        cls = up.get("childclass")
    return defaults.get(cls or "main", [])


def attribute(el: ET.Element, name: str, parents: dict, defaults: dict[str, list[dict]]) -> str | None:
    """An MJCF element's attribute as MuJoCo resolves it: its own, else its default class's."""
    if el.get(name) is not None:
        return el.get(name)
    return next((attrs[name] for attrs in default_chain(el, parents, defaults) if name in attrs), None)


def mjcf_joint_values(root: ET.Element) -> dict[str, frozenset[str]]:
    """MJCF joint name -> the values of :data:`JOINT_VALUES` it states (``effort`` is decided from
    the actuators, see :func:`stated_effort`)."""
    parents = {child: parent for parent in root.iter() for child in parent}
    defaults = class_defaults(root, "joint")
    out = {}
    for joint in root.iter("joint"):
        if parents.get(joint) is None or parents[joint].tag == "default" or not joint.get("name"):
            continue
        out[joint.get("name")] = frozenset(
            value
            for value, attrs in MJCF_ATTRIBUTES.items()
            if any(attribute(joint, a, parents, defaults) is not None for a in attrs)
        )
    return out  # type: ignore[return-value]  # unnamed joints skipped above


def urdf_joint_values(root: ET.Element) -> dict[str, frozenset[str]]:
    """URDF joint name -> the values of :data:`JOINT_VALUES` it states: ``<dynamics damping>`` and
    ``friction``, ``<limit>`` (position limits, and ``effort``); a continuous joint states that it
    has no position limits. URDF has no armature."""
    out = {}
    for joint in root.findall("joint"):  # not a <transmission>'s <joint>, which names one
        dynamics, limit = joint.find("dynamics"), joint.find("limit")
        values = {
            v
            for v, a in (("damping", "damping"), ("friction", "friction"))
            if dynamics is not None and dynamics.get(a) is not None
        }
        if joint.get("type") == "continuous" or (limit is not None and (limit.get("lower") or limit.get("upper"))):
            values.add("range")
        if limit is not None and limit.get("effort") is not None:
            values.add("effort")
        out[joint.get("name")] = frozenset(values)
    return out  # type: ignore[return-value]  # a URDF's names are checked on reading


def urdf_links_without_inertial(root: ET.Element) -> set[str]:
    """URDF links that state no ``<inertial>`` (massless by the format's default)."""
    return {link.get("name") for link in root.findall("link") if link.find("inertial") is None}  # type: ignore[misc]  # a URDF's names are checked on reading


def unset(stated: frozenset[str] | None, value: str) -> bool:
    """Whether a joint leaves ``value`` unset (``stated`` None: not known, taken as stated)."""
    return stated is not None and value not in stated
