"""One neutral description of a loaded model, the same for both files: movable joints in chain
order with their world axis lines at q = 0, limits and joint dynamics; frames with their world
poses at q = 0; body inertials in the world frame. The URDF is read through Pinocchio, the MJCF
through MuJoCo (the libraries resolve defaults, classes and conventions; kinverify only compares).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

INF = math.inf


@dataclass
class JointDesc:
    name: str
    type: str  # "revolute" or "prismatic"
    parent: str | None  # nearest movable ancestor joint (None: on the fixed base)
    child: str  # frame that moves with the joint (URDF child link / MJCF body)
    parent_frame: str  # frame the joint hangs from (URDF parent link / MJCF parent body)
    axis: np.ndarray  # unit direction, world, q = 0
    anchor: np.ndarray  # a point on the axis, world, q = 0
    lower: float
    upper: float
    damping: float | None = None
    friction: float | None = None
    armature: float | None = None  # None: the format cannot express it
    effort: float | None = None
    velocity: float | None = None


@dataclass
class BodyInertial:
    owner: str | None  # movable joint the body moves with (None: fixed base)
    mass: float
    com: np.ndarray  # world, q = 0
    inertia: np.ndarray  # 3x3 about the CoM, world axes


@dataclass
class ModelDesc:
    kind: str  # "urdf" or "mjcf"
    library: str
    joints: list[JointDesc]
    frames: dict[str, np.ndarray]  # name -> world pose at q = 0
    frame_owner: dict[str, str | None]  # name -> movable joint it moves with
    frame_depth: dict[str, int]
    bodies: list[BodyInertial]
    skipped: list[str] = field(default_factory=list)  # joints not compared, with the reason

    def joint(self, name: str) -> JointDesc:
        return next(j for j in self.joints if j.name == name)


def describe_urdf(urdf_text: str) -> ModelDesc:
    """Pinocchio's reading of the URDF (fixed base, every joint at 0)."""
    import pinocchio as pin

    model = pin.buildModelFromXML(urdf_text)
    data = model.createData()
    q = pin.neutral(model)
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    joints, skipped = [], []
    movable = {}
    frames = {f.name: data.oMf[i].homogeneous.copy() for i, f in enumerate(model.frames) if f.type == pin.FrameType.BODY}
    owner, depth = {}, {}
    for i, f in enumerate(model.frames):
        if f.type != pin.FrameType.BODY:
            continue
        depth[f.name] = _frame_depth(model, i)
    for jid in range(1, model.njoints):
        jm = model.joints[jid]
        name = model.names[jid]
        if jm.nq != 1 or jm.nv != 1:
            skipped.append(f"{name}: {jm.shortname()} has {jm.nq} coordinates; only 1-DOF joints are compared (held at neutral)")
            continue
        movable[jid] = name
    for i, f in enumerate(model.frames):
        if f.type == pin.FrameType.BODY:
            owner[f.name] = _movable_ancestor(model, f.parentJoint, movable)
    for jid, name in movable.items():
        jm = model.joints[jid]
        col = np.reshape(pin.getJointJacobian(model, data, jid, pin.LOCAL_WORLD_ALIGNED), (6, -1))[:, jm.idx_v]
        revolute = np.linalg.norm(col[3:]) > 0.5
        axis = col[3:] if revolute else col[:3]
        child = _child_link(model, jid)
        parent_frame = _parent_link(model, jid)
        lo, up = float(model.lowerPositionLimit[jm.idx_q]), float(model.upperPositionLimit[jm.idx_q])
        joints.append(JointDesc(
            name, "revolute" if revolute else "prismatic", _movable_ancestor(model, model.parents[jid], movable),
            child, parent_frame, axis / np.linalg.norm(axis), data.oMi[jid].translation.copy(),
            lo if abs(lo) < 1e300 else -INF, up if abs(up) < 1e300 else INF,
            damping=float(model.damping[jm.idx_v]), friction=float(model.friction[jm.idx_v]), armature=None,
            effort=float(model.effortLimit[jm.idx_v]), velocity=float(model.velocityLimit[jm.idx_v])))
    bodies = []
    for jid in range(model.njoints):
        inertia = model.inertias[jid]
        if inertia.mass <= 0:
            continue
        rot = data.oMi[jid].rotation
        bodies.append(BodyInertial(_movable_ancestor(model, jid, movable), float(inertia.mass),
                                   data.oMi[jid].act(inertia.lever), rot @ inertia.inertia @ rot.T))
    return ModelDesc("urdf", "pinocchio", joints, frames, owner, depth, bodies, skipped)


def _movable_ancestor(model, jid: int, movable: dict) -> str | None:
    while jid > 0 and jid not in movable:
        jid = model.parents[jid]
    return movable.get(jid)


def _frame_depth(model, fid: int) -> int:
    depth = 0
    while fid > 0:
        fid = model.frames[fid].parentFrame
        depth += 1
    return depth


