"""Attribution: each matched joint's own difference, after what the joints above it already move,
so that a change is said once, where it is, and nothing it carries is blamed for moving with it.

Each matched joint carries a rigid body: its link and what hangs from it (centres of mass and
inertias, named frames, the next joints' axis lines), its own axis line among them. Down the chain,
at the aligned zero, the MJCF's body of each joint is brought onto the URDF's by a *carry*, the
rigid motion that takes out what the joints above already account for (the base's is the
identity: the world transform is the alignment's). A joint inherits its parent's carry, unless
its frame sits elsewhere on its parent (the MJCF's body ``pos`` or ``quat`` edited, a URDF joint
``<origin>`` changed) with everything it holds the same in its own axes: then that is *its* one
difference, a moved frame (the offset vector, along its axis too) or a turned one (axis and angle:
the tilt of its axis and the twist about it together), and its own carry lays its MJCF frame onto
the URDF's.

Only a frame change that explains more of the body's features than the parent's carry does is
taken, and only when both files hang the body's contents in one frame (the same centre of mass,
inertia and axis in its own axes): where they agree in the world but not in the link's axes, the
files chose the link frame differently (a frame convention: a constant turn about the joint's
axis with everything it holds turned back is no difference at all), and nothing is said.

The findings then compare each joint's axis, and each rigid body's inertial, after its carry (see
:mod:`kinverify.filemode.findings.alignment`, :mod:`kinverify.filemode.compare.inertials`): a
second change below another is measured in its own right.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from kinverify.filemode.align.geometry import project_on_line, rotation_between
from kinverify.filemode.read.model import ModelDesc
from kinverify.model.transforms import axis_angle_to_matrix, geodesic_distance, invert_transform, matrix_to_quat, rotation_log

INERTIAL_ANGLE = 1e-6  # rad: an inertia tensor's orientation is known to about this, beyond the written precision


@dataclass
class Attribution:
    """One matched joint (URDF name) after the joints above it: ``carry`` (4x4) brings what the
    MJCF's joint moves, at the aligned zero in the URDF's world, onto the URDF's; ``axis``: its
    axis lines after the carry, (angle rad, distance m); ``moved`` (xyz m, in its parent link's
    axes) and ``turn`` (rotation vector rad, in its own axes): how its frame sits elsewhere on its
    parent, when that is its difference (else None)."""

    joint: str
    carry: np.ndarray
    axis: tuple[float, float] = (0.0, 0.0)
    moved: np.ndarray | None = None
    turn: np.ndarray | None = None
    parent_frame: str = ""
    folded: float = 0.0  # the zero offset the fit took, part of its frame's turn (said there; the joint map's is then 0)
    tilt_twist: tuple[float, float] = (0.0, 0.0)  # of a turn: how far it tilts the joint's axis, and turns about it [rad]
    contents: int = 0  # what the body holds (centre of mass, inertia, named frames) that still differs after the carry
    merged_base: str = ""  # a first joint's URDF parent link that the MJCF merges into its world
    base_placed: bool = False  # that link sits away from the URDF's world (its root's fixed joints place it)

    @property
    def changed(self) -> bool:
        return self.moved is not None or self.turn is not None


def _apply(t: np.ndarray, x: np.ndarray) -> np.ndarray:
    return t[:3, :3] @ x + t[:3, 3]


def joint_line(desc: ModelDesc, joint: str, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A joint's axis direction and a point of its axis with its moving frame at ``pose``."""
    j = desc.joint(joint)
    t0 = desc.frames[j.child]
    rot = pose[:3, :3] @ t0[:3, :3].T
    return rot @ j.axis, rot @ (j.anchor - t0[:3, 3]) + pose[:3, 3]


def _inertial(desc: ModelDesc, owner: str, poses: dict) -> tuple[float, np.ndarray, np.ndarray] | None:
    """Mass, centre of mass and inertia about it (world) of the bodies moving with ``owner`` only."""
    parts = [
        (b.mass, _apply(poses[b.name], b.com_local), poses[b.name][:3, :3] @ b.inertia_local @ poses[b.name][:3, :3].T)
        for b in desc.bodies
        if b.owner == owner and b.mass > 0 and b.name in poses
    ]
    mass = float(sum(p[0] for p in parts))
    if mass <= 0:
        return None
    com: np.ndarray = sum((p[0] * p[1] for p in parts), np.zeros(3)) / mass
    inertia: np.ndarray = sum(
        (i + m * (float((c - com) @ (c - com)) * np.eye(3) - np.outer(c - com, c - com)) for m, c, i in parts), np.zeros((3, 3))
    )
    return mass, com, inertia


