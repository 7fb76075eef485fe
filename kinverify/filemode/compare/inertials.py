"""Mass, centre of mass and inertia of each rigid body, compared in one frame.

A rigid body ("group") is everything that moves with one matched joint, or with the base:
links joined by fixed joints are merged, and the bodies of a joint present in one file only are
included, held at zero. Each group's mass, centre of mass and inertia tensor about the centre of
mass are expressed in the URDF's world at the aligned zero configuration (the MJCF's through the
alignment), so a file's choice of link frame is not a difference, while a swapped or rotated
inertia is: tensors are compared by their difference (its largest eigenvalue, frame-free) and
described by their principal moments and axes.

Bodies with no twin in the other file (no frame of the same role) explain a difference when the
groups agree without them: a gripper in one file only, rotor masses the other file lacks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from kinverify.filemode.compare.context import aligned_poses
from kinverify.filemode.read.model import BodyInertial, ModelDesc
from kinverify.model.transforms import geodesic_distance

ROOT = "(base)"


@dataclass
class Inertial:
    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))


def combine(parts: list[tuple[float, np.ndarray, np.ndarray]]) -> Inertial:
    """Mass, CoM and inertia about the CoM of rigidly joined parts (mass, com, inertia about com)."""
    mass = float(sum(p[0] for p in parts))
    if mass <= 0:
        return Inertial()
    com = np.asarray(sum(p[0] * p[1] for p in parts)) / mass
    inertia = np.zeros((3, 3))
    for m, c, i in parts:
        r = c - com
        inertia += i + m * (np.dot(r, r) * np.eye(3) - np.outer(r, r))
    return Inertial(mass, com, inertia)


@dataclass
class Part:
    """One body of a file placed in the common frame."""

    name: str
    mass: float
    com: np.ndarray
    inertia: np.ndarray
    twin: str | None  # the other file's body in the same role, None when it has none
    snapped: float = 0.0  # MuJoCo dropped this rotation of its principal axes [rad] (see describe)
    known: bool = True  # False: part of its mass came from a mesh file that is absent
    com_known: bool = True  # False: its mass is known, not its centre of mass and inertia (an absent mesh)
    moved_by: str | None = None  # the joint in this file only that moves it (held at zero here)
    snapped_com: float = 0.0  # MuJoCo put its centre of mass this far [m] from where the file states it (see describe)
    unset_twin: str | None = None  # the other file's link in the same role, which states no inertial


@dataclass
class Group:
    key: str  # URDF name of the joint it moves with, or ROOT
    urdf_link: str  # the URDF link / MJCF body that names it
    mjcf_link: str
    urdf: list[Part]
    mjcf: list[Part]
    fixed_base_root: bool  # welded to the world of a fixed-base robot: no effect on its motion
    seated: tuple[float, float] = (0.0, 0.0)  # (rad, m) of the carry its MJCF parts were compared after (see carry_to_joints)

    def total(self, side: str, leave_out=()) -> Inertial:
        parts = self.urdf if side == "urdf" else self.mjcf
        return combine([(p.mass, p.com, p.inertia) for p in parts if not any(p is x for x in leave_out)])

    def twinless(self, side: str) -> list[Part]:
        return [p for p in (self.urdf if side == "urdf" else self.mjcf) if p.twin is None and p.mass > 0]


@dataclass(frozen=True)
class Difference:
    """How two inertials differ: |Δm| [kg], |Δcom| [m], ‖ΔI‖₂ [kg·m²]."""

    mass: float
    com: float
    tensor: float

    def within(self, mass_tol: float, com_tol: float, tensor_tol: float) -> bool:
        return self.mass <= mass_tol and self.com <= com_tol and self.tensor <= tensor_tol


def difference(a: Inertial, b: Inertial) -> Difference:
    com = float(np.linalg.norm(a.com - b.com)) if a.mass > 0 and b.mass > 0 else 0.0
    tensor = float(np.abs(np.linalg.eigvalsh(a.inertia - b.inertia)).max())
    return Difference(abs(a.mass - b.mass), com, tensor)


def _owner_key(desc: ModelDesc, owner: str | None, to_key: dict) -> str:
    """The group a body belongs to: its joint's, or the nearest matched ancestor's (a joint in
    one file only is held at zero), or the base."""
    parent = {j.name: j.parent for j in desc.joints}
    while owner is not None and owner not in to_key:
        owner = parent.get(owner)
    return ROOT if owner is None else to_key[owner]


def _moved_by(desc: ModelDesc, owner: str | None, to_key: dict) -> str | None:
    """The joint in this file only that moves a body (the nearest such ancestor), if any."""
    parent = {j.name: j.parent for j in desc.joints}
    while owner is not None and owner not in to_key:
        if desc.has_joint(owner) and owner not in desc.held:
            return owner
        owner = parent.get(owner)
    return None


def _base_body(desc: ModelDesc) -> str | None:
    """The body nearest the root that moves with no joint and has mass (the base link or body)."""
    massive = [b.name for b in desc.bodies if b.owner is None and b.mass > 0 and b.name in desc.frame_depth]
    return min(massive, key=lambda n: desc.frame_depth[n], default=None)


def groups(u: ModelDesc, m: ModelDesc, joint_pairs, frame_pairs, poses_u: dict, poses_m: dict, floating: bool) -> list[Group]:
    """The rigid bodies of both files, paired. ``poses_u``/``poses_m``: body frame name -> pose at
    the aligned zero in the URDF's world (the MJCF's already brought through the alignment)."""
    key_u = {a: a for a, _ in joint_pairs}
    key_m = {b: a for a, b in joint_pairs}
    twin_u = {fu: fm for fu, fm in frame_pairs}
    twin_m = {fm: fu for fu, fm in frame_pairs}
    out: dict[str, Group] = {}
    root = next(
        ((fu, fm) for fu, fm in frame_pairs if u.frame_owner.get(fu) is None and m.frame_owner.get(fm) is None), (ROOT, ROOT)
    )
    both = sorted(
        (u.frame_depth.get(f, 0), f)
        for f in u.frames
        if u.frame_owner.get(f) is None
        and f in m.frames
        and m.frame_owner.get(f) is None
        and (u.body(f) is not None or m.body(f) is not None)
    )
    # the base is named after its body (the same name in both files, else the massive body nearest
    # the root), not after a frame on it that a first joint happens to hang from
    root = (both[0][1], both[0][1]) if both else (_base_body(u) or root[0], _base_body(m) or root[1])
    for a, b in [(ROOT, ROOT)] + list(joint_pairs):
        link_u = root[0] if a == ROOT else u.joint(a).child
        link_m = root[1] if b == ROOT else m.joint(b).child
        out[a] = Group(a, link_u, link_m, [], [], a == ROOT and not floating)

    def place(body: BodyInertial, pose: np.ndarray | None) -> tuple[np.ndarray, np.ndarray]:
        if pose is None:
            return body.com, body.inertia
        rot = pose[:3, :3]
        return rot @ body.com_local + pose[:3, 3], rot @ body.inertia_local @ rot.T

    def same_body(bu: BodyInertial, bm: BodyInertial | None) -> bool:
        """Twin frames are one body when they move with the same matched joint and no joint in
        one file only moves either."""
        return (
            bm is not None
            and _owner_key(u, bu.owner, key_u) == _owner_key(m, bm.owner, key_m)
            and _moved_by(u, bu.owner, key_u) is None
            and _moved_by(m, bm.owner, key_m) is None
        )

    for body in u.bodies:
        com, inertia = place(body, poses_u.get(body.name))
        twin = twin_u.get(body.name)
        silent = twin if twin is not None and m.body(twin) is None and twin in m.no_inertial else None
        twin = twin if twin is not None and same_body(body, m.body(twin)) else None
        out[_owner_key(u, body.owner, key_u)].urdf.append(
            Part(
                body.name,
                body.mass,
                com,
                inertia,
                twin,
                known=body.mass_known,
                unset_twin=silent,
                moved_by=_moved_by(u, body.owner, key_u),
                com_known=body.com_known,  # a USD first side may state a mass with no centre of mass
            )
        )
    for body in m.bodies:
        com, inertia = place(body, poses_m.get(body.name))
        twin = twin_m.get(body.name)
        silent = twin if twin is not None and u.body(twin) is None and twin in u.no_inertial else None
        twin = twin if twin is not None and (tb := u.body(twin)) is not None and same_body(tb, body) else None
        out[_owner_key(m, body.owner, key_m)].mjcf.append(
            Part(
                body.name,
                body.mass,
                com,
                inertia,
                twin,
                body.snapped,
                known=body.mass_known,
                unset_twin=silent,
                moved_by=_moved_by(m, body.owner, key_m),
                snapped_com=body.snapped_com,
                com_known=body.com_known,
            )
        )
    return [g for g in out.values() if g.urdf or g.mjcf]


def rounded_side(x: float, y: float) -> str:
    """Which of two readings of a number was written with fewer digits (the rounded one)."""
    lx, ly = (len(repr(float(v)).lstrip("-").replace(".", "").lstrip("0")) for v in (x, y))
    return "URDF" if lx < ly else "MJCF" if ly < lx else "both files"


def principal(inertia: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments (ascending) and axes (columns)."""
    w, v = np.linalg.eigh(inertia)
    return w, v


