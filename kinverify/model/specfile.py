"""Load an :class:`~kinverify.spec.ArmSpec` from a TOML file or a plain dict.

The format is documented in the README ("Spec format"). Every error is a one-line
:class:`~kinverify.errors.SpecError` naming the file and the field path.
"""

from __future__ import annotations

import math
import os
import tomllib
from pathlib import Path
from typing import Any, Literal, cast, overload

import numpy as np

from kinverify.model import dh as dhmod
from kinverify.errors import SpecError
from kinverify.pipeline.limits import MAX_JOINTS, MAX_MODEL_BYTES
from kinverify.model.inertia import DEFAULT_DENSITY, inertial_from_geometry
from kinverify.model.spec import (
    JOINT_TYPES,
    check_scalar,
    ArmSpec,
    DHRow,
    DHTable,
    Geometry,
    Inertial,
    Joint,
    Limits,
    Link,
    Origin,
    Tool,
)

ANGLE_UNITS = {"rad": 1.0, "deg": math.pi / 180.0}
DEFAULT_LINK_RADIUS = 0.03  # m, the seed arm's link radius


class _Table:
    """A dict read at a field path: typed getters, and unknown keys rejected on ``done()``."""

    def __init__(self, data: Any, path: str) -> None:
        if not isinstance(data, dict):
            raise SpecError(path, f"expected a table, got {type(data).__name__}")
        self.used: set[str]
        self.data, self.path, self.used = data, path, set()

    def at(self, key: str) -> str:
        return f"{self.path}.{key}" if self.path else key

    def get(self, key: str, default: Any = None, required: bool = False) -> Any:
        self.used.add(key)
        if key not in self.data:
            if required:
                raise SpecError(self.at(key), "missing required field")
            return default
        return self.data[key]

    @overload
    def table(self, key: str, required: Literal[True]) -> "_Table": ...
    @overload
    def table(self, key: str, required: bool = False) -> "_Table | None": ...
    def table(self, key: str, required: bool = False) -> "_Table | None":
        value = self.get(key, required=required)
        return None if value is None else _Table(value, self.at(key))

    def tables(self, key: str) -> list["_Table"]:
        value = self.get(key, [])
        if not isinstance(value, list):
            raise SpecError(self.at(key), f"expected an array of tables, got {type(value).__name__}")
        return [_Table(item, f"{self.at(key)}[{i}]") for i, item in enumerate(value)]

    def string(self, key: str, default: str | None = None, required: bool = False) -> str | None:
        value = self.get(key, default, required)
        if value is not None and not isinstance(value, str):
            raise SpecError(self.at(key), f"expected a string, got {value!r}")
        return value

    def done(self) -> None:
        unknown = sorted(set(self.data) - self.used)
        if unknown:
            raise SpecError(self.at(unknown[0]), f"unknown field (allowed: {', '.join(sorted(self.used))})")


def _build(path: str, factory, **kwargs):
    """Call a dataclass constructor, prefixing its field errors with ``path``."""
    try:
        return factory(**kwargs)
    except SpecError as err:
        raise err.within(path) from None


def _angle_unit(t: _Table, key: str = "unit", default: str | None = None) -> float:
    unit = t.string(key, default)
    if unit is None:
        raise SpecError(t.at(key), "missing required field (angle unit 'deg' or 'rad')")
    if unit not in ANGLE_UNITS:
        raise SpecError(t.at(key), f"unknown angle unit {unit!r}; expected 'deg' or 'rad'")
    return ANGLE_UNITS[unit]


def _scaled(value, scale: float, path: str):
    if isinstance(value, list) and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value):
        return [v * scale for v in value]
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return value * scale
    raise SpecError(path, f"expected numbers, got {value!r}")