class _Body:
    """The features of what one joint pair moves, both files, at the aligned zero (URDF world)."""

    def __init__(self, info, a: str, b: str, pm: dict, children: list[tuple[str, str]]) -> None:
        u, m, fl = info.u, info.m, info.floors
        ju = u.joint(a)
        self.ptol, self.rtol = info.tol(ju.child)
        sign = info.alignment.joint(a).sign
        self.own: list[tuple[str, Any, Any]] = []
        self.next: list[tuple[str, Any, Any]] = []
        au, pu = joint_line(u, a, info.poses_u[ju.child])
        am, pmm = joint_line(m, b, pm[m.joint(b).child])
        self.own.append(("line", (au, pu), (sign * am, pmm)))
        for c, d in children:
            cu, cm = u.joint(c), m.joint(d)
            if cu.child in info.poses_u and cm.child in pm:
                self.next.append(("line", joint_line(u, c, info.poses_u[cu.child]), joint_line(m, d, pm[cm.child])))
        iu, im = _inertial(u, a, info.poses_u), _inertial(m, b, pm)
        if iu is not None and im is not None:
            self.own.append(("com", iu[1], im[1]))
            if abs(iu[0] - im[0]) <= 1e-3 * max(iu[0], im[0]):  # a different mass is a different inertial
                self.own.append(("tensor", iu[2], im[2]))
            norm = max(float(np.abs(np.linalg.eigvalsh(x[2])).max()) for x in (iu, im))
            origin = info.poses_u[ju.child][:3, 3]
            self.com_tol = self.ptol + 2 * fl.com + self.rtol * float(np.linalg.norm(iu[1] - origin))
            self.tensor_tol = (1e-9 + fl.relative + 2 * (fl.inertial_angle + self.rtol + INERTIAL_ANGLE)) * norm
        for fu, fm, _ in info.matching.frames:
            if (
                u.frame_owner.get(fu) == a
                and m.frame_owner.get(fm) == b
                and m.frame_kind.get(fm) == "site"
                and fu in info.poses_u
                and fm in pm
            ):
                self.own.append(("site", info.poses_u[fu][:3, 3], pm[fm][:3, 3]))

    def errors(self, feature, carry: np.ndarray) -> list[float]:
        """How far a feature is off under ``carry``, relative to its tolerance (> 1: differs)."""
        kind, x, y = feature
        if kind == "line":
            (au, pu), (am, pm) = x, y
            am, pm = carry[:3, :3] @ am, _apply(carry, pm)
            angle = float(np.arctan2(np.linalg.norm(np.cross(au, am)), float(au @ am)))
            return [angle / self.rtol, float(np.linalg.norm(pm - project_on_line(pm, pu, au))) / self.ptol]
        if kind == "tensor":
            rot = carry[:3, :3]
            return [float(np.abs(np.linalg.eigvalsh(x - rot @ y @ rot.T)).max()) / self.tensor_tol]
        tol = self.com_tol if kind == "com" else self.ptol
        return [float(np.linalg.norm(x - _apply(carry, y))) / tol]

    def differing(self, carry: np.ndarray, features) -> int:
        return sum(e > 1.0 for f in features for e in self.errors(f, carry))


