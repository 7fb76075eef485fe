"""An Isaac Lab-style actuator table (YAML or TOML) as one more side: where the training gains live.

The table mirrors Isaac Lab's ``ArticulationCfg``: actuator groups, each with ``joint_names_expr``
(regular expressions, matched whole against joint names as Isaac Lab does) and ``stiffness``,
``damping``, ``effort_limit``, ``velocity_limit``, ``armature``, ``friction``, each a number or a
``{regex: number}`` table; ``init_state.joint_pos`` (``{regex: number}``) is the default pose::

    units = "radian"            # Isaac Lab's convention (the default); "degree": angles, and gains
                                # and velocities per degree, as USD drives state them
    [actuators.legs]
    joint_names_expr = [".*_hip_joint", ".*_thigh_joint"]
    stiffness = 25.0
    damping = {".*_hip_joint" = 0.5, ".*_thigh_joint" = 0.6}
    [init_state.joint_pos]
    ".*_thigh_joint" = 0.9

A flat form, ``[joints."REGEX"]`` with the same keys, is one group per pattern. Isaac Lab's gains
are per radian for a revolute joint (its Python config feeds PhysX per radian); ``units =
"degree"`` converts stiffness and damping ×180/π, velocities and positions ×π/180. The patterns
are matched against the joint names of the first file in which every pattern names a joint; the
joints the table's groups name are driven; the others keep whatever drive the asset gives them (Isaac
Lab warns and leaves them to the asset: not stated here). A value the table leaves out comes
from the asset, as a ``None`` does in Isaac Lab ("inherited": not compared). It has no order of
its own."""

from __future__ import annotations

import math
import re
import tomllib
from pathlib import Path

import yaml

from kinverify.errors import InputError
from kinverify.io.read import read_bytes
from kinverify.map.side import VALUE_NAMES, MapJoint, Side, to_radian

KEYS = {
    "stiffness": "stiffness",
    "damping": "damping",
    "effort_limit": "effort",
    "effort_limit_sim": "effort",
    "effort": "effort",
    "velocity_limit": "velocity",
    "velocity_limit_sim": "velocity",
    "velocity": "velocity",
    "armature": "armature",
    "friction": "friction",
}
LABEL = "--actuators"


def load_table(path: str) -> dict:
    """The table's content; :class:`InputError` naming the file when it is not YAML or TOML."""
    text = read_bytes(path, LABEL).decode("utf-8", "replace")
    try:
        data = tomllib.loads(text) if Path(path).suffix.lower() == ".toml" else yaml.safe_load(text)
    except (tomllib.TOMLDecodeError, yaml.YAMLError) as err:
        raise InputError(
            f"{LABEL}: {path}: not valid {'TOML' if path.lower().endswith('.toml') else 'YAML'}: "
            f"{' '.join(str(err).split())[:200]}"
        ) from None
    if not isinstance(data, dict):
        raise InputError(f"{LABEL}: {path}: expected a table of actuator groups, got {type(data).__name__}")
    return data


def _groups(data: dict, path: str) -> dict[str, dict]:
    groups = data.get("actuators") or {}
    flat = data.get("joints") or {}
    if not isinstance(groups, dict) or not isinstance(flat, dict):
        raise InputError(f"{LABEL}: {path}: 'actuators' and 'joints' must be tables")
    out = {}
    for name, group in groups.items():
        if not isinstance(group, dict) or "joint_names_expr" not in group:
            raise InputError(f"{LABEL}: {path}: actuators.{name}: expected a table with joint_names_expr")
        exprs = group["joint_names_expr"]
        out[str(name)] = {**group, "joint_names_expr": [exprs] if isinstance(exprs, str) else list(exprs)}
    for pattern, values in flat.items():
        if not isinstance(values, dict):
            raise InputError(f"{LABEL}: {path}: joints.{pattern}: expected a table of values")
        out[f"joints.{pattern}"] = {**values, "joint_names_expr": [str(pattern)]}
    unknown = [
        f"{g}.{k}" for g, group in out.items() for k in group if k not in KEYS and k not in ("joint_names_expr", "class_type")
    ]
    if unknown:
        raise InputError(f"{LABEL}: {path}: unknown key {unknown[0]}; known: joint_names_expr, {', '.join(KEYS)}")
    if not out:
        raise InputError(f'{LABEL}: {path}: no actuator groups (expected [actuators.NAME] or [joints."REGEX"])')
    return out


