"""One neutral description of a loaded model, the same for both files: movable joints in chain
order with their world axis lines at q = 0, limits, joint dynamics, couplings (URDF ``<mimic>``,
MJCF ``<equality joint>``) and the force actuators can exert on them; frames (URDF links, MJCF
bodies and sites) with their world poses at q = 0; each body's inertial in its own frame and in
the world at q = 0. The URDF is read through Pinocchio, the MJCF through MuJoCo (the libraries
resolve defaults, classes and conventions; kinverify only compares). ``q = 0`` is every joint's
zero (MuJoCo ``qpos = 0``, not ``qpos0``: a ``ref`` is a zero offset).
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
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
    lower: float  # -inf / inf: unlimited
    upper: float
    damping: float | None = None
    friction: float | None = None
    armature: float | None = None  # None: the format cannot express it
    effort: float | None = None  # None: not stated; inf: actuators without a force bound
    velocity: float | None = None  # None: the format cannot express it
    effort_how: str = ""  # where the effort comes from (URDF <limit>, MJCF actuators)


@dataclass
class BodyInertial:
    owner: str | None  # movable joint the body moves with (None: fixed base)
    mass: float
    com: np.ndarray  # world, q = 0
    inertia: np.ndarray  # 3x3 about the CoM, world axes, q = 0
    name: str = ""  # URDF link / MJCF body; also the name of its frame
    com_local: np.ndarray = field(default_factory=lambda: np.zeros(3))  # in the body's frame
    inertia_local: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))  # about the CoM, body axes
    snapped: float = 0.0  # MuJoCo: angle [rad] of principal axes it aligned with the body frame (body_sameframe)


@dataclass(frozen=True)
class Coupling:
    """``follower = multiplier * leader + offset`` (radians or metres)."""

    follower: str
    leader: str
    multiplier: float
    offset: float
    source: str  # "<mimic>" or "<equality joint>"
    nonlinear: bool = False  # MJCF polycoef terms beyond the linear one (not compared)


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
    frame_kind: dict[str, str] = field(default_factory=dict)  # "link" (URDF link, MJCF body) or "site"
    couplings: list[Coupling] = field(default_factory=list)
    gravity: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -9.81]))
    extensions: dict[str, dict] = field(default_factory=dict)  # joint -> non-standard tags (drake rotor inertia)

    def joint(self, name: str) -> JointDesc:
        return next(j for j in self.joints if j.name == name)

    def has_joint(self, name: str) -> bool:
        return any(j.name == name for j in self.joints)

    @property
    def total_mass(self) -> float:
        return float(sum(b.mass for b in self.bodies))

    def body(self, name: str) -> BodyInertial | None:
        return next((b for b in self.bodies if b.name == name), None)


def _inertial_world(pose: np.ndarray, com_local, inertia_local) -> tuple[np.ndarray, np.ndarray]:
    rot = pose[:3, :3]
    return rot @ np.asarray(com_local) + pose[:3, 3], rot @ inertia_local @ rot.T


# --- URDF through Pinocchio -------------------------------------------------------------------

def describe_urdf(urdf_text: str) -> ModelDesc:
    """Pinocchio's reading of the URDF (fixed base, every joint at 0). Continuous joints are read
    as unlimited revolute joints (see :func:`kinverify.filemode.prepare.prepare_urdf`)."""
    import pinocchio as pin

    from kinverify.filemode.prepare import continuous_joints, prepare_urdf

    model = pin.buildModelFromXML(prepare_urdf(urdf_text))
    data = model.createData()
    q = pin.neutral(model)
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    root = ET.fromstring(urdf_text)
    xml_joints = {j.get("name"): j for j in root.findall("joint")}
    unlimited = continuous_joints(urdf_text)
    movable, skipped = {}, []
    for jid in range(1, model.njoints):
        jm = model.joints[jid]
        if jm.nq != 1 or jm.nv != 1:
            skipped.append(f"{model.names[jid]}: {jm.shortname()} has {jm.nq} coordinates; only 1-DOF joints are "
                           "compared (held at neutral)")
            continue
        movable[jid] = model.names[jid]
    body = pin.FrameType.BODY
    frames, owner, depth, kind = {}, {}, {}, {}
    for i, f in enumerate(model.frames):
        if f.type != body:
            continue
        frames[f.name] = data.oMf[i].homogeneous.copy()
        owner[f.name] = _movable_ancestor(model, f.parentJoint, movable)
        depth[f.name] = _frame_depth(model, i)
        kind[f.name] = "link"
    joints = []
    for jid, name in movable.items():
        jm = model.joints[jid]
        col = np.reshape(pin.getJointJacobian(model, data, jid, pin.LOCAL_WORLD_ALIGNED), (6, -1))[:, jm.idx_v]
        revolute = np.linalg.norm(col[3:]) > 0.5
        axis = col[3:] if revolute else col[:3]
        lo, up = float(model.lowerPositionLimit[jm.idx_q]), float(model.upperPositionLimit[jm.idx_q])
        if name in unlimited:
            lo, up = -INF, INF
        limit = xml_joints[name].find("limit") if name in xml_joints else None
        stated = limit is not None and limit.get("effort") is not None
        joints.append(JointDesc(
            name, "revolute" if revolute else "prismatic", _movable_ancestor(model, model.parents[jid], movable),
            _child_link(model, jid), _parent_link(model, jid), axis / np.linalg.norm(axis), data.oMi[jid].translation.copy(),
            lo if abs(lo) < 1e300 else -INF, up if abs(up) < 1e300 else INF,
            damping=float(model.damping[jm.idx_v]), friction=float(model.friction[jm.idx_v]), armature=None,
            effort=float(model.effortLimit[jm.idx_v]) if stated else None,
            velocity=float(model.velocityLimit[jm.idx_v]) if limit is not None and limit.get("velocity") else None,
            effort_how="URDF <limit effort>" if stated else "no effort in the URDF"))
    bodies = _urdf_bodies(model, data, movable)
    couplings = []
    for name, el in xml_joints.items():
        mimic = el.find("mimic")
        if mimic is not None and mimic.get("joint"):
            couplings.append(Coupling(name, mimic.get("joint"), float(mimic.get("multiplier", 1.0)),
                                      float(mimic.get("offset", 0.0)), "<mimic>"))
    return ModelDesc("urdf", "pinocchio", joints, frames, owner, depth, bodies, skipped, kind, couplings,
                     extensions=_urdf_extensions(root))


def _urdf_bodies(model, data, movable: dict) -> list[BodyInertial]:
    """One inertial per URDF link: Pinocchio fuses fixed links into their joint's inertia and keeps
    each fixed link's own inertia on its fixed-joint frame; a moving link is its joint's inertia
    minus the fixed links fused into it."""
    import pinocchio as pin

    fixed, fused = {}, {}
    for f in model.frames:
        if f.type == pin.FrameType.FIXED_JOINT and f.inertia.mass > 0:
            fused[f.parentJoint] = fused.get(f.parentJoint, pin.Inertia.Zero()) + f.placement.act(f.inertia)
    out = []
    for i, f in enumerate(model.frames):
        if f.type != pin.FrameType.BODY:
            continue
        parent = model.frames[f.parentFrame]
        if f.inertia.mass > 0:  # the root link keeps its inertia on its own frame
            inertia = f.inertia
        elif parent.type == pin.FrameType.FIXED_JOINT and f.parentFrame > 0:
            inertia = parent.inertia  # in the fixed joint's frame, which is the link's
        elif parent.type == pin.FrameType.JOINT:
            inertia = model.inertias[f.parentJoint] - fused.get(f.parentJoint, pin.Inertia.Zero())
            inertia = f.placement.actInv(inertia)
        else:
            continue
        mass = float(inertia.mass)
        if mass <= 1e-12:
            continue
        pose = data.oMf[i].homogeneous
        com_l, ine_l = np.array(inertia.lever), np.array(inertia.inertia)
        com_w, ine_w = _inertial_world(pose, com_l, ine_l)
        out.append(BodyInertial(_movable_ancestor(model, f.parentJoint, movable), mass, com_w, ine_w, f.name, com_l, ine_l))
    return out


def _urdf_extensions(root) -> dict[str, dict]:
    """Non-standard ``<transmission>`` tags Pinocchio does not read (Drake's gear ratio and rotor inertia)."""
    out = {}
    for tr in root.iter("transmission"):
        joint = tr.find("joint")
        if joint is None:
            continue
        found = {}
        for el in tr.iter():
            tag = el.tag.split("}")[-1].split(":")[-1]
            if tag in ("gear_ratio", "rotor_inertia") and el.get("value") is not None:
                try:
                    found[tag] = float(el.get("value"))
                except ValueError:
                    continue
        if found:
            out[joint.get("name")] = found
    return out


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


# --- MJCF through MuJoCo ----------------------------------------------------------------------

def describe_mjcf(mjcf_text: str) -> ModelDesc:
    """MuJoCo's reading of the MJCF, with every ``qpos`` at 0 (not ``qpos0``: ``ref`` is a zero offset)."""
    import mujoco

    m = mujoco.MjModel.from_xml_string(mjcf_text)
    d = mujoco.MjData(m)
    d.qpos[:] = 0.0
    mujoco.mj_kinematics(m, d)
    hinge, slide = int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)
    movable = {j: m.joint(j).name for j in range(m.njnt) if int(m.jnt_type[j]) in (hinge, slide)}
    skipped = [f"{m.joint(j).name or f'joint #{j}'}: {mujoco.mjtJoint(int(m.jnt_type[j])).name} joints are not compared "
               "(held at 0)" for j in range(m.njnt) if j not in movable]

    def body_owner(b: int) -> str | None:
        while b > 0:
            js = [j for j in range(m.body_jntadr[b], m.body_jntadr[b] + m.body_jntnum[b]) if j in movable] if m.body_jntnum[b] else []
            if js:
                return movable[js[-1]]
            b = m.body_parentid[b]
        return None

    frames, owner, depth, kind = {}, {}, {}, {}
    for b in range(1, m.nbody):
        name = m.body(b).name
        if not name:
            continue
        frames[name], owner[name] = _pose(d.xpos[b], d.xmat[b]), body_owner(b)
        depth[name], kind[name] = _body_depth(m, b), "link"
    for s in range(m.nsite):
        name = m.site(s).name
        if name and name not in frames:
            b = m.site_bodyid[s]
            frames[name], owner[name] = _pose(d.site_xpos[s], d.site_xmat[s]), body_owner(b)
            depth[name], kind[name] = _body_depth(m, b) + 1, "site"
    actuation = actuator_efforts(m)
    joints = []
    for j, name in movable.items():
        b, v = m.jnt_bodyid[j], m.jnt_dofadr[j]
        same_body = [k for k in range(m.body_jntadr[b], j) if k in movable]
        parent = movable[same_body[-1]] if same_body else body_owner(m.body_parentid[b])
        limited = bool(m.jnt_limited[j])
        lo, up = (float(m.jnt_range[j][0]), float(m.jnt_range[j][1])) if limited else (-INF, INF)
        effort, how = actuation.get(j, (None, "no actuator in the MJCF"))
        if m.jnt_actfrclimited[j]:
            cap = float(max(abs(m.jnt_actfrcrange[j][0]), abs(m.jnt_actfrcrange[j][1])))
            effort, how = (cap, f"joint actuatorfrcrange ±{cap:g}") if effort is None or cap < effort else (effort, how)
        joints.append(JointDesc(
            name, "revolute" if int(m.jnt_type[j]) == hinge else "prismatic", parent, m.body(b).name,
            m.body(m.body_parentid[b]).name if m.body_parentid[b] > 0 else "world",
            np.array(d.xaxis[j]), np.array(d.xanchor[j]), lo, up,
            damping=float(m.dof_damping[v]), friction=float(m.dof_frictionloss[v]), armature=float(m.dof_armature[v]),
            effort=effort, velocity=None, effort_how=how))
    bodies = []
    for b in range(1, m.nbody):
        if m.body_mass[b] <= 0:
            continue
        rot_i = np.reshape(d.ximat[b], (3, 3))
        rot_b = np.reshape(d.xmat[b], (3, 3))
        ine_w = rot_i @ np.diag(m.body_inertia[b]) @ rot_i.T
        com_l = rot_b.T @ (np.array(d.xipos[b]) - d.xpos[b])
        bodies.append(BodyInertial(body_owner(b), float(m.body_mass[b]), np.array(d.xipos[b]), ine_w, m.body(b).name,
                                   com_l, rot_b.T @ ine_w @ rot_b, _snapped(m, b)))
    return ModelDesc("mjcf", "mujoco", joints, frames, owner, depth, bodies, skipped, kind, _mjcf_couplings(m, movable),
                     np.array(m.opt.gravity, dtype=float))