def attribute(info) -> dict[str, Attribution]:
    """Every matched joint's attribution (see the module docstring), in the URDF's chain order.
    ``info``: :class:`kinverify.filemode.compare.context.FileModeInfo` of the aligned files."""
    u, m, al = info.u, info.m, info.alignment
    to_m = {j.urdf: j.mjcf for j in al.joints}
    tinv = invert_transform(al.T)
    pm = {name: tinv @ pose for name, pose in info.poses_m.items()}
    out: dict[str, Attribution] = {}
    for j in al.joints:
        a, b = j.urdf, j.mjcf
        ju, jm = u.joint(a), m.joint(b)
        if ju.child not in info.poses_u or jm.child not in pm:
            continue
        up = ju.parent
        while up is not None and up not in to_m:  # a joint in one file only: what it moves is held at zero
            up = u.joint(up).parent
        inherited = out[up].carry if up in out else np.eye(4)
        children = [
            (c.name, to_m[c.name])
            for c in u.joints
            if c.parent == a and c.name in to_m and m.has_joint(to_m[c.name]) and m.joint(to_m[c.name]).parent == b
        ]
        body = _Body(info, a, b, pm, children)
        att = Attribution(a, inherited, parent_frame=u.joint(up).child if up is not None else "")
        att.merged_base = _merged_base(u, m, ju, jm) if up is None else ""
        placed = info.poses_u.get(att.merged_base) if att.merged_base else None
        att.base_placed = placed is not None and not np.allclose(placed, np.eye(4), rtol=0.0, atol=1e-12)
        same_parent = ju.parent == up and (jm.parent == to_m[up] if up is not None else jm.parent is None)
        if same_parent:
            _frame_change(att, info, body, up, ju.child, pm[jm.child])
        if up in out and out[up].changed and not att.changed:
            _unneeded_offset(att, body, j)
        att.axis = tuple(body.errors(body.own[0], att.carry)[k] * (body.rtol, body.ptol)[k] for k in (0, 1))
        if not att.changed and (att.axis[0] > body.rtol or att.axis[1] > body.ptol):
            _seat(att, body)
        att.contents = body.differing(att.carry, body.own[1:])
        out[a] = att
    return out


def _merged_base(u: ModelDesc, m: ModelDesc, ju, jm) -> str:
    """The URDF link a first joint hangs from when the MJCF has no frame of its own for it (MuJoCo
    merges a fixed base into its world, so both files place that joint's frame from the world),
    else ""."""
    link = ju.parent_frame
    return link if link not in ("", "world") and link not in m.frames and jm.parent_frame in ("", "world") else ""


def _frame_change(att: Attribution, info, body: _Body, parent: str | None, child: str, pose_m: np.ndarray) -> None:
    """Take the joint's frame change as its difference when it explains more than the parent's
    carry and leaves what the joint's own body holds agreeing (see the module docstring)."""
    pose_u = info.poses_u[child]
    seen = att.carry @ pose_m  # the MJCF's frame, what the joints above account for taken out
    delta = seen[:3, 3] - pose_u[:3, 3]
    angle = float(geodesic_distance(pose_u[:3, :3], seen[:3, :3]))
    if float(np.linalg.norm(delta)) <= body.ptol and angle <= body.rtol:
        return
    own = pose_u @ invert_transform(pose_m)
    features = body.own + body.next
    if body.differing(own, body.own) or body.differing(own, features) >= body.differing(att.carry, features):
        return
    offset = info.alignment.joint(att.joint).offset
    if angle > body.rtol and offset and info.u.joint(att.joint).type == "revolute":
        # a frame turned about another axis than its joint's, whose twist part the alignment took
        # for a zero offset: one turn, as the file writes the frame (at the MJCF's own zero)
        am, pm = joint_line(info.m, info.alignment.joint(att.joint).mjcf, pose_m)
        seen = seen @ invert_transform(_about(invert_transform(pose_m), am, pm, offset))
        att.folded = offset
        info.alignment.joint(att.joint).offset = 0.0  # the files' joints share their zero: the turn is the difference
        delta = seen[:3, 3] - pose_u[:3, 3]
    base = info.poses_u[info.u.joint(parent).child] if parent is not None else np.eye(4)
    if float(np.linalg.norm(delta)) > body.ptol:
        att.moved = base[:3, :3].T @ delta
    turn = pose_u[:3, :3].T @ seen[:3, :3]
    if angle > body.rtol and float(np.linalg.norm(rotation_log(turn))) > body.rtol:
        att.turn = rotation_log(turn)
        axis = pose_u[:3, :3].T @ body.own[0][1][0]  # the joint's axis in its own (URDF) axes
        q = matrix_to_quat(turn)
        tilt = float(np.arctan2(np.linalg.norm(np.cross(axis, turn @ axis)), float(axis @ turn @ axis)))
        att.tilt_twist = (tilt, abs(2 * float(np.arctan2(float(q[1:] @ axis), q[0]))))
    att.carry = own