def _compile(pattern, where: str, path: str) -> re.Pattern:
    try:
        return re.compile(str(pattern))
    except re.error as err:
        raise InputError(f"{LABEL}: {path}: {where}: bad regular expression {pattern!r}: {err}") from None


def _number(v, where: str, path: str) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise InputError(f"{LABEL}: {path}: {where}: expected a finite number, got {v!r}")
    return float(v)


def _patterns(data: dict, path: str) -> list[str]:
    pats = [p for g in _groups(data, path).values() for p in g["joint_names_expr"]]
    pos = (data.get("init_state") or {}).get("joint_pos") or {}
    return pats + list(pos)


def read_table(path: str, files: list[Side]) -> tuple[Side, int]:
    """The table as a side, its joints named as in the first of ``files`` in which every pattern
    names a joint, and that file's index."""
    data = load_table(path)
    units = data.get("units", "radian")
    if units not in ("radian", "degree"):
        raise InputError(f"{LABEL}: {path}: units: expected 'radian' or 'degree', got {units!r}")
    patterns = [_compile(p, "joint_names_expr", path) for p in _patterns(data, path)]
    target = next((s for s in files if all(any(p.fullmatch(n) for n in s.names) for p in patterns)), None)
    if target is None:
        missing = next((p.pattern for p in patterns if not any(p.fullmatch(n) for s in files for n in s.names)), None)
        raise InputError(
            f"{LABEL}: {path}: no file has every joint the table names (pattern {missing!r} "
            f"matches no joint of {', '.join(s.label for s in files)})"
            if missing
            else f"{LABEL}: {path}: no single file has every joint the table names"
        )
    joints = {j.name: MapJoint(j.name, j.type) for j in target.joints}  # driven: None, the asset's drives
    owner: dict[str, str] = {}
    for gname, group in _groups(data, path).items():
        exprs = [_compile(p, f"actuators.{gname}.joint_names_expr", path) for p in group["joint_names_expr"]]
        members = [n for n in joints if any(e.fullmatch(n) for e in exprs)]
        for n in members:
            if n in owner:
                raise InputError(f"{LABEL}: {path}: joint {n!r} is in two actuator groups ({owner[n]}, {gname})")
            owner[n] = gname
            joints[n].driven, joints[n].mode = True, f"group {gname}"
        for key, ours in KEYS.items():
            if key in group and group[key] is not None:
                _assign(joints, members, ours, group[key], f"actuators.{gname}.{key}", path, units)
    pos = (data.get("init_state") or {}).get("joint_pos") or {}
    if pos:
        _assign(joints, list(joints), "default", pos, "init_state.joint_pos", path, units)
    expresses = frozenset(VALUE_NAMES)  # what it leaves out comes from the asset: "inherited", never a finding
    notes = [
        f"joint names matched against {target.label}; angles per {units}"
        + (" (converted to per radian)" if units == "degree" else "")
    ]
    side = Side(
        path,
        path,
        "table",
        "(no order: an actuator table)",
        list(joints.values()),
        None,
        expresses,
        notes=notes,
        ordered=False,
        silence="inherited",
    )
    return side, files.index(target)


def _assign(joints: dict, members: list[str], name: str, spec, where: str, path: str, units: str) -> None:
    """``spec`` (a number, or ``{regex: number}``) on the ``members``; a joint two patterns name is refused."""
    if isinstance(spec, dict):
        rules = [(_compile(p, where, path), _number(v, f"{where}.{p}", path)) for p, v in spec.items()]
    else:
        rules = [(re.compile(".*"), _number(spec, where, path))]
    for n in members:
        hits = [v for p, v in rules if p.fullmatch(n)]
        if len(hits) > 1 and isinstance(spec, dict):
            raise InputError(f"{LABEL}: {path}: {where}: joint {n!r} matches several patterns")
        if hits:
            j = joints[n]
            amount = to_radian(hits[0], name, j.type) if units == "degree" else hits[0]
            if not math.isfinite(amount) or (amount < 0 and name != "default"):
                raise InputError(
                    f"{LABEL}: {path}: {where}: {hits[0]!r} on joint {n!r} is "
                    + ("negative" if amount < 0 else "too large once per radian")
                )
            setattr(j, name, amount)
            j.how[name] = where