def _origin(t: _Table) -> Origin:
    xyz = t.get("xyz", (0.0, 0.0, 0.0))
    rpy, rpy_deg = t.get("rpy"), t.get("rpy_deg")
    if rpy is not None and rpy_deg is not None:
        raise SpecError(t.at("rpy_deg"), "give either rpy [rad] or rpy_deg [deg], not both")
    if rpy_deg is not None:
        rpy = _scaled(rpy_deg, math.pi / 180.0, t.at("rpy_deg"))
    return _build(t.path, Origin, xyz=xyz, rpy=rpy if rpy is not None else (0.0, 0.0, 0.0))


def _geometry(t: _Table) -> Geometry:
    g = _build(
        t.path,
        Geometry,
        shape=t.string("shape", required=True),
        radius=t.get("radius", 0.0),
        fromto=t.get("fromto"),
        size=t.get("size"),
        pos=t.get("pos", (0.0, 0.0, 0.0)),
    )
    t.done()
    return g


def _link(t: _Table, default_name: str, default_geometry: Geometry | None, density: float) -> Link:
    name = t.get("name", default_name)
    g_table = t.table("geometry")
    geometry = _geometry(g_table) if g_table is not None else default_geometry
    i_table, mass = t.table("inertial"), t.get("mass")
    if i_table is not None:
        if mass is not None:
            raise SpecError(t.at("mass"), "give either mass or an inertial table, not both")
        inertial = _build(
            i_table.path,
            Inertial,
            mass=i_table.get("mass", required=True),
            com=i_table.get("com", (0.0, 0.0, 0.0)),
            inertia=i_table.get("inertia", required=True),
        )
        i_table.done()
    else:
        if geometry is None:
            raise SpecError(t.at("inertial"), "missing: a link without geometry needs inertial data")
        if mass is not None:
            mass = check_scalar(mass, t.at("mass"), positive=True)
        try:
            inertial = _build(t.path, inertial_from_geometry, geom=geometry, mass=mass, density=density)
        except ArithmeticError:  # a size so small (or large) that the volume under- or overflows
            raise SpecError(
                t.at("geometry"), "too small or too large to derive a mass and inertia from; give an inertial table"
            ) from None
    t.done()
    return _build(t.path, Link, name=name, inertial=inertial, geometry=geometry)


def _default_geometry(end, radius: float) -> Geometry:
    """A capsule from the link origin to ``end`` (next joint or tool), or a sphere."""
    if end is None or np.linalg.norm(end) < 1e-6:
        return Geometry("sphere", radius=radius)
    return Geometry("capsule", radius=radius, fromto=(0.0, 0.0, 0.0) + tuple(float(x) for x in end))


def _limits(t: _Table, joint_type: str) -> Limits:
    scale = _angle_unit(t) if joint_type == "revolute" else 1.0
    if joint_type == "prismatic" and t.string("unit", "m") != "m":
        raise SpecError(t.at("unit"), "prismatic limits are in metres: unit must be 'm'")
    lower, upper = t.get("lower", required=True), t.get("upper", required=True)
    limits = _build(
        t.path,
        Limits,
        lower=_scaled(lower, scale, t.at("lower")),
        upper=_scaled(upper, scale, t.at("upper")),
        velocity=_scaled(t.get("velocity", 3.0 / scale), scale, t.at("velocity")),
        effort=t.get("effort", 100.0),
    )
    t.done()
    return limits


def _dh_row(t: _Table, scale: float) -> DHRow:
    values = {}
    for key in ("a", "alpha", "d", "theta"):
        v = check_scalar(t.get(key, 0.0), t.at(key))
        values[key] = v * (scale if key in ("alpha", "theta") else 1.0)
    t.done()
    return DHRow(**values)


BOOLEAN_FIELDS = ("base.floating",)  # the only fields that take true/false


