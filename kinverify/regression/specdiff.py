"""Parameter-level differences between two :class:`~kinverify.spec.ArmSpec`.

Joints, links and tools are matched by name; every differing field is one :class:`ParamChange`
(origins, axes, limits, joint dynamics, inertias, geometry, tool parents, base placement,
gravity, DH table), and names present in only one spec are ``added``/``removed`` changes.
Numbers equal to within ``atol`` (default 1e-12, far below any physical change) count as equal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from kinverify.model.spec import ArmSpec, Link

ATOL = 1e-12


@dataclass(frozen=True)
class ParamChange:
    """``where`` is the object (``joint joint2``, ``link link3``, ``tool tcp``, ``base``, ``arm``),
    ``field`` the parameter (``origin.xyz``, ``limits.upper``, ``inertial.mass``...);
    ``kind`` is ``changed``, ``added`` or ``removed``; ``delta`` the Euclidean size of a numeric
    change in the field's unit (m, rad, kg...), None for non-numeric changes."""

    where: str
    field: str
    kind: str
    old: Any
    new: Any
    delta: float | None = None

    def describe(self) -> str:
        if self.kind == "added":
            return f"{self.where} added"
        if self.kind == "removed":
            return f"{self.where} removed"
        size = f" (Δ {self.delta:.6g})" if self.delta is not None else ""
        return f"{self.where}: {self.field} {_fmt(self.old)} -> {_fmt(self.new)}{size}"

    def to_dict(self) -> dict[str, Any]:
        return {
            "where": self.where,
            "field": self.field,
            "kind": self.kind,
            "old": _plain(self.old),
            "new": _plain(self.new),
            "delta": self.delta,
            "text": self.describe(),
        }


def _plain(v):
    return list(v) if isinstance(v, tuple) else v


def _fmt(v) -> str:
    if isinstance(v, (tuple, list)):
        return "[" + ", ".join(_fmt(x) for x in v) + "]"
    if isinstance(v, float):
        return f"{v:.9g}"
    return str(v)


def _numeric(v) -> bool:
    if isinstance(v, bool):
        return False
    if isinstance(v, (int, float)):
        return True
    return isinstance(v, (tuple, list)) and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v)


def _compare(out: list[ParamChange], where: str, field: str, old, new, atol: float) -> None:
    if _numeric(old) and _numeric(new):
        a = [float(old)] if isinstance(old, (int, float)) else [float(x) for x in old]
        b = [float(new)] if isinstance(new, (int, float)) else [float(x) for x in new]
        if len(a) == len(b):
            delta = math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b, strict=True)))
            if delta > atol:
                out.append(ParamChange(where, field, "changed", old, new, delta))
            return
    if old != new:
        out.append(ParamChange(where, field, "changed", old, new))


def _link_changes(out, old: Link, new: Link, atol: float) -> None:
    where = f"link {new.name}"
    for attr in ("mass", "com", "inertia"):
        _compare(out, where, f"inertial.{attr}", getattr(old.inertial, attr), getattr(new.inertial, attr), atol)
    og, ng = old.geometry, new.geometry
    if (og is None) != (ng is None) or (og is not None and ng is not None and og.shape != ng.shape):
        _compare(out, where, "geometry", og and og.shape, ng and ng.shape, atol)
    elif og is not None:
        for attr in ("radius", "fromto", "size", "pos"):
            a, b = getattr(og, attr), getattr(ng, attr)
            if a is None or b is None:
                if a != b:
                    out.append(ParamChange(where, f"geometry.{attr}", "changed", a, b))
            else:
                _compare(out, where, f"geometry.{attr}", a, b, atol)


def _names(out, kind: str, old: list[str], new: list[str]) -> list[str]:
    """Record added/removed names; return the common ones in the new order."""
    for name in old:
        if name not in new:
            out.append(ParamChange(f"{kind} {name}", "name", "removed", name, None))
    for name in new:
        if name not in old:
            out.append(ParamChange(f"{kind} {name}", "name", "added", None, name))
    return [n for n in new if n in old]


def diff_specs(old: ArmSpec, new: ArmSpec, atol: float = ATOL) -> list[ParamChange]:
    """Every parameter that differs between ``old`` and ``new``, base to tip."""
    out: list[ParamChange] = []
    _compare(out, "arm", "name", old.name, new.name, atol)
    _compare(out, "arm", "gravity", old.gravity, new.gravity, atol)
    _compare(out, "base", "origin.xyz", old.base_origin.xyz, new.base_origin.xyz, atol)
    _compare(out, "base", "origin.rpy", old.base_origin.rpy, new.base_origin.rpy, atol)
    old_joints, new_joints = {j.name: j for j in old.joints}, {j.name: j for j in new.joints}
    common = _names(out, "joint", list(old_joints), list(new_joints))
    if [n for n in old_joints if n in common] != common:
        out.append(ParamChange("arm", "joint order", "changed", [n for n in old_joints if n in common], common))
    old_parent = dict(zip(old.joint_names, (old.link_names[p] for p in old.parent_indices), strict=True))
    new_parent = dict(zip(new.joint_names, (new.link_names[p] for p in new.parent_indices), strict=True))
    for name in common:
        a, b = old_joints[name], new_joints[name]
        where = f"joint {name}"
        for field, x, y in (
            ("parent", old_parent[name], new_parent[name]),
            ("type", a.type, b.type),
            ("origin.xyz", a.origin.xyz, b.origin.xyz),
            ("origin.rpy", a.origin.rpy, b.origin.rpy),
            ("axis", a.axis, b.axis),
            ("link", a.link.name, b.link.name),
        ):
            _compare(out, where, field, x, y, atol)
        for attr in ("lower", "upper", "velocity", "effort"):
            _compare(out, where, f"limits.{attr}", getattr(a.limits, attr), getattr(b.limits, attr), atol)
        for attr in ("damping", "friction", "armature"):
            _compare(out, where, attr, getattr(a, attr), getattr(b, attr), atol)
    old_links = {link.name: link for link in (old.base_link, *(j.link for j in old.joints))}
    new_links = {link.name: link for link in (new.base_link, *(j.link for j in new.joints))}
    for name in _names(out, "link", list(old_links), list(new_links)):
        _link_changes(out, old_links[name], new_links[name], atol)
    old_tools, new_tools = {t.name: t for t in old.tools}, {t.name: t for t in new.tools}
    for name in _names(out, "tool", list(old_tools), list(new_tools)):
        ta, tb = old_tools[name], new_tools[name]
        _compare(out, f"tool {name}", "parent", ta.parent, tb.parent, atol)
        _compare(out, f"tool {name}", "origin.xyz", ta.origin.xyz, tb.origin.xyz, atol)
        _compare(out, f"tool {name}", "origin.rpy", ta.origin.rpy, tb.origin.rpy, atol)
    _dh_changes(out, old, new, atol)
    return out


def _dh_changes(out, old: ArmSpec, new: ArmSpec, atol: float) -> None:
    if (old.dh is None) != (new.dh is None):
        out.append(ParamChange("dh", "table", "added" if old.dh is None else "removed", old.dh is not None, new.dh is not None))
        return
    if old.dh is None or new.dh is None:  # both or neither
        return
    _compare(out, "dh", "convention", old.dh.convention, new.dh.convention, atol)
    for i, (a, b) in enumerate(zip(old.dh.rows, new.dh.rows, strict=False)):
        for attr in ("a", "alpha", "d", "theta"):
            _compare(out, f"dh row {i}", attr, getattr(a, attr), getattr(b, attr), atol)
