"""``kinverify diff`` of two URDFs (through Pinocchio) or two MJCFs (through MuJoCo).

Both files are read as file mode reads them (:mod:`kinverify.filemode.read.loading`: unsafe XML
refused, meshes dropped) and described by their library (:mod:`kinverify.filemode.read.describe_urdf`).
Parameter level: :mod:`kinverify.fileparams` (joint origins, axes, limits, inertias, frames;
names added, removed or renamed), with joints paired by file mode's matching.

Behaviour level: FK and Jacobians of every common frame at the same seeded configurations of the
common joints (inside both files' limits; a joint in one file only is held at 0), and the reach
of each file's deepest frames from its base over its own configurations. The result is a
:class:`~kinverify.modeldiff.ModelDiff`, printed and rendered like a diff of two specs.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from kinverify.errors import InputError, library_reason
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.filemode.read.loading import LoadedFile, load_mjcf, load_urdf
from kinverify.filemode.read.model import ModelDesc
from kinverify.model.transforms import geodesic_distance
from kinverify.pipeline.sampling import sample_configurations
from kinverify.regression.fileparams import pair_names, param_changes
from kinverify.regression.modeldiff import DIFF_SAMPLES, REACH_SAMPLES, FrameChange, ModelDiff, ReachChange

KINDS = {".urdf": "urdf", ".xml": "mjcf", ".mjcf": "mjcf"}
ROOTS = {"robot": "urdf", "mujoco": "mjcf"}
OPEN_RANGE = {"revolute": math.pi, "prismatic": 0.5}  # sampled range of a joint without limits


def file_kind(path: str) -> str | None:
    """``"urdf"``, ``"mjcf"`` or None (a spec or something else): the root element decides for
    XML files, the extension otherwise."""
    from kinverify.io.read import InputFileError, read_head

    p = Path(path)
    if p.suffix.lower() == ".toml":
        return None
    try:
        head = read_head(p, 4096).decode("utf-8", errors="replace")
    except InputFileError as err:
        if err.errno is None:  # a FIFO, a device, a folder: never read
            raise InputError(str(err)) from None
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
        raise InputError(f"{path}: {lib} cannot load the {kind.upper()}: {library_reason(err)}") from None
    return loaded, desc


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
    from kinverify.backends.mujoco_ import MujocoBackend
    from kinverify.backends.pinocchio_ import PinocchioBackend

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
        out.append(
            FrameChange(
                frame,
                float(dp.max()),
                float(dr.max()),
                float(np.linalg.norm(dj[:, :3], axis=(-2, -1)).max()),
                float(np.linalg.norm(dj[:, 3:], axis=(-2, -1)).max()),
                tuple(q[worst].tolist()),
            )
        )
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
    if kinds[0] is None or kinds[1] is None:
        bad = old_path if kinds[0] is None else new_path
        raise InputError(f"{bad}: not a URDF or MJCF; diff compares two specs (.toml), two URDFs or two MJCFs")
    if kinds[0] != kinds[1]:
        urdf, mjcf = (old_path, new_path) if kinds[0] == "urdf" else (new_path, old_path)
        raise InputError(
            f"{old_path} is {'a URDF' if kinds[0] == 'urdf' else 'an MJCF'} and {new_path} "
            f"{'a URDF' if kinds[1] == 'urdf' else 'an MJCF'}: diff compares two files of one kind; "
            f"to compare a URDF with an MJCF run `kinverify verify --urdf {urdf} --mjcf {mjcf}`"
        )
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