def _snapped(m, b: int) -> float:
    """The rotation [rad] of a body's principal axes that MuJoCo's compiler dropped, treating them
    as aligned with the body frame (``body_sameframe``) because it was below about 1e-6 rad."""
    import mujoco

    aligned = (int(mujoco.mjtSameFrame.mjSAMEFRAME_BODY), int(mujoco.mjtSameFrame.mjSAMEFRAME_BODYROT))
    vec = float(np.linalg.norm(m.body_iquat[b][1:]))
    return 2.0 * float(np.arcsin(min(1.0, vec))) if int(m.body_sameframe[b]) in aligned and vec > 0 else 0.0


def _pose(pos, mat) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = np.reshape(mat, (3, 3)), pos
    return t


def _body_depth(m, b: int) -> int:
    depth = 0
    while b > 0:
        b = m.body_parentid[b]
        depth += 1
    return depth


def _mjcf_couplings(m, movable: dict) -> list[Coupling]:
    """Active ``<equality joint>`` constraints: ``q1 − ref1 = p0 + p1 (q2 − ref2) + …`` as a coupling."""
    import mujoco

    out = []
    for e in range(m.neq):
        if int(m.eq_type[e]) != int(mujoco.mjtEq.mjEQ_JOINT) or not m.eq_active0[e]:
            continue
        j1, j2 = int(m.eq_obj1id[e]), int(m.eq_obj2id[e])
        if j1 not in movable or j2 not in movable:
            continue
        p = np.array(m.eq_data[e][:5], dtype=float)
        ref1, ref2 = float(m.qpos0[m.jnt_qposadr[j1]]), float(m.qpos0[m.jnt_qposadr[j2]])
        out.append(Coupling(movable[j1], movable[j2], float(p[1]), ref1 + float(p[0]) - float(p[1]) * ref2,
                            "<equality joint>", nonlinear=bool(np.any(p[2:] != 0))))
    return out


