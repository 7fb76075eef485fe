"""``kinverify diff`` of two URDFs (through Pinocchio) or two MJCFs (through MuJoCo).

Both files are read as file mode reads them (:mod:`kinverify.filemode.loading`: unsafe XML
refused, meshes dropped) and described by their library (:mod:`kinverify.filemode.describe`).
Joints are paired as file mode pairs a URDF with an MJCF (:func:`kinverify.filemode.match.match_joints`:
by name, by name without a prefix common to every name, then by chain order where the joint type
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

Behaviour level: FK and Jacobians of every common frame at the same seeded configurations of the
common joints (inside both files' limits; a joint in one file only is held at 0), and the reach
of each file's deepest frames from its base over its own configurations. The result is a
:class:`~kinverify.modeldiff.ModelDiff`, printed and rendered like a diff of two specs.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .errors import InputError
from .filemode.describe import ModelDesc, describe_mjcf, describe_urdf
from .filemode.loading import LoadedFile, load_mjcf, load_urdf
from .filemode.match import match_joints
from .modeldiff import DIFF_SAMPLES, REACH_SAMPLES, FrameChange, ModelDiff, ReachChange
from .sampling import sample_configurations
from .specdiff import ATOL, ParamChange
from .transforms import geodesic_distance, invert_transform, matrix_to_rpy

KINDS = {".urdf": "urdf", ".xml": "mjcf", ".mjcf": "mjcf"}
ROOTS = {"robot": "urdf", "mujoco": "mjcf"}
OPEN_RANGE = {"revolute": math.pi, "prismatic": 0.5}  # sampled range of a joint without limits


def file_kind(path: str) -> str | None:
    """``"urdf"``, ``"mjcf"`` or None (a spec or something else): the root element decides for
    XML files, the extension otherwise."""
    p = Path(path)
    if p.suffix.lower() == ".toml":
        return None
    try:
        head = p.read_text(encoding="utf-8", errors="replace")[:4096]
    except OSError:
        return KINDS.get(p.suffix.lower())
    for root, kind in ROOTS.items():
        if f"<{root}" in head:
            return kind
    return KINDS.get(p.suffix.lower())


def _load(path: str, kind: str) -> tuple[LoadedFile, ModelDesc]:
    try:
        loaded = load_urdf(path) if kind == "urdf" else load_mjcf(path)
    except InputError as err:
        raise InputError(str(err).removeprefix(f"--{kind}: ")) from None
    try:
        desc = describe_urdf(loaded.text) if kind == "urdf" else describe_mjcf(loaded.text)
    except (ValueError, RuntimeError) as err:
        lib = "Pinocchio" if kind == "urdf" else "MuJoCo"
        raise InputError(f"{path}: {lib} cannot load the {kind.upper()}: {str(err).strip().splitlines()[-1]}") from None
    return loaded, desc


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
        out.append(ParamChange(where, "origin.rotation", "changed", _tuple(matrix_to_rpy(old[:3, :3])),
                               _tuple(matrix_to_rpy(new[:3, :3])), angle))


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
            other = new_prefix + f[len(old_prefix):]
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
        out[owner] = (mass, _tuple(r.T @ (com - t[:3, 3])),
                      _tuple([local[0, 0], local[1, 1], local[2, 2], local[0, 1], local[0, 2], local[1, 2]]))
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
        _change(out, where, "anchor", _tuple(ra[:3, :3].T @ (a.anchor - ra[:3, 3])), _tuple(rb[:3, :3].T @ (b.anchor - rb[:3, 3])))
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
            _pose_changes(out, f"frame {name}", _relative(old, name, _joint_frame(old, oa)),
                          _relative(new, other, _joint_frame(new, ob)))
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
            out.append(ParamChange(f"inertia moving with {owner or 'base'}", "mass", "changed", 0.0, inew[owner][0], inew[owner][0]))
    return out


def _limits(old: ModelDesc, new: ModelDesc, joints: list[tuple[str, str]]):
    """Sampling ranges of paired joints: inside both files' limits (disjoint: the old file's)."""
    lower, upper, revolute = [], [], []
    for name, other in joints:
        a, b = old.joint(name), new.joint(other)
        lo, up = max(a.lower, b.lower), min(a.upper, b.upper)
        if not lo < up:
            lo, up = a.lower, a.upper
        span = OPEN_RANGE[a.type]
        lower.append(lo if math.isfinite(lo) else -span)
        upper.append(up if math.isfinite(up) else span)
        revolute.append(a.type == "revolute")
    return lower, upper, revolute


def _backend(loaded: LoadedFile, joints, frames):
    from .backends.mujoco_ import MujocoBackend
    from .backends.pinocchio_ import PinocchioBackend

    if loaded.kind == "urdf":
        return PinocchioBackend.from_urdf(loaded.text, joints, frames, name="pinocchio-urdf")
    return MujocoBackend.from_mjcf(loaded.text, joints, frames, name="mujoco")


def frame_changes(old_file: LoadedFile, new_file: LoadedFile, joints, frames, q) -> list[FrameChange]:
    """Per frame pair, the largest FK and Jacobian change at configurations ``q`` of the joint
    pairs (named as in the old file)."""
    eo = _backend(old_file, [a for a, _ in joints], [a for a, _ in frames]).evaluate(q)
    en = _backend(new_file, [b for _, b in joints], [b for _, b in frames]).evaluate(q)
    out = []
    for f, (frame, _) in enumerate(frames):
        dp = np.linalg.norm(en.poses[:, f, :3, 3] - eo.poses[:, f, :3, 3], axis=-1)
        dr = geodesic_distance(eo.poses[:, f, :3, :3], en.poses[:, f, :3, :3])
        dj = en.jacobians[:, f] - eo.jacobians[:, f]
        worst = int(np.argmax(dp)) if dp.max() > 0 else int(np.argmax(dr))
        out.append(FrameChange(frame, float(dp.max()), float(dr.max()),
                               float(np.linalg.norm(dj[:, :3], axis=(-2, -1)).max()),
                               float(np.linalg.norm(dj[:, 3:], axis=(-2, -1)).max()), tuple(q[worst].tolist())))
    return out


def reach(loaded: LoadedFile, desc: ModelDesc, samples: int = REACH_SAMPLES, seed: int = 0) -> dict[str, float]:
    """Largest distance [m] of the file's deepest moving frames from its base (the shallowest
    fixed frame; the world origin if none) over its own seeded configurations."""
    moving = [f for f in desc.frames if desc.frame_owner.get(f) is not None]
    if not moving or not desc.joints:
        return {}
    deepest = max(desc.frame_depth[f] for f in moving)
    ends = [f for f in moving if desc.frame_depth[f] == deepest]
    fixed = [f for f in desc.frames if desc.frame_owner.get(f) is None]
    base = desc.frames[min(fixed, key=lambda f: desc.frame_depth[f])][:3, 3] if fixed else np.zeros(3)
    names = [j.name for j in desc.joints]
    lower, upper, revolute = _limits(desc, desc, [(n, n) for n in names])
    q = sample_configurations(lower, upper, revolute, samples, seed)
    poses = _backend(loaded, names, ends).evaluate(q, with_jacobians=False).poses
    return {f: float(np.max(np.linalg.norm(poses[:, i, :3, 3] - base, axis=-1))) for i, f in enumerate(ends)}


def diff_files(old_path: str, new_path: str, samples: int = DIFF_SAMPLES, seed: int = 0) -> ModelDiff:
    """Parameter- and behaviour-level differences from the file ``old_path`` to ``new_path``
    (two URDFs or two MJCFs; anything else: :class:`InputError`)."""
    kinds = file_kind(old_path), file_kind(new_path)
    if None in kinds:
        bad = old_path if kinds[0] is None else new_path
        raise InputError(f"{bad}: not a URDF or MJCF; diff compares two specs (.toml), two URDFs or two MJCFs")
    if kinds[0] != kinds[1]:
        urdf, mjcf = (old_path, new_path) if kinds[0] == "urdf" else (new_path, old_path)
        raise InputError(f"{old_path} is {'a URDF' if kinds[0] == 'urdf' else 'an MJCF'} and {new_path} "
                         f"{'a URDF' if kinds[1] == 'urdf' else 'an MJCF'}: diff compares two files of one kind; "
                         f"to compare a URDF with an MJCF run `kinverify verify --urdf {urdf} --mjcf {mjcf}`")
    if samples < 0:
        raise InputError(f"--samples must be >= 0, got {samples}")
    (lo, old), (ln, new) = _load(old_path, kinds[0]), _load(new_path, kinds[1])
    joints, frames = pair_names(old, new)
    result = ModelDiff(lo.name, ln.name, param_changes(old, new, joints, frames))
    result.notes += [f"{path}: {w}" for path, f in ((old_path, lo), (new_path, ln)) for w in f.warnings]
    result.notes += [f"{path}: {s}" for path, d in ((old_path, old), (new_path, new)) for s in d.skipped]
    renamed = [f"{a} -> {b}" for a, b in joints if a != b]
    if renamed:
        result.notes.append(f"joints paired by file mode's matching although renamed: {', '.join(renamed)}")
    only = [j.name for j in old.joints if j.name not in dict(joints)]
    only += [j.name for j in new.joints if j.name not in {b for _, b in joints}]
    if only:
        result.notes.append(f"joints in one file only, held at 0: {', '.join(only)}")
    if joints and frames:
        lower, upper, revolute = _limits(old, new, joints)
        q = sample_configurations(lower, upper, revolute, samples, seed)
        result.samples = len(q)
        result.frames = frame_changes(lo, ln, joints, frames, q)
        if any((old.joint(a).lower, old.joint(a).upper) != (new.joint(b).lower, new.joint(b).upper) for a, b in joints):
            result.notes.append("joint limits changed: FK and Jacobians are compared inside both files' limits")
    else:
        result.notes.append("no common joints or frames: FK and Jacobians not compared")
    ro, rn = reach(lo, old), reach(ln, new)
    result.reach = [ReachChange(f, ro.get(f), rn.get(f)) for f in dict.fromkeys([*ro, *rn])]
    return result