def _unneeded_offset(att: Attribution, body: _Body, j) -> None:
    """A zero offset the fit gave a joint below a moved or turned frame may stand only for that
    frame's change (the fit knows zero offsets, not turned frames: a frame turned about another
    axis is fitted as an offset about its joint's axis, and the joint below makes up the rest):
    when what the joint moves agrees under its carry as well with the offset taken out, the offset
    is no difference of its own and is dropped (``j``: its :class:`JointMap`)."""
    if not j.offset or j.type != "revolute":
        return
    am, point = body.own[0][2]
    undo = np.eye(4)  # the MJCF's body turned back about its own axis line by the offset
    undo[:3, :3] = axis_angle_to_matrix(j.sign * am, np.array([-j.offset]))[0]
    undo[:3, 3] = point - undo[:3, :3] @ point
    trial = att.carry @ undo
    features = body.own + body.next
    if body.differing(trial, features) <= body.differing(att.carry, features):
        att.carry = trial
        j.offset = 0.0


def _seat(att: Attribution, body: _Body) -> None:
    """A joint whose axis line differs while its frame is the files' own choice (no frame change
    to take): what it moves is carried seated on its axis (the MJCF's laid onto the URDF's by the
    smallest rigid motion) when that makes more of what it moves agree than the parent's carry
    does (its frame and axis moved together); an axis tilted within its frame moves nothing at the
    zero, and keeps the parent's carry."""
    (au, pu), (am, pm) = body.own[0][1], body.own[0][2]
    am, pm = att.carry[:3, :3] @ am, _apply(att.carry, pm)
    seat = np.eye(4)
    seat[:3, :3] = rotation_between(am, au)
    seat[:3, 3] = project_on_line(pm, pu, au) - seat[:3, :3] @ pm
    seated = seat @ att.carry
    features = body.own + body.next
    if body.differing(seated, features) < body.differing(att.carry, features):
        att.carry = seated


def _about(to_local: np.ndarray, axis: np.ndarray, point: np.ndarray, angle: float) -> np.ndarray:
    """The motion (4x4, in a body's own coordinates) of a turn by ``angle`` about the world line
    (``axis``, ``point``), ``to_local`` taking world coordinates to the body's."""
    a, p = to_local[:3, :3] @ axis, _apply(to_local, point)
    out = np.eye(4)
    out[:3, :3] = axis_angle_to_matrix(a, np.array([angle]))[0]
    out[:3, 3] = p - out[:3, :3] @ p
    return out


def findings_count(info) -> int:
    """How many differences the alignment and attribution of ``info`` leave to report: the world
    transform, each sign flip, zero offset, moved or turned frame and axis that differs, and each
    rigid body whose own contents differ after its carry."""
    al = info.alignment
    t = al.T
    n = int(float(np.abs(t[:3, 3]).max()) > 1e-9 or float(geodesic_distance(t[:3, :3], np.eye(3))) > 1e-9)
    n += _base_frames_differ(info)
    for j in al.joints:
        att = al.attribution.get(j.urdf)
        n += (j.sign < 0) + bool(j.offset)
        if att is None:
            continue
        ptol, rtol = info.tol(info.u.joint(j.urdf).child)
        n += (att.moved is not None) + (att.turn is not None) + (att.axis[0] > rtol or att.axis[1] > ptol)
        n += att.contents
    return n


def _base_frames_differ(info) -> int:
    """1 when a frame that no joint moves in either file (a fixed base's links, bodies or sites),
    matched in both, sits elsewhere under the alignment: a world transform that misplaces the
    base's own frames is a difference of its own, so a first joint's moved or turned frame is
    not taken for the world's (the worlds as they are keep such frames together)."""
    u, m = info.u, info.m
    tinv = invert_transform(info.alignment.T)
    for fu, fm, _ in info.matching.frames:
        if u.frame_owner.get(fu, "") is not None or m.frame_owner.get(fm, "") is not None:
            continue
        if fu not in info.poses_u or fm not in info.poses_m:
            continue
        ptol, rtol = info.tol(fu)
        x, y = info.poses_u[fu], tinv @ info.poses_m[fm]
        if float(np.linalg.norm(x[:3, 3] - y[:3, 3])) > ptol or float(geodesic_distance(x[:3, :3], y[:3, :3])) > rtol:
            return 1
    return 0