def _strict_types(value: Any, path: str) -> None:
    """Booleans only in :data:`BOOLEAN_FIELDS` (and there only booleans), no text in an array:
    ``true`` and ``"1"`` are not numbers (numpy would take them as 1.0), nor ``1`` a boolean."""
    if path in BOOLEAN_FIELDS:
        if not isinstance(value, bool):
            raise SpecError(path, f"expected true or false, got {_toml_repr(value)}")
        return
    if isinstance(value, bool):
        raise SpecError(path, f"expected a number or a string, got a boolean ({str(value).lower()}): booleans are not numbers")
    if isinstance(value, dict):
        for key, item in value.items():
            _strict_types(item, f"{path}.{key}" if path else str(key))
    elif isinstance(value, list):
        for i, item in enumerate(value):
            if isinstance(item, (bool, str)):
                raise SpecError(path, f"expected numbers, got {_toml_repr(value)} (element {i} is not a number)")
            _strict_types(item, f"{path}[{i}]")


def _toml_repr(value: Any) -> str:
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, list):
        return "[" + ", ".join(_toml_repr(v) for v in value) + "]"
    return repr(value)


def spec_from_dict(data: dict, file: str | None = None) -> ArmSpec:
    """Build a validated spec from the TOML structure (see README); errors name ``file``."""
    try:
        _strict_types(data, "")
        return _spec_from_table(_Table(data, ""))
    except SpecError as err:
        raise err.in_file(file) if file else err from None


