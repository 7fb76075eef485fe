"""Matching the URDF's joints and frames to the MJCF's: by name, by name without the prefix (or
suffix) the file puts on its names (``panda_joint1`` ~ ``joint1``, ``iiwa_joint_1`` ~ ``joint1``),
then by place in the kinematic tree: the joints hanging from one matched joint (or from the base)
are paired by type, by the size of what hangs from them, and by how their axis lines lie to each
other and to their parent's axis (distances between lines and angles between axes: independent of
the base frame, of zero offsets, of where each file puts a joint's origin along its axis and of
sign conventions), which tells the fingers of a hand or the legs of a robot apart; what is left,
by chain order, checked by the angle between consecutive axes. Frames: each joint pair's moving frames, the frames the
first joints hang from, then frames of the same (normalised) name that move with the same joint.
Coupled joints (URDF ``<mimic>``, MJCF ``<equality joint>``) are matched like the others; the
follower of a coupling is computed from its leader, not sampled.
"""

from __future__ import annotations

import itertools
import os
import re
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from kinverify.errors import InputError, UnknownNameError
from kinverify.filemode.align.geometry import line_distance
from kinverify.filemode.read.model import Coupling, ModelDesc


@dataclass
class Matching:
    joints: list[tuple[str, str, str]]  # (urdf joint, mjcf joint, how matched), URDF chain order
    unmatched_urdf: list[str]
    unmatched_mjcf: list[str]
    frames: list[tuple[str, str, str]]  # (urdf frame, mjcf frame, why compared), chain order
    couplings: dict[str, Coupling] = field(default_factory=dict)  # URDF follower -> coupling (URDF names)

    @property
    def independent(self) -> list[str]:
        """The URDF names of the compared joint coordinates: every matched joint but followers."""
        return [a for a, _, _ in self.joints if a not in self.couplings]

    def mjcf_name(self, urdf_joint: str) -> str:
        return next(b for a, b, _ in self.joints if a == urdf_joint)

    def urdf_name(self, mjcf_joint: str) -> str | None:
        return next((a for a, b, _ in self.joints if b == mjcf_joint), None)


def _strip_affix(names: list[str]) -> list[str]:
    """Drop a prefix (or suffix) that most names share, ending (starting) at a separator."""
    if len(names) < 2:
        return names
    out = names
    for reverse in (False, True):
        seq = [n[::-1] for n in out] if reverse else out
        common = os.path.commonprefix(seq)
        cut = max(common.rfind("_"), common.rfind("-"), common.rfind("/"), common.rfind(":")) + 1
        if not cut:  # a prefix most (not all) names share, e.g. iiwa_ on all links but "base"
            heads = Counter(hm[0] for n in seq if (hm := re.match(r"^[^_\-/:]*[_\-/:]", n)))
            head, count = heads.most_common(1)[0] if heads else ("", 0)
            cut = len(head) if count > len(seq) / 2 and count >= 2 else 0
            seq = [n[cut:] if cut and n.startswith(head) and len(n) > cut else n for n in seq]
        else:
            seq = [n[cut:] if len(n) > cut else n for n in seq]
        out = [n[::-1] for n in seq] if reverse else seq
    return out


def _normalise(names) -> dict[str, str]:
    """name -> lowercased alphanumerics without the prefix and suffix most names share."""
    names = list(names)
    return {n: re.sub(r"[^0-9a-z]", "", core.lower()) or n.lower() for n, core in zip(names, _strip_affix(names), strict=True)}


def _numbers(names) -> dict[str, str]:
    """name -> its last number (``iiwa_joint_1`` -> ``1``), or the name when it has none."""
    return {n: (re.findall(r"\d+", n) or [f"~{n}"])[-1].lstrip("0") or "0" for n in names}


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


MAX_PERMUTED = 7  # siblings paired by trying every assignment; above this, greedily


def _descendants(desc: ModelDesc) -> dict[str, int]:
    """Joint -> how many joints hang below it."""
    children: dict[str | None, list[str]] = {}
    for j in desc.joints:
        children.setdefault(j.parent, []).append(j.name)

    def count(name: str) -> int:
        return sum(1 + count(c) for c in children.get(name, []))

    return {j.name: count(j.name) for j in desc.joints}


