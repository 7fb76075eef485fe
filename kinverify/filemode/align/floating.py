"""Floating bases in file mode: which file floats, and the base coordinates of both.

A URDF floats when its root joint is ``floating``; it is fixed when its root link is ``world``
(the ROS and Gazebo convention for a robot welded to the world) with fixed joints below it; a
root link with no joint at all says neither (ROS describes fixed and floating robots alike that
way). An MJCF floats when one top-level body has a free joint.

When both float (or the URDF leaves it unstated and the MJCF floats), the base pose becomes six
compared coordinates, ``base:x ... base:yaw`` (:mod:`kinverify.model.floating`): each file's
base body at that world pose. The alignment still runs on both files with their bases fixed at
the identity, so its world transform ``T`` is how the MJCF's base body frame sits on the URDF's
base link (``T⁻¹`` in the URDF base's axes): the MJCF side is given the base pose ``T·B·T⁻¹`` in
its world, which brought back by ``T⁻¹`` is the URDF's ``B``. The MJCF's start pose (its free
body's ``pos``/``quat``, ``qpos0``) is the free joint's initial value, not a property of the robot.

When only one file floats, that is one finding and the rest is compared with the base fixed.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

import numpy as np

from kinverify.filemode.findings.table import finding, fmt
from kinverify.model.floating import BASE_COORDINATES, base_coordinates, base_limits, base_transforms, rate_matrices

ADDED_ROOT = "world"  # the link added above a URDF root link read as floating (MuJoCo's URDF import: the world)
ADDED_JOINT = "kinverify_floating_base"


@dataclass(frozen=True)
class UrdfBase:
    kind: str  # "floating", "fixed" or "unstated"
    root: str  # the URDF's root link
    joint: str | None  # the floating root joint (kind "floating") or the joint to the world (kind "fixed")
    link: str = ""  # the base link: the floating joint's child, else the root link


def urdf_base(urdf_text: str) -> UrdfBase:
    """How the URDF's root link is held (see the module docstring)."""
    root = ET.fromstring(urdf_text)
    joints = root.findall("joint")
    children = {c.get("link") for j in joints for c in j.findall("child")}
    roots = [el.get("name") for el in root.findall("link") if el.get("name") not in children]
    name = roots[0] if roots else ""
    below = [j for j in joints if (p := j.find("parent")) is not None and p.get("link") == name]
    floating = next((j for j in below if j.get("type") == "floating"), None)
    if floating is not None:
        child = floating.find("child")
        return UrdfBase("floating", name, floating.get("name"), child.get("link") if child is not None else name)  # type: ignore[arg-type]  # a URDF's names are checked on reading
    if name == "world" and below and all(j.get("type") == "fixed" for j in below):
        return UrdfBase("fixed", name, below[0].get("name"), name)
    return UrdfBase("unstated", name, None, name)  # type: ignore[arg-type]  # a URDF's names are checked on reading


def fixed_urdf(urdf_text: str, keep_origin: bool) -> str:
    """The URDF with its floating root joint made fixed: at its ``<origin>`` (``keep_origin``,
    where the URDF puts the base at rest) or at the identity (the base coordinates at zero)."""
    root = ET.fromstring(urdf_text)
    base = urdf_base(urdf_text)
    if base.kind != "floating":
        return urdf_text
    joint = next(j for j in root.findall("joint") if j.get("name") == base.joint)
    joint.set("type", "fixed")
    for el in list(joint):
        if el.tag not in ("parent", "child") and (el.tag != "origin" or not keep_origin):
            joint.remove(el)
    return ET.tostring(root, encoding="unicode")


def floating_urdf(urdf_text: str) -> str:
    """The URDF with a floating joint above its root link when it has none (kind "unstated")."""
    base = urdf_base(urdf_text)
    if base.kind != "unstated":
        return urdf_text
    root = ET.fromstring(urdf_text)
    ET.SubElement(root, "link", name=ADDED_ROOT)
    joint = ET.SubElement(root, "joint", name=ADDED_JOINT, type="floating")
    ET.SubElement(joint, "parent", link=ADDED_ROOT)
    ET.SubElement(joint, "child", link=base.root)
    return ET.tostring(root, encoding="unicode")


