"""Parameter-level differences between two model files (URDF or MJCF), for ``kinverify diff``.

Each file is described by :mod:`kinverify.filemode.read.describe_urdf`. Joints are paired as file mode
pairs a URDF with an MJCF (:func:`kinverify.filemode.align.match.match_joints`: by name, by name without a prefix common to every name, then by chain order where the joint type
and the angle to the parent axis agree), so a re-export that renamed joints is still compared;
frames are paired by name, then as the child frames of paired joints, then by the prefix change
the renamed joints share (``panda_link0`` ~ ``link0``). A pair whose names differ is reported as a
rename.

Parameter level, everything at q = 0 and relative to the parent, so one edited number shows as
one change and not as every frame downstream of it:

- ``joint J``: ``origin.xyz`` [m] and ``origin.rotation`` (rpy, Δ = rotation angle [rad]) of the
  child frame in the parent frame (a URDF joint origin; an MJCF body pos/quat), ``axis`` and
  ``anchor`` [m] in the child frame, ``type``, limits, effort, velocity, damping, friction,
  armature;
- ``frame F`` (frames that are not a joint's child: fixed links, tools, sites): pose in the frame
  of the joint it moves with (the base: the world);
- ``inertia moving with J`` (``base``: the fixed part): total ``mass`` [kg], ``com`` [m] and
  ``inertia`` about the CoM ``[ixx, iyy, izz, ixy, ixz, iyz]`` [kg·m²] in J's child frame, of
  every body moving with J (MJCF bodies welded to one another count as one);
- joints and frames present in only one file: ``added`` / ``removed``; renamed: ``name``.
"""

from __future__ import annotations

import math

import numpy as np

from kinverify.filemode.align.match import match_joints
from kinverify.filemode.read.model import ModelDesc
from kinverify.model.transforms import geodesic_distance, invert_transform, matrix_to_rpy
from kinverify.regression.specdiff import ATOL, ParamChange


def _number(v) -> bool:
    if isinstance(v, tuple):
        return all(_number(x) for x in v)
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _change(out: list[ParamChange], where: str, field: str, old, new) -> None:
    """Append a change when ``old`` and ``new`` differ (numbers: by more than ATOL; an infinite
    limit that became finite, or the reverse, is a change of size inf)."""
    if _number(old) and _number(new):
        a, b = np.atleast_1d(np.asarray(old, float)), np.atleast_1d(np.asarray(new, float))
        if a.shape == b.shape:
            both = np.isfinite(a) & np.isfinite(b)
            if not np.array_equal(a[~both], b[~both]):
                out.append(ParamChange(where, field, "changed", old, new, math.inf))
                return
            delta = float(np.linalg.norm(a[both] - b[both]))
            if delta > ATOL:
                out.append(ParamChange(where, field, "changed", old, new, delta))
            return
    if old != new:
        out.append(ParamChange(where, field, "changed", old, new))


def _tuple(v) -> tuple[float, ...]:
    return tuple(float(x) for x in np.ravel(v))


def _relative(desc: ModelDesc, frame: str, parent: str | None) -> np.ndarray:
    """Pose of ``frame`` in ``parent`` (the world when None) at q = 0."""
    t = desc.frames[frame]
    return t if parent is None or parent not in desc.frames else invert_transform(desc.frames[parent]) @ t


def _pose_changes(out, where: str, old: np.ndarray, new: np.ndarray) -> None:
    _change(out, where, "origin.xyz", _tuple(old[:3, 3]), _tuple(new[:3, 3]))
    angle = float(geodesic_distance(old[None, :3, :3], new[None, :3, :3])[0])
    if angle > ATOL:
        out.append(
            ParamChange(
                where, "origin.rotation", "changed", _tuple(matrix_to_rpy(old[:3, :3])), _tuple(matrix_to_rpy(new[:3, :3])), angle
            )
        )


def pair_names(old: ModelDesc, new: ModelDesc) -> tuple[list[tuple[str, str]], list[tuple[str, str]]]:
    """Joint pairs (file mode's matching: by name, by name without a common prefix, then by chain
    order where type and twist agree) and frame pairs (by name, then each joint pair's child
    frames), both in the old file's order."""
    joints = [(a, b) for a, b, _ in match_joints(old, new)[0]] if old.joints and new.joints else []
    frames = [(f, f) for f in old.frames if f in new.frames]
    paired_old, paired_new = {f for f, _ in frames}, {f for _, f in frames}
    for a, b in joints:
        ca, cb = old.joint(a).child, new.joint(b).child
        if ca not in paired_old and cb not in paired_new:
            frames.append((ca, cb))
            paired_old.add(ca)
            paired_new.add(cb)
    old_prefix, new_prefix = _rename_prefixes(joints)
    for f in old.frames:  # remaining frames: the prefix change the joints had
        if f not in paired_old and f.startswith(old_prefix):
            other = new_prefix + f[len(old_prefix) :]
            if other in new.frames and other not in paired_new:
                frames.append((f, other))
                paired_new.add(other)
    order = {f: i for i, f in enumerate(old.frames)}
    return joints, sorted(frames, key=lambda p: order[p[0]])