def _child_link(model, jid: int) -> str:
    import pinocchio as pin

    for f in model.frames:
        if f.type == pin.FrameType.BODY and f.parentJoint == jid:
            return f.name
    return model.names[jid]


def _parent_link(model, jid: int) -> str:
    import pinocchio as pin

    jframe = model.getFrameId(model.names[jid], pin.FrameType.JOINT)
    fid = model.frames[jframe].parentFrame
    while fid > 0 and model.frames[fid].type != pin.FrameType.BODY:
        fid = model.frames[fid].parentFrame
    return model.frames[fid].name


def describe_mjcf(mjcf_text: str) -> ModelDesc:
    """MuJoCo's reading of the MJCF, with every ``qpos`` at 0 (not ``qpos0``: ``ref`` is a zero offset)."""
    import mujoco

    m = mujoco.MjModel.from_xml_string(mjcf_text)
    d = mujoco.MjData(m)
    d.qpos[:] = 0.0
    mujoco.mj_kinematics(m, d)
    hinge, slide = int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)
    movable = {j: m.joint(j).name for j in range(m.njnt) if int(m.jnt_type[j]) in (hinge, slide)}
    skipped = [f"{m.joint(j).name}: {mujoco.mjtJoint(int(m.jnt_type[j])).name} joints are not compared (held at 0)"
               for j in range(m.njnt) if j not in movable]

    def body_owner(b: int) -> str | None:
        while b > 0:
            js = [j for j in range(m.body_jntadr[b], m.body_jntadr[b] + m.body_jntnum[b]) if j in movable] if m.body_jntnum[b] else []
            if js:
                return movable[js[-1]]
            b = m.body_parentid[b]
        return None

    def pose(pos, mat) -> np.ndarray:
        t = np.eye(4)
        t[:3, :3], t[:3, 3] = np.reshape(mat, (3, 3)), pos
        return t

    frames, owner, depth = {}, {}, {}
    for b in range(1, m.nbody):
        name = m.body(b).name
        frames[name], owner[name] = pose(d.xpos[b], d.xmat[b]), body_owner(b)
        depth[name] = _body_depth(m, b)
    for s in range(m.nsite):
        name = m.site(s).name
        if name and name not in frames:
            b = m.site_bodyid[s]
            frames[name], owner[name], depth[name] = pose(d.site_xpos[s], d.site_xmat[s]), body_owner(b), _body_depth(m, b) + 1
    effort = _actuator_efforts(m)
    joints = []
    for j, name in movable.items():
        b, v = m.jnt_bodyid[j], m.jnt_dofadr[j]
        same_body = [k for k in range(m.body_jntadr[b], j) if k in movable]
        parent = movable[same_body[-1]] if same_body else body_owner(m.body_parentid[b])
        limited = bool(m.jnt_limited[j])
        lo, up = (float(m.jnt_range[j][0]), float(m.jnt_range[j][1])) if limited else (-INF, INF)
        joints.append(JointDesc(
            name, "revolute" if int(m.jnt_type[j]) == hinge else "prismatic", parent, m.body(b).name,
            m.body(m.body_parentid[b]).name if m.body_parentid[b] > 0 else "world",
            np.array(d.xaxis[j]), np.array(d.xanchor[j]), lo, up,
            damping=float(m.dof_damping[v]), friction=float(m.dof_frictionloss[v]), armature=float(m.dof_armature[v]),
            effort=float(max(abs(m.jnt_actfrcrange[j][0]), abs(m.jnt_actfrcrange[j][1]))) if m.jnt_actfrclimited[j] else effort.get(j),
            velocity=None))
    bodies = []
    for b in range(1, m.nbody):
        if m.body_mass[b] <= 0:
            continue
        rot = np.reshape(d.ximat[b], (3, 3))
        bodies.append(BodyInertial(body_owner(b), float(m.body_mass[b]), np.array(d.xipos[b]),
                                   rot @ np.diag(m.body_inertia[b]) @ rot.T))
    return ModelDesc("mjcf", "mujoco", joints, frames, owner, depth, bodies, skipped)


def _body_depth(m, b: int) -> int:
    depth = 0
    while b > 0:
        b = m.body_parentid[b]
        depth += 1
    return depth


def _actuator_efforts(m) -> dict[int, float]:
    """Joint torque/force limit implied by a force-limited actuator acting on a joint alone."""
    import mujoco

    out = {}
    for a in range(m.nu):
        if int(m.actuator_trntype[a]) != int(mujoco.mjtTrn.mjTRN_JOINT) or not m.actuator_forcelimited[a]:
            continue
        j = int(m.actuator_trnid[a][0])
        out[j] = float(max(abs(m.actuator_forcerange[a][0]), abs(m.actuator_forcerange[a][1])) * abs(m.actuator_gear[a][0]))
    return out