def _layout(desc: ModelDesc, names: list[str], parent: str | None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """How sibling joints lie: distances between their axis lines, |cos| of the angles between
    their axes, and each one's (distance, |cos|) to its parent's axis (zeros on the base)."""
    js = [desc.joint(n) for n in names]
    n = len(js)
    dist, cos = np.zeros((n, n)), np.zeros((n, n))
    for i, j in itertools.combinations(range(n), 2):
        dist[i, j] = dist[j, i] = line_distance(js[i].anchor, js[i].axis, js[j].anchor, js[j].axis)
        cos[i, j] = cos[j, i] = abs(float(js[i].axis @ js[j].axis))
    to_parent = np.zeros((n, 2))
    if parent is not None:
        p = desc.joint(parent)
        to_parent = np.array([[line_distance(p.anchor, p.axis, j.anchor, j.axis), abs(float(p.axis @ j.axis))] for j in js])
    return dist, cos, to_parent


def _pair_siblings(
    u: ModelDesc, m: ModelDesc, cu: list[str], cm: list[str], parents: tuple, sizes: tuple
) -> list[tuple[str, str]]:
    """The assignment of sibling joints (same matched parent) that best keeps their types, what
    hangs below them and how their axes lie (see the module docstring)."""
    lu, lm = _layout(u, cu, parents[0]), _layout(m, cm, parents[1])
    scale = max(1e-3, float(lu[0].max(initial=0.0)), float(lm[0].max(initial=0.0)))

    def cost(iu: tuple, im: tuple) -> float:
        c = sum(
            1e3 * (u.joint(cu[a]).type != m.joint(cm[b]).type)
            + abs(sizes[0][cu[a]] - sizes[1][cm[b]])
            + abs(lu[2][a, 0] - lm[2][b, 0]) / scale
            + abs(lu[2][a, 1] - lm[2][b, 1])
            for a, b in zip(iu, im, strict=True)
        )
        for (a1, b1), (a2, b2) in itertools.combinations(list(zip(iu, im, strict=True)), 2):
            c += abs(lu[0][a1, a2] - lm[0][b1, b2]) / scale + abs(lu[1][a1, a2] - lm[1][b1, b2])
        return c

    k = min(len(cu), len(cm))
    iu: list[int] | tuple[int, ...]
    im: list[int] | tuple[int, ...]
    if max(len(cu), len(cm)) <= MAX_PERMUTED:
        options = (
            (iu, im) for iu in itertools.combinations(range(len(cu)), k) for im in itertools.permutations(range(len(cm)), k)
        )
        iu, im = min(options, key=lambda o: round(cost(*o), 9))  # a tie (mirror-image fingers) keeps the files' order
    else:  # many siblings: each takes its best remaining partner, in order
        iu, im = [], []
        for a in range(len(cu)):
            rest = [b for b in range(len(cm)) if b not in im]
            if rest:
                iu.append(a)
                im.append(min(rest, key=lambda b: cost(tuple(iu), tuple(im) + (b,))))
    return [(cu[a], cm[b]) for a, b in zip(iu, im, strict=True) if u.joint(cu[a]).type == m.joint(cm[b]).type]


def _by_tree(u: ModelDesc, m: ModelDesc, pairs: list, free_u: list[str], free_m: list[str]) -> list[tuple[str, str]]:
    """Unmatched joints paired by their place in the tree, from the base down (see the module docstring)."""
    sizes = (_descendants(u), _descendants(m))
    matched = {a: b for a, b, _ in pairs}
    free_u, free_m = list(free_u), list(free_m)
    found: list[tuple[str, str]] = []
    queue: list[tuple[str | None, str | None]] = [(None, None)] + [(a, b) for a, b, _ in pairs]
    while queue:
        pu, pm = queue.pop(0)
        cu = [n for n in free_u if u.joint(n).parent == pu]
        cm = [n for n in free_m if m.joint(n).parent == pm]
        if not cu or not cm:
            continue
        for a, b in _pair_siblings(u, m, cu, cm, (pu, pm), sizes):
            found.append((a, b))
            matched[a] = b
            free_u.remove(a)
            free_m.remove(b)
            queue.append((a, b))
    # joints one file hangs under a joint the other lacks (fingers under a gripper slide): paired
    # under their nearest matched ancestors, when each lies on that ancestor's axis as its twin
    # does (on the base nothing says how a joint lies before the alignment: left unpaired)
    for pu, pm in list(matched.items()):
        cu = [n for n in free_u if _matched_ancestor(u, n, matched) == pu]
        cm = [n for n in free_m if _matched_ancestor(m, n, set(matched.values())) == pm]
        if not cu or not cm or (all(u.joint(n).parent == pu for n in cu) and all(m.joint(n).parent == pm for n in cm)):
            continue
        for a in cu:  # the twin lies on the ancestor's axis alike; mirror images: the closer name
            alike = [b for b in cm if b in free_m and u.joint(a).type == m.joint(b).type and _lies_alike(u, m, a, b, pu, pm)]
            if alike:
                b = max(alike, key=lambda x: len(os.path.commonprefix([a, x])))
                found.append((a, b))
                free_u.remove(a)
                free_m.remove(b)
    return found


def _matched_ancestor(desc: ModelDesc, name: str, matched) -> str | None:
    """The nearest ancestor joint of ``name`` that is matched (None: the base)."""
    parent = desc.joint(name).parent
    while parent is not None and parent not in matched:
        parent = desc.joint(parent).parent
    return parent


def _lies_alike(u: ModelDesc, m: ModelDesc, a: str, b: str, pu: str, pm: str) -> bool:
    """Whether two joints lie on their matched ancestors' axes alike: the distance between the
    axis lines within 1 mm, the angle's cosine within 1e-3."""
    (_, _, tu), (_, _, tm) = _layout(u, [a], pu), _layout(m, [b], pm)
    return abs(tu[0, 0] - tm[0, 0]) <= 1e-3 and abs(tu[0, 1] - tm[0, 1]) <= 1e-3


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
    for a, b in _by_key(free(0), free(1), _numbers(u_names), _numbers(m_names)):
        pairs.append((a, b, "number in the name"))
    for a, b in _by_tree(u, m, pairs, free(0), free(1)):
        pairs.append((a, b, "place in the tree"))
    # Chain order: what is left of each file's main chain, paired in order when the types agree
    # and the angle to the parent axis (independent of the base frame) agrees.
    fu, fm = free(0), free(1)
    for a, b in zip(fu, fm, strict=False):
        ta, tb = _twist(u, a), _twist(m, b)
        if u.joint(a).type == m.joint(b).type and (ta is None or tb is None or abs(ta - tb) < 1e-3):
            pairs.append((a, b, "chain order and axis"))
        else:
            break
    order = {n: i for i, n in enumerate(u_names)}
    pairs.sort(key=lambda p: order[p[0]])
    return pairs, free(0), free(1)


def resolve_couplings(couplings, order: list[str], followers=frozenset()) -> dict[str, Coupling]:
    """Each coupled joint as ``joint = k·root + c`` of the first joint of its group in ``order``
    that is not in ``followers`` (the URDF's mimic joints, which its readers do not take as
    inputs), else the first (couplings are linear relations between two joints, so a group of
    them, a chain ``a = k·b``, ``b = l·c`` or two followers of one leader, ties every member to
    one joint)."""
    rank = {n: i for i, n in enumerate(order)}
    edges: dict[str, list[tuple[str, float, float, Coupling]]] = {}
    held = []
    for c in couplings:
        if c.follower not in rank or c.leader not in rank:
            continue
        if not c.multiplier:  # f = 0·l + o: held at its offset, it ties no joint to another
            held.append(c)
            continue
        edges.setdefault(c.follower, []).append((c.leader, c.multiplier, c.offset, c))  # f = k·l + o
        edges.setdefault(c.leader, []).append((c.follower, 1 / c.multiplier, -c.offset / c.multiplier, c))
    out: dict[str, Coupling] = {c.follower: Coupling(c.follower, c.leader, 0.0, c.offset, c.source, c.nonlinear) for c in held}
    seen: set[str] = set()
    for start in sorted(edges, key=rank.__getitem__):
        if start in seen:
            continue
        group, todo = {start}, [start]
        while todo:
            for other, *_ in edges.get(todo.pop(), []):
                if other not in group:
                    group.add(other)
                    todo.append(other)
        root = min(group, key=lambda j: (j in followers, rank[j]))
        seen |= group
        value: dict[str, tuple[float, float, Coupling | None]]
        value, todo = {root: (1.0, 0.0, None)}, [root]  # joint -> (k, c, a coupling on the way) with joint = k·root + c
        while todo:
            j = todo.pop()
            kj, cj, _ = value[j]
            for other, k, o, c in edges.get(j, []):  # j = k·other + o  =>  other = (j − o) / k
                if other not in value and k:
                    value[other] = (kj / k, (cj - o) / k, c)
                    todo.append(other)
        for j, (k, c, via) in value.items():
            if j != root and j not in out:
                assert via is not None  # reached through a coupling
                source = next((x.source for x in couplings if x.follower == j), via.source)
                nonlinear = any(x.nonlinear for x in couplings if j in (x.follower, x.leader))
                out[j] = Coupling(j, root, k, c, source, nonlinear)
    return out


def match_couplings(u: ModelDesc, m: ModelDesc, joints) -> dict[str, Coupling]:
    """URDF follower -> the coupling the comparison uses (URDF names, each follower in terms of the
    first joint of its group, :func:`resolve_couplings`): the URDF's own, then the MJCF's mapped to
    URDF names for the joints the URDF leaves free."""
    to_u = {b: a for a, b, _ in joints}
    order = [a for a, _, _ in joints]
    mine = [c for c in u.couplings if c.follower in to_u.values() and c.leader in to_u.values()]
    theirs = [
        Coupling(to_u[c.follower], to_u[c.leader], c.multiplier, c.offset, c.source, c.nonlinear)
        for c in m.couplings
        if c.follower in to_u and c.leader in to_u
    ]
    coupled = {x for c in mine for x in (c.follower, c.leader)}
    return resolve_couplings(
        mine + [c for c in theirs if c.follower not in coupled and c.leader not in coupled], order, {c.follower for c in mine}
    )


def match_frames(u: ModelDesc, m: ModelDesc, joints, explicit=()) -> list[tuple[str, str, str]]:
    """Each matched joint's moving frame, the frames the first matched joints hang from (on the
    base in both files; a frame whose name the other file gives to another frame waits for its
    namesake), then
    frames with the same (normalised) name in both files that move with the same joint, plus frames
    given on the command line."""
    frames = [(u.joint(a).child, m.joint(b).child, f"moves with {a}") for a, b, _ in joints]
    used_u, used_m = {f[0] for f in frames}, {f[1] for f in frames}
    for a, b, _ in joints:  # on the base in both files, and not a frame the other file names otherwise
        pu, pm = u.joint(a).parent_frame, m.joint(b).parent_frame
        if (
            u.joint(a).parent is None
            and m.joint(b).parent is None
            and pu in u.frames
            and pm in m.frames
            and pu not in used_u
            and pm not in used_m
            and (pu == pm or (pu not in m.frames and pm not in u.frames))
        ):
            frames.append((pu, pm, f"{a} hangs from it"))
            used_u.add(pu)
            used_m.add(pm)
    for item in explicit:
        a, sep, b = item.partition("=")
        if not sep or not a or not b:
            raise InputError(f"--frames: expected URDF_FRAME=MJCF_FRAME, got {item!r}")
        if a not in u.frames:
            raise UnknownNameError("URDF frame", a, list(u.frames))
        if b not in m.frames:
            raise UnknownNameError("MJCF frame", b, list(m.frames))
        frames.append((a, b, "given"))
        used_u.add(a)
        used_m.add(b)
    joint_of = {a: b for a, b, _ in joints}
    nu, nm = _normalise(u.frames), _normalise(m.frames)
    for how, keys in (("same name", ({n: n for n in u.frames}, {n: n for n in m.frames})), ("similar name", (nu, nm))):
        free_u = [f for f in u.frames if f not in used_u]
        free_m = [f for f in m.frames if f not in used_m]
        for a, b in _by_key(free_u, free_m, *keys):
            owner_u, owner_m = u.frame_owner[a], m.frame_owner[b]
            if (owner_u is None and owner_m is None) or (owner_u is not None and joint_of.get(owner_u) == owner_m):
                frames.append((a, b, how))
                used_u.add(a)
                used_m.add(b)
    return sorted(frames, key=lambda f: u.frame_depth.get(f[0], 0))  # chain order: the base first


def match(u: ModelDesc, m: ModelDesc, joints=(), frames=()) -> Matching:
    if not u.joints:
        raise InputError("the URDF has no movable 1-DOF joints")
    if not m.joints:
        raise InputError("the MJCF has no movable hinge or slide joints")
    pairs, uu, um = match_joints(u, m, joints)
    if not pairs:
        raise InputError(
            f"no common joints: URDF has {', '.join(j.name for j in u.joints)}; "
            f"MJCF has {', '.join(j.name for j in m.joints)} (pair them with --joints URDF=MJCF)"
        )
    return Matching(pairs, uu, um, match_frames(u, m, pairs, frames), match_couplings(u, m, pairs))