def decide(base: UrdfBase, free: list[str]) -> tuple[bool, str, str]:
    """(compare the base as coordinates, finding kind, message) for the URDF's base and the MJCF's
    free top-level bodies; kind "" when there is nothing to say."""
    if len(free) == 1 and base.kind in ("floating", "unstated"):
        how = (
            f"the URDF's root joint {base.joint} is floating"
            if base.kind == "floating"
            else f"the URDF's root link {base.root} has no joint (ROS describes fixed and floating robots alike so; the "
            "MJCF's free joint says this one floats)"
        )
        return (
            True,
            "floating_base",
            (
                f"both files float ({how}; the MJCF's body {free[0]} has a free joint): the base pose is compared as six "
                f"coordinates ({', '.join(BASE_COORDINATES)}), both bases at the same pose; the MJCF's start pose (its free "
                "body's pos/quat) is the free joint's initial value, not a property of the robot"
            ),
        )
    if len(free) > 1:
        extra = "; the URDF's floating root is held there too" if base.kind == "floating" else ""
        return (
            False,
            "floating_base",
            (
                f"the MJCF has {len(free)} free top-level bodies ({', '.join(free)}): held at the identity pose, where the "
                f"URDF's root link is{extra} (the base pose of one robot is compared only when one body floats)"
            ),
        )
    if len(free) == 1 and base.kind == "fixed":
        return (
            False,
            "floating_one_file",
            (
                f"the MJCF's body {free[0]} floats (free joint) but the URDF welds its root link to the world ({base.joint} "
                "is fixed): the files describe different robots; the rest is compared with the MJCF's base held fixed "
                "where the URDF's is"
            ),
        )
    if not free and base.kind == "floating":
        return (
            False,
            "floating_one_file",
            (
                f"the URDF's root joint {base.joint} is floating but the MJCF has no free joint (its robot is welded to the "
                "world): the files describe different robots; the rest is compared with the URDF's base held fixed at the "
                "joint's origin"
            ),
        )
    return False, "", ""


def base_samples(n: int, seed: int) -> np.ndarray:
    """``n`` base coordinates within :func:`base_limits` of the origin."""
    lower, upper = base_limits(np.zeros(3))
    return np.random.default_rng(seed).uniform(lower, upper, size=(n, 6))


def conjugated(t: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The MJCF's base coordinates ``b'`` for ours ``b`` (``B' = T·B·T⁻¹``) and ``D = ∂b'/∂b``
    ``(N, 6, 6)``: linear ``ṗ' = R_T·ṗ − R_T·[R·c]×·ω``, angular ``ω' = R_T·ω`` with ``ω = E(b)·ṙ``,
    ``c`` the translation of ``T⁻¹`` and ``ṙ' = E(b')⁻¹·ω'``."""
    b = np.atleast_2d(np.asarray(b, dtype=float))
    tinv = np.linalg.inv(t)
    big = base_transforms(b)
    new = base_coordinates(t @ big @ tinv)
    rt, c = t[:3, :3], tinv[:3, 3]
    rc = big[:, :3, :3] @ c  # (N, 3)
    skew = np.zeros((len(b), 3, 3))
    skew[:, 0, 1], skew[:, 0, 2], skew[:, 1, 2] = -rc[:, 2], rc[:, 1], -rc[:, 0]
    skew -= np.swapaxes(skew, 1, 2)
    e, e_new = rate_matrices(b), rate_matrices(new)
    d = np.zeros((len(b), 6, 6))
    d[:, :3, :3] = rt
    d[:, :3, 3:] = -rt @ skew @ e
    d[:, 3:, 3:] = np.linalg.solve(e_new, rt @ e)
    return new, d


def base_findings(findings: list, base) -> list:
    """The alignment's findings when a file floats (``base``: the build's ``BaseDecision``): a
    floating file's base pose is a coordinate, so no world transform is reported. When both float,
    the transform is how the MJCF's base body frame sits on the URDF's base link: one warning
    (the comparison is made after it; the same base coordinates put the two robots apart)."""
    if not base.kind or base.kind == "floating_base" and not base.floating:
        return findings
    out = [f for f in findings if f.kind != "base_transform"]
    moved = next((f for f in findings if f.kind == "base_transform"), None)
    if moved is not None and base.floating:
        v = moved.values
        out.insert(
            0,
            finding(
                "base_frame_offset",
                f"the base frames differ: the URDF's base link {base.urdf.link} sits at "
                f"xyz = {fmt(v['xyz'])} m, rpy = {fmt(v['rpy'])} rad in the frame of the MJCF's base body "
                f"{base.free[0]}, so the same base coordinates place the two robots apart (the files are compared "
                "after it)",
                v,
                magnitude=moved.magnitude,
                unit="m|rad",
                link=base.urdf.link,
            ),
        )
    return out