def _spec_from_table(top: _Table) -> ArmSpec:
    name = top.string("name", required=True)
    top.string("description")
    density = check_scalar(top.get("density", DEFAULT_DENSITY), "density", positive=True)
    radius = check_scalar(top.get("link_radius", DEFAULT_LINK_RADIUS), "link_radius", positive=True)
    dh_table = top.table("dh")
    convention = None
    if dh_table is not None:
        convention = dh_table.string("convention", required=True)
        if convention not in dhmod.CONVENTIONS:
            raise SpecError(dh_table.at("convention"), f"unknown DH convention {convention!r}; expected 'standard' or 'modified'")
        dh_scale = _angle_unit(dh_table, "angle_unit")
        flange_name = dh_table.string("flange", "flange")
        dh_table.done()
    joint_tables = top.tables("joints")
    if not joint_tables:
        raise SpecError("joints", "an arm needs at least one joint")
    if len(joint_tables) > MAX_JOINTS:
        raise SpecError(
            "joints", f"{len(joint_tables)} joints, above the {MAX_JOINTS} kinverify compares (see docs/robustness.md)"
        )
    types, axes, origins, rows = [], [], [], []
    for jt in joint_tables:
        jtype = jt.string("type", "revolute")
        if jtype not in JOINT_TYPES:
            raise SpecError(jt.at("type"), f"unknown joint type {jtype!r}; expected one of {', '.join(JOINT_TYPES)}")
        types.append(jtype)
        if convention is None:
            if jt.get("dh") is not None:
                raise SpecError(jt.at("dh"), "a dh row needs a top-level [dh] table with the convention")
            origins.append(_origin(jt))
            axes.append(jt.get("axis", required=True))
        else:
            for key in ("xyz", "rpy", "rpy_deg", "axis"):
                if key in jt.data:
                    raise SpecError(jt.at(key), "DH joints take their origin and axis from the dh row")
            rows.append(_dh_row(jt.table("dh", required=True), dh_scale))
            axes.append((0.0, 0.0, 1.0))
    flange = None
    if convention is not None:
        origins, flange_t = dhmod.joint_origins(convention, tuple(rows))
        flange = None if flange_t is None else dhmod.origin_from_transform(flange_t)
    tool_tables = top.tables("tools")
    tool_specs = []
    for tt in tool_tables:
        tool_specs.append((tt, tt.string("name", required=True), tt.string("parent"), _origin(tt)))
    last_link_table = joint_tables[-1].data.get("link", {})
    last_link = last_link_table.get("name", f"link{len(joint_tables)}") if isinstance(last_link_table, dict) else None
    tools = []
    if flange is not None:
        tools.append(Tool(cast(str, flange_name), cast(str, last_link), flange))  # a non-table last [link] is refused below
    for tt, tname, parent, origin in tool_specs:
        if flange is not None and parent in (None, flange_name):
            t = flange.transform @ origin.transform
            origin = dhmod.origin_from_transform(t)
            parent = last_link
        tools.append(_build(tt.path, Tool, name=tname, parent=parent or last_link, origin=origin))
        tt.done()
    link_names = [_link_name(jt, i) for i, jt in enumerate(joint_tables)]
    parents = [jt.string("parent") for jt in joint_tables]
    joints = []
    for i, jt in enumerate(joint_tables):
        # default geometry: towards the first joint hanging from this link, else its first tool
        children = [k for k in range(i + 1, len(joint_tables)) if (parents[k] or link_names[k - 1]) == link_names[i]]
        end: tuple[float, float, float] | None
        if children:
            end = origins[children[0]].xyz
        else:
            ends = [t.origin.xyz for t in tools if t.parent == link_names[i]]
            end = ends[0] if ends else None
        lt = jt.table("link") or _Table({}, jt.at("link"))
        link = _link(lt, f"link{i + 1}", _default_geometry(end, radius), density)
        lim_table = jt.table("limits", required=True)
        joint = _build(
            jt.path,
            Joint,
            name=jt.get("name", f"joint{i + 1}"),
            type=types[i],
            origin=origins[i],
            axis=axes[i],
            limits=_limits(lim_table, types[i]),
            link=link,
            damping=jt.get("damping", 0.0),
            friction=jt.get("friction", 0.0),
            armature=jt.get("armature", 0.0),
            parent=parents[i],
        )
        jt.done()
        joints.append(joint)
    base = top.table("base") or _Table({}, "base")
    base_origin = _origin(base)
    floating = base.get("floating", False)
    first = origins[0].xyz
    base_geometry = (
        _default_geometry(first, radius * 5 / 3) if np.linalg.norm(first) > 1e-6 else Geometry("sphere", radius=radius)
    )
    bl = base.table("link") or _Table({}, "base.link")
    base_link = _link(bl, "base", base_geometry, density)
    base.done()
    dh = DHTable(convention, tuple(rows)) if convention else None
    gravity = top.get("gravity", (0.0, 0.0, -9.81))
    top.done()
    return _build(
        "",
        ArmSpec,
        name=name,
        base_origin=base_origin,
        base_link=base_link,
        joints=joints,
        tools=tools,
        dh=dh,
        gravity=gravity,
        floating=floating,
    )


def _link_name(jt, i: int) -> str:
    table = jt.data.get("link", {})
    name = table.get("name") if isinstance(table, dict) else None
    return name if isinstance(name, str) else f"link{i + 1}"


def load_spec(path: str | Path) -> ArmSpec:
    """Read and validate a spec file; raise :class:`SpecError` naming the file on any problem
    (read by :mod:`kinverify.io.read`: a regular file of at most ``MAX_MODEL_BYTES``)."""
    from kinverify.io.formats import toml_loads
    from kinverify.io.read import InputFileError, read_bytes

    file = str(path)
    try:
        raw = read_bytes(path, "the spec MODEL", MAX_MODEL_BYTES)
    except InputFileError as err:
        reason = f"cannot read spec file: {os.strerror(err.errno)}" if err.errno else err.reason.removeprefix("is ")
        raise SpecError("", reason, file) from None
    try:
        data = toml_loads(raw.decode("utf-8"), file)
    except UnicodeDecodeError:
        raise SpecError("", "not a UTF-8 text file", file) from None
    except tomllib.TOMLDecodeError as err:
        raise SpecError("", f"malformed TOML: {err}", file) from None
    except InputFileError as err:
        raise SpecError("", err.reason, file) from None
    return spec_from_dict(data, file)
