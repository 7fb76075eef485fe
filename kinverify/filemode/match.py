"""Matching the URDF's joints and frames to the MJCF's: by name, by name without the prefix the
file puts on every name (``panda_joint1`` ~ ``joint1``), then by chain order, checked by the axes.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass

import numpy as np

from kinverify.errors import InputError, UnknownNameError
from kinverify.filemode.describe import ModelDesc


@dataclass
class Matching:
    joints: list[tuple[str, str, str]]  # (urdf joint, mjcf joint, how matched), URDF chain order
    unmatched_urdf: list[str]
    unmatched_mjcf: list[str]
    frames: list[tuple[str, str, str]]  # (urdf frame, mjcf frame, why compared), chain order


def _normalise(names) -> dict[str, str]:
    """name -> lowercased alphanumerics without the prefix common to all names (when ≥ 2 names)."""
    names = list(names)
    prefix = os.path.commonprefix(names) if len(names) >= 2 else ""
    out = {}
    for n in names:
        core = n[len(prefix):] if prefix and len(n) > len(prefix) else n
        out[n] = re.sub(r"[^0-9a-z]", "", core.lower()) or n.lower()
    return out


def _by_key(u_names, m_names, key_u, key_m) -> list[tuple[str, str]]:
    m_by_key: dict[str, list[str]] = {}
    for n in m_names:
        m_by_key.setdefault(key_m[n], []).append(n)
    pairs = []
    for n in u_names:
        cands = m_by_key.get(key_u[n], [])
        if len(cands) == 1 and sum(key_u[x] == key_u[n] for x in u_names) == 1:
            pairs.append((n, cands[0]))
    return pairs


def _twist(desc: ModelDesc, name: str) -> float | None:
    """|cos| of the angle between a joint's axis and its parent joint's: base-frame independent."""
    j = desc.joint(name)
    if j.parent is None:
        return None
    return float(abs(np.dot(j.axis, desc.joint(j.parent).axis)))


def match_joints(u: ModelDesc, m: ModelDesc, explicit=()) -> tuple[list[tuple[str, str, str]], list[str], list[str]]:
    u_names, m_names = [j.name for j in u.joints], [j.name for j in m.joints]
    pairs: list[tuple[str, str, str]] = []
    for item in explicit:
        a, sep, b = item.partition("=")
        if not sep or not a or not b:
            raise InputError(f"--joints: expected URDF_JOINT=MJCF_JOINT, got {item!r}")
        if a not in u_names:
            raise UnknownNameError("URDF joint", a, u_names)
        if b not in m_names:
            raise UnknownNameError("MJCF joint", b, m_names)
        pairs.append((a, b, "given"))

    def free(side: int) -> list[str]:
        used = {p[side] for p in pairs}
        return [n for n in (u_names if side == 0 else m_names) if n not in used]

    for a, b in _by_key(free(0), free(1), {n: n for n in u_names}, {n: n for n in m_names}):
        pairs.append((a, b, "name"))
    nu, nm = _normalise(u_names), _normalise(m_names)
    for a, b in _by_key(free(0), free(1), nu, nm):
        pairs.append((a, b, "name without prefix"))
    # Chain order: the remaining joints of each file's main chain, paired in order when the types
    # agree and the angle to the parent axis (independent of the base frame) agrees.
    fu, fm = free(0), free(1)
    for a, b in zip(fu, fm):
        ta, tb = _twist(u, a), _twist(m, b)
        if u.joint(a).type == m.joint(b).type and (ta is None or tb is None or abs(ta - tb) < 1e-3):
            pairs.append((a, b, "chain order and axis"))
        else:
            break
    order = {n: i for i, n in enumerate(u_names)}
    pairs.sort(key=lambda p: order[p[0]])
    return pairs, free(0), free(1)


def match_frames(u: ModelDesc, m: ModelDesc, joints, explicit=()) -> list[tuple[str, str, str]]:
    """Each matched joint's moving frame, then the deepest frame with the same (normalised) name in
    both files (the end effector), plus frames given on the command line."""
    frames = [(u.joint(a).child, m.joint(b).child, f"moves with {a}") for a, b, _ in joints]
    for item in explicit:
        a, sep, b = item.partition("=")
        if not sep or not a or not b:
            raise InputError(f"--frames: expected URDF_FRAME=MJCF_FRAME, got {item!r}")
        if a not in u.frames:
            raise UnknownNameError("URDF frame", a, list(u.frames))
        if b not in m.frames:
            raise UnknownNameError("MJCF frame", b, list(m.frames))
        frames.append((a, b, "given"))
    if not explicit:
        nu, nm = _normalise(u.frames), _normalise(m.frames)
        common = [(a, b) for a, b in _by_key(list(u.frames), list(m.frames), nu, nm)
                  if a not in {f[0] for f in frames} and b not in {f[1] for f in frames}]
        joint_of = {a: b for a, b, _ in joints}
        # only frames that move with a compared joint (or the fixed base) can be compared
        common = [(a, b) for a, b in common
                  if (u.frame_owner[a] is None and m.frame_owner[b] is None) or joint_of.get(u.frame_owner[a]) == m.frame_owner[b]]
        if common:
            a, b = max(common, key=lambda p: (m.frame_depth[p[1]], u.frame_depth[p[0]]))
            if m.frame_owner[b] is not None:
                frames.append((a, b, "deepest common frame (end effector)"))
    return sorted(frames, key=lambda f: u.frame_depth.get(f[0], 0))  # chain order: the base first


def match(u: ModelDesc, m: ModelDesc, joints=(), frames=()) -> Matching:
    if not u.joints:
        raise InputError("the URDF has no movable 1-DOF joints")
    if not m.joints:
        raise InputError("the MJCF has no movable hinge or slide joints")
    pairs, uu, um = match_joints(u, m, joints)
    if not pairs:
        raise InputError(f"no common joints: URDF has {', '.join(j.name for j in u.joints)}; "
                         f"MJCF has {', '.join(j.name for j in m.joints)} (pair them with --joints URDF=MJCF)")
    return Matching(pairs, uu, um, match_frames(u, m, pairs, frames))