def _axis_name(v: np.ndarray, frame: np.ndarray | None) -> str:
    """A direction named in a link frame's axes when it lies along one (``+x``), else as a vector."""
    local = v if frame is None else frame[:3, :3].T @ v
    k = int(np.argmax(np.abs(local)))
    if abs(local[k]) > 1 - 1e-6:
        return "xyz"[k]
    return "[" + ", ".join(f"{x:.3g}" for x in local) + "]"


def describe_tensors(a: np.ndarray, b: np.ndarray, frame: np.ndarray | None, moment_tol: float) -> dict:
    """Principal moments and axes of two tensors (URDF, MJCF) in ``frame``'s axes (a 4x4 pose in
    the common frame; None: the common frame), which axes differ and by how much."""
    wa, va = principal(a)
    wb, vb = principal(b)
    scale = max(float(np.abs(wa).max()), float(np.abs(wb).max()), 1e-300)
    same_moments = bool(np.abs(wa - wb).max() <= max(moment_tol, 1e-12 * scale))
    axes = []
    for k in range(3):
        gap = min(abs(wa[k] - wa[j]) for j in range(3) if j != k) / scale
        angle = math.degrees(math.atan2(float(np.linalg.norm(np.cross(va[:, k], vb[:, k]))), abs(float(va[:, k] @ vb[:, k]))))
        axes.append(
            {
                "moment_urdf": float(wa[k]),
                "moment_mjcf": float(wb[k]),
                "angle_deg": angle,
                "defined": gap > 1e-3,
                "urdf_axis": _axis_name(va[:, k], frame),
                "mjcf_axis": _axis_name(vb[:, k], frame),
            }
        )
    turned = [x for x in axes if x["defined"] and x["angle_deg"] > 1e-3]
    return {
        "urdf_principal": wa.tolist(),
        "mjcf_principal": wb.tolist(),
        "same_moments": same_moments,
        "axes": axes,
        "largest_axis_angle_deg": max([x["angle_deg"] for x in axes if x["defined"]], default=0.0),
        "turned": [f"moment {x['moment_urdf']:.4g} along {x['urdf_axis']} (URDF) vs {x['mjcf_axis']} (MJCF)" for x in turned],
    }