def _rename_prefixes(joints) -> tuple[str, str]:
    """``(old, new)`` when every renamed joint pair differs only by a leading prefix, e.g.
    ``panda_joint1 -> joint1`` gives ``("panda_", "")``; ``("", "")`` otherwise."""
    found = set()
    for a, b in joints:
        if a == b:
            continue
        if a.endswith(b):
            found.add((a[: len(a) - len(b)], ""))
        elif b.endswith(a):
            found.add(("", b[: len(b) - len(a)]))
        else:
            return "", ""
    return found.pop() if len(found) == 1 else ("", "")


def _renames(out, kind: str, pairs, old_names, new_names) -> None:
    """Names added, removed or renamed (a pair whose names differ)."""
    paired_old, paired_new = {a for a, _ in pairs}, {b for _, b in pairs}
    out += [ParamChange(f"{kind} {a}", "name", "changed", a, b) for a, b in pairs if a != b]
    out += [ParamChange(f"{kind} {n}", "name", "removed", n, None) for n in old_names if n not in paired_old]
    out += [ParamChange(f"{kind} {n}", "name", "added", None, n) for n in new_names if n not in paired_new]


def _joint_frame(desc: ModelDesc, joint: str | None) -> str | None:
    return None if joint is None else desc.joint(joint).child


def _inertias(desc: ModelDesc) -> dict[str | None, tuple[float, tuple, tuple]]:
    """owner joint -> (mass, CoM, inertia about the CoM) of its bodies, in the owner's child frame."""
    out = {}
    for owner in dict.fromkeys(b.owner for b in desc.bodies):
        bodies = [b for b in desc.bodies if b.owner == owner]
        mass = sum(b.mass for b in bodies)
        com = sum(b.mass * b.com for b in bodies) / mass
        inertia = sum(b.inertia + b.mass * ((d @ d) * np.eye(3) - np.outer(d, d)) for b in bodies for d in [b.com - com])
        frame = _joint_frame(desc, owner)
        t = np.eye(4) if frame is None else desc.frames[frame]
        r = t[:3, :3]
        local = r.T @ inertia @ r
        out[owner] = (
            mass,
            _tuple(r.T @ (com - t[:3, 3])),
            _tuple([local[0, 0], local[1, 1], local[2, 2], local[0, 1], local[0, 2], local[1, 2]]),
        )
    return out


def param_changes(old: ModelDesc, new: ModelDesc, joints=None, frames=None) -> list[ParamChange]:
    """Every parameter that differs, base to tip (see the module docstring); ``joints`` and
    ``frames``: (old name, new name) pairs, default :func:`pair_names`."""
    if joints is None or frames is None:
        joints, frames = pair_names(old, new)
    out: list[ParamChange] = []
    _renames(out, "joint", joints, [j.name for j in old.joints], [j.name for j in new.joints])
    for name, other in joints:
        a, b = old.joint(name), new.joint(other)
        where = f"joint {name}"
        _change(out, where, "type", a.type, b.type)
        _pose_changes(out, where, _relative(old, a.child, a.parent_frame), _relative(new, b.child, b.parent_frame))
        ra, rb = old.frames[a.child], new.frames[b.child]
        _change(out, where, "axis", _tuple(ra[:3, :3].T @ a.axis), _tuple(rb[:3, :3].T @ b.axis))
        _change(
            out, where, "anchor", _tuple(ra[:3, :3].T @ (a.anchor - ra[:3, 3])), _tuple(rb[:3, :3].T @ (b.anchor - rb[:3, 3]))
        )
        for attr in ("lower", "upper", "effort", "velocity", "damping", "friction", "armature"):
            x, y = getattr(a, attr), getattr(b, attr)
            field = f"limits.{attr}" if attr in ("lower", "upper", "effort", "velocity") else attr
            _change(out, where, field, None if x is None else float(x), None if y is None else float(y))
    _renames(out, "frame", frames, list(old.frames), list(new.frames))
    joint_map = dict(joints)
    children_old = {j.child for j in old.joints}
    for name, other in frames:
        if name in children_old:  # its origin is its joint's
            continue
        oa, ob = old.frame_owner.get(name), new.frame_owner.get(other)
        if oa is not None and joint_map.get(oa) != ob:
            out.append(ParamChange(f"frame {name}", "moves with", "changed", oa, ob or "base"))
        elif (oa is None) != (ob is None):
            out.append(ParamChange(f"frame {name}", "moves with", "changed", "base", ob))
        else:
            _pose_changes(
                out, f"frame {name}", _relative(old, name, _joint_frame(old, oa)), _relative(new, other, _joint_frame(new, ob))
            )
    io, inew = _inertias(old), _inertias(new)
    mapped = {owner: (joint_map.get(owner) if owner is not None else None) for owner in io}
    for owner in io:
        where = f"inertia moving with {owner or 'base'}"
        if owner is not None and owner not in joint_map:
            continue  # the joint was removed: reported above
        if mapped[owner] not in inew:
            out.append(ParamChange(where, "mass", "changed", io[owner][0], 0.0, io[owner][0]))
            continue
        for k, field in enumerate(("mass", "com", "inertia")):
            _change(out, where, field, io[owner][k], inew[mapped[owner]][k])
    for owner in inew:
        if owner not in mapped.values() and (owner is None or owner in joint_map.values()):
            out.append(
                ParamChange(f"inertia moving with {owner or 'base'}", "mass", "changed", 0.0, inew[owner][0], inew[owner][0])
            )
    return out