def actuator_efforts(m) -> dict[int, tuple[float, str]]:
    """Joint id -> (the largest force or torque MuJoCo's actuators can put on that joint, how).

    An actuator on a joint or on a fixed tendon through it (coefficient c) transmits
    ``gear · c`` times its force. Its force is bounded by ``forcerange`` when force-limited, by
    ``ctrlrange × gain`` for a motor (fixed gain, no bias) with a control range, and unbounded
    otherwise (a position or velocity servo without ``forcerange``): ``inf``."""
    import mujoco

    found: dict[int, list[tuple[float, str]]] = {}
    joint_trn = (int(mujoco.mjtTrn.mjTRN_JOINT), int(mujoco.mjtTrn.mjTRN_JOINTINPARENT))
    for a in range(m.nu):
        trn, target = int(m.actuator_trntype[a]), int(m.actuator_trnid[a][0])
        if trn in joint_trn:
            through = [(target, 1.0, "")]
        elif trn == int(mujoco.mjtTrn.mjTRN_TENDON):
            tname = m.tendon(target).name or f"#{target}"
            through = [(int(m.wrap_objid[w]), float(m.wrap_prm[w]), f" on tendon {tname} (coef {float(m.wrap_prm[w]):g})")
                       for w in range(m.tendon_adr[target], m.tendon_adr[target] + m.tendon_num[target])
                       if int(m.wrap_type[w]) == int(mujoco.mjtWrap.mjWRAP_JOINT)]
        else:
            continue
        gear = float(m.actuator_gear[a][0])
        name = m.actuator(a).name or f"actuator #{a}"
        motor = (int(m.actuator_gaintype[a]) == int(mujoco.mjtGain.mjGAIN_FIXED)
                 and int(m.actuator_biastype[a]) == int(mujoco.mjtBias.mjBIAS_NONE))
        if m.actuator_forcelimited[a]:
            force = float(max(abs(m.actuator_forcerange[a][0]), abs(m.actuator_forcerange[a][1])))
            bound, why = force, f"forcerange ±{force:g}"
        elif motor and m.actuator_ctrllimited[a]:
            ctrl = float(max(abs(m.actuator_ctrlrange[a][0]), abs(m.actuator_ctrlrange[a][1])))
            gain = abs(float(m.actuator_gainprm[a][0]))
            bound, why = ctrl * gain, f"ctrlrange ±{ctrl:g} × gain {gain:g}"
        else:
            bound, why = INF, "no forcerange" + ("" if motor else " (a servo: unbounded force)")
        for joint, coef, via in through:
            scale = abs(gear * coef)
            effort = bound * scale if math.isfinite(bound) else INF
            gear_txt = f" × gear {gear:g}" if gear != 1 else ""
            found.setdefault(joint, []).append((effort, f"{name}{via}: {why}{gear_txt}"))
    return {j: (float(sum(e for e, _ in items)), "; ".join(h for _, h in items)) for j, items in found.items()}