@dataclass
class GroupResult:
    """A rigid body compared: both files' inertials, their difference, the tolerances in effect
    and the verdict: ``agree``, ``rounding`` (within the written precision only), ``explained``
    (agree once the bodies with no twin are left out: ``extra``), ``unset`` (agree once the bodies
    whose twin in the other file states no inertial are left out), ``unknown`` (part of a mass came
    from an absent mesh: not compared) or ``differs``. The parts a joint in one file only moves
    (``moved``) are that joint's, said once with it, and never compared here."""

    group: Group
    urdf: Inertial
    mjcf: Inertial
    diff: Difference
    tol: tuple[float, float, float]  # mass [kg], com [m], tensor [kg·m²]
    status: str
    without_extra: Difference | None = None
    extra: list[Part] = field(default_factory=list)  # the parts whose leaving out makes the files agree
    tensors: dict = field(default_factory=dict)  # describe_tensors of the two inertias
    moved: list[Part] = field(default_factory=list)  # parts a joint in one file only moves: left out, that joint's

    @property
    def label(self) -> str:
        g = self.group
        return g.urdf_link if g.urdf_link == g.mjcf_link else f"{g.urdf_link} / {g.mjcf_link}"

    def ratio(self, k: int) -> float:
        value = (self.diff.mass, self.diff.com, self.diff.tensor)[k]
        return value / self.tol[k] if self.tol[k] > 0 else (math.inf if value > 0 else 0.0)


def carry_to_joints(grps: list[Group], info) -> None:
    """Each rigid body compared in the frame it hangs from: the MJCF's parts moved by its joint's
    carry (:mod:`kinverify.filemode.align.attribution`), which takes out what the joints above it
    change (and its own frame, when that moved or turned with everything it holds), so a body is
    not blamed for where the chain puts it. Where nothing above differs, this is the identity: the
    bodies are compared where they are, in the URDF's world at the aligned zero."""
    for g in grps:
        att = info.alignment.attribution.get(g.key)
        if att is None or np.allclose(att.carry, np.eye(4), rtol=0.0, atol=1e-15):
            continue
        rot = att.carry[:3, :3]
        for part in g.mjcf:
            part.com = rot @ part.com + att.carry[:3, 3]
            part.inertia = rot @ part.inertia @ rot.T
        g.seated = (float(geodesic_distance(rot, np.eye(3))), float(np.linalg.norm(att.carry[:3, 3])))


def analyse(info, defaults: tuple[float, ...]) -> list[GroupResult]:
    """Every rigid body of both files compared (see the module docstring); ``defaults``: the
    mass, CoM and tensor tolerances in effect (the written precision may raise them)."""
    grps = groups(
        info.u,
        info.m,
        info.joint_pairs,
        info.frame_pairs,
        info.poses_u,
        aligned_poses(info.alignment, info.poses_m) if info.file_mode else info.poses_m,
        info.floating,
    )
    fl = info.floors
    out = []
    if info.file_mode:
        carry_to_joints(grps, info)
    for g in grps:
        a, b = g.total("urdf"), g.total("mjcf")
        frames = [p.name for p in g.urdf]
        pos_floor = max([fl.frame(f)[0] for f in frames], default=0.0)
        rot_floor = max([fl.frame(f)[1] for f in frames], default=0.0)
        lever = max([float(np.linalg.norm(p.com - a.com)) for p in g.urdf] + [0.0])
        big = max(a.mass, b.mass)
        com_floor = info.floor("inertia.com", fl.com + pos_floor + rot_floor * lever)
        mass_tol = max(defaults[0], info.floor("inertia.mass", fl.relative * big))
        snapped_com = sum(p.snapped_com * p.mass for p in g.mjcf) / max(b.mass, 1e-300)  # MuJoCo's, not the file's
        com_tol = max(defaults[1], com_floor) + snapped_com
        norm = max(float(np.abs(np.linalg.eigvalsh(a.inertia)).max()), float(np.abs(np.linalg.eigvalsh(b.inertia)).max()))
        snapped = sum(2 * p.snapped * float(np.ptp(np.linalg.eigvalsh(p.inertia))) for p in g.mjcf)
        tensor_tol = max(
            defaults[2],
            info.floor(
                "inertia.tensor",
                (fl.relative + 2 * (fl.inertial_angle + rot_floor)) * norm + 2 * big * (lever + fl.com) * com_floor,
            ),
            defaults[2] + snapped,
        )
        diff = difference(a, b)
        if not all(p.com_known for p in g.urdf + g.mjcf):  # the mass is compared, not where it sits
            com_tol = tensor_tol = math.inf
        tol = (mass_tol, com_tol, tensor_tol)
        # what a joint in one file only moves, with no twin in the other file, is that joint's part
        # (an extra part, said with it), not this body's, unless the bodies agree with it held at zero
        moved = [p for p in g.urdf + g.mjcf if p.moved_by and p.twin is None and p.mass > 0]
        if moved and not diff.within(*tol):
            a, b = g.total("urdf", moved), g.total("mjcf", moved)
            diff = difference(a, b)
        else:
            moved = []
        # a body one file leaves unset (no inertial) weighs only in the other: when the stated ones
        # differ on their own, their difference is the finding's, by the stated values alone (the unset
        # one is said apart, as a warning)
        unset = [p for p in g.urdf + g.mjcf if p.unset_twin and not any(p is x for x in moved)]
        stated = [p for p in g.urdf + g.mjcf if p.mass > 0 and not any(p is x for x in moved + unset)]
        # only where every stated part has its twin (the unset one's mass is not stated elsewhere in the body)
        if unset and stated and all(p.twin is not None for p in stated) and not diff.within(*tol):
            stated_u, stated_m = g.total("urdf", moved + unset), g.total("mjcf", moved + unset)
            if not difference(stated_u, stated_m).within(*tol):
                a, b, diff = stated_u, stated_m, difference(stated_u, stated_m)
        if not all(p.known for p in g.urdf + g.mjcf):  # a placeholder mass: nothing to say, either way
            result = GroupResult(g, a, b, diff, tol, "unknown", moved=moved)
        elif diff.within(*tol):
            exact = (
                (defaults[0], defaults[1] + snapped_com, defaults[2] + snapped)
                if math.isfinite(com_tol)
                else (defaults[0], com_tol, tensor_tol)
            )
            status = "rounding" if not diff.within(*exact) and info.file_mode else "agree"
            result = GroupResult(g, a, b, diff, tol, status, moved=moved)
        else:
            result = GroupResult(g, a, b, diff, tol, "differs", moved=moved)
            lone_u, lone_m = (g.twinless(s) for s in ("urdf", "mjcf"))
            # bodies with no twin explain a difference only when one file has them: with some in both,
            # the files describe one body by other links (a massless root link and its inertia link)
            extra = [p for p in (lone_u if not lone_m else lone_m if not lone_u else []) if not any(p is x for x in moved)]
            without = difference(g.total("urdf", moved + extra), g.total("mjcf", moved + extra)) if extra else None
            if without is not None and without.within(*tol):
                status = "unset" if all(p.unset_twin for p in extra) else "explained"
                result = GroupResult(g, a, b, diff, tol, status, without, extra, moved=moved)
        frame = info.poses_u.get(g.urdf_link)
        result.tensors = describe_tensors(a.inertia, b.inertia, frame, tensor_tol)
        out.append(result)
    return out


def uniform_mass_ratio(results) -> float | None:
    """The MJCF's mass over the URDF's when it is one and the same (not 1) for every rigid body
    with mass in both files: a units mistake, not many differences."""
    massive = [r for r in results if r.urdf.mass > 0 and r.mjcf.mass > 0 and not r.group.fixed_base_root]
    ratios = [r.mjcf.mass / r.urdf.mass for r in massive]
    if len(massive) < 2 or not all(abs(x / ratios[0] - 1) < 1e-6 for x in ratios) or abs(ratios[0] - 1) < 1e-2:
        return None
    return ratios[0]
