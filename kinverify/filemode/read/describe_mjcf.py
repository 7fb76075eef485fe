"""MuJoCo's reading of an MJCF as a :class:`~kinverify.filemode.read.model.ModelDesc` (see
:mod:`kinverify.filemode.read.describe_urdf`), with the force MuJoCo's actuators can put on each joint."""

from __future__ import annotations

import math

import mujoco
import numpy as np

from kinverify.filemode.read.model import INF, BodyInertial, Coupling, JointDesc, ModelDesc


def describe_mjcf(mjcf_text: str) -> ModelDesc:
    """MuJoCo's reading of the MJCF, with every ``qpos`` at 0 (not ``qpos0``: ``ref`` is a zero offset)."""
    m = mujoco.MjModel.from_xml_string(mjcf_text)
    d = mujoco.MjData(m)
    d.qpos[:] = 0.0
    mujoco.mj_kinematics(m, d)
    hinge, slide = int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)
    flex, flex_notes = flex_bodies(m)
    unnamed, unnamed_notes = unnamed_subtrees(m, flex)
    flex |= unnamed
    flex_notes += unnamed_notes
    robot = [j for j in range(m.njnt) if int(m.jnt_bodyid[j]) not in flex]
    movable = {j: m.joint(j).name for j in robot if int(m.jnt_type[j]) in (hinge, slide)}
    skipped = [
        f"{m.joint(j).name or f'joint #{j}'}: {mujoco.mjtJoint(int(m.jnt_type[j])).name} joints are not compared (held at 0)"
        for j in robot
        if j not in movable
    ] + flex_notes
    held = [m.joint(j).name for j in robot if j not in movable and m.joint(j).name]

    def body_owner(b: int) -> str | None:
        while b > 0:
            js = (
                [j for j in range(m.body_jntadr[b], m.body_jntadr[b] + m.body_jntnum[b]) if j in movable]
                if m.body_jntnum[b]
                else []
            )
            if js:
                return movable[js[-1]]
            b = m.body_parentid[b]
        return None

    frames, owner, depth, kind = {}, {}, {}, {}
    for b in range(1, m.nbody):
        name = m.body(b).name
        if not name or b in flex:
            continue
        frames[name], owner[name] = _pose(d.xpos[b], d.xmat[b]), body_owner(b)
        depth[name], kind[name] = _body_depth(m, b), "link"
    for s in range(m.nsite):
        name, b = m.site(s).name, int(m.site_bodyid[s])
        if name and name not in frames and b not in flex:  # a site on a body not compared is not compared
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
        effort, how, each = actuation.get(j, (None, "no actuator in the MJCF", ()))
        if m.jnt_actfrclimited[j]:  # the joint's cap on the total actuator force
            cap = float(max(abs(m.jnt_actfrcrange[j][0]), abs(m.jnt_actfrcrange[j][1])))
            if effort is None or cap < effort:
                effort, how, each = cap, f"joint actuatorfrcrange ±{cap:g}", ()
        joints.append(
            JointDesc(
                name,
                "revolute" if int(m.jnt_type[j]) == hinge else "prismatic",
                parent,
                m.body(b).name,
                m.body(m.body_parentid[b]).name if m.body_parentid[b] > 0 else "world",
                np.array(d.xaxis[j]),
                np.array(d.xanchor[j]),
                lo,
                up,
                damping=float(m.dof_damping[v]),
                friction=float(m.dof_frictionloss[v]),
                armature=float(m.dof_armature[v]),
                stiffness=float(m.jnt_stiffness[j]),
                effort=effort,
                velocity=None,
                effort_how=how,
                effort_each=each if len(each) > 1 else (),
            )
        )
    bodies = []
    for b in range(1, m.nbody):
        if m.body_mass[b] <= 0 or b in flex:
            continue
        rot_i = np.reshape(d.ximat[b], (3, 3))
        rot_b = np.reshape(d.xmat[b], (3, 3))
        ine_w = rot_i @ np.diag(m.body_inertia[b]) @ rot_i.T
        com_l = rot_b.T @ (np.array(d.xipos[b]) - d.xpos[b])
        bodies.append(
            BodyInertial(
                body_owner(b),
                float(m.body_mass[b]),
                np.array(d.xipos[b]),
                ine_w,
                m.body(b).name,
                com_l,
                rot_b.T @ ine_w @ rot_b,
                _snapped(m, b),
                snapped_com=_snapped_com(m, b),
            )
        )
    return ModelDesc(
        "mjcf",
        "mujoco",
        joints,
        frames,
        owner,
        depth,
        bodies,
        skipped,
        kind,
        _mjcf_couplings(m, movable),
        np.array(m.opt.gravity, dtype=float),
        held=held,
        gravcomp={
            m.body(b).name: float(m.body_gravcomp[b])
            for b in range(1, m.nbody)
            if m.body_gravcomp[b] and m.body_mass[b] > 0 and b not in flex
        },
    )


def unnamed_subtrees(m, skipped: set[int]) -> tuple[set[int], list[str]]:
    """Bodies moved by a hinge or slide joint without a name (no library can be asked for it by
    name), with the bodies they carry, and one note per such body: not compared."""
    moving = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
    tops = sorted(
        {
            int(m.jnt_bodyid[j])
            for j in range(m.njnt)
            if not m.joint(j).name and int(m.jnt_type[j]) in moving and int(m.jnt_bodyid[j]) not in skipped
        }
    )
    out = set()
    for b in range(1, m.nbody):
        a = b
        while a > 0 and a not in tops:
            a = int(m.body_parentid[a])
        if a > 0:
            out.add(b)
    notes = [
        f"body {m.body(b).name or f'#{b}'}: moved by an unnamed joint; it and the bodies it carries are not "
        "compared (name the joint to compare them)"
        for b in tops
    ]
    return out, notes


def flex_bodies(m) -> tuple[set[int], list[str]]:
    """The bodies MuJoCo made for the vertices of deformable objects (``<flexcomp>``; each with its
    own unnamed slide joints), and one note per object: they are not part of the robot and are not
    compared. A vertex held by its parent body (``<pin>``, or a rigid flex) leaves that body in."""
    out, notes = set(), []
    for f in range(m.nflex):
        name = mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_FLEX, f) or f"#{f}"
        ids = {int(b) for b in m.flex_vertbodyid[m.flex_vertadr[f] : m.flex_vertadr[f] + m.flex_vertnum[f]]}
        parents = {int(m.body_parentid[b]) for b in ids}
        # <flexcomp name="cloth"> makes bodies cloth_0, cloth_1, ...; a <flex> over the model's own bodies makes none
        own = {b for b in ids if b > 0 and b not in parents and m.body(b).name.startswith(f"{name}_")} if len(ids) > 1 else set()
        if own:
            out |= own
            notes.append(
                f"flex {name}: a deformable object of {len(own)} bodies (<flexcomp>), not part of the robot: not compared"
            )
    return out, notes


def free_joint_values(text: str) -> dict[str, float]:
    """The largest armature and damping an MJCF's free joints give their six dofs (often from a
    default class meant for the legs), those that are not 0 ({} if MuJoCo cannot read the text)."""
    try:
        m = mujoco.MjModel.from_xml_string(text)
    except ValueError:
        return {}
    dofs = [
        int(m.jnt_dofadr[j]) + k for j in range(m.njnt) if int(m.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_FREE) for k in range(6)
    ]
    values = {
        "armature": float(max((m.dof_armature[v] for v in dofs), default=0.0)),
        "damping": float(max((m.dof_damping[v] for v in dofs), default=0.0)),
    }
    return {k: v for k, v in values.items() if v}


def _snapped(m, b: int) -> float:
    """The rotation [rad] of a body's principal axes that MuJoCo's compiler dropped, treating them
    as aligned with the body frame (``body_sameframe``) because it was below about 1e-6 rad."""
    aligned = (int(mujoco.mjtSameFrame.mjSAMEFRAME_BODY), int(mujoco.mjtSameFrame.mjSAMEFRAME_BODYROT))
    vec = float(np.linalg.norm(m.body_iquat[b][1:]))
    return 2.0 * float(np.arcsin(min(1.0, vec))) if int(m.body_sameframe[b]) in aligned and vec > 0 else 0.0


def _snapped_com(m, b: int) -> float:
    """How far [m] a body's stated centre of mass (``body_ipos``) lies from where MuJoCo's run time
    puts it: at the body origin, when the compiler found it within about 1e-6 m of it (``body_sameframe``)."""
    same = int(m.body_sameframe[b]) == int(mujoco.mjtSameFrame.mjSAMEFRAME_BODY)
    return float(np.linalg.norm(m.body_ipos[b])) if same else 0.0


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
    out = []
    for e in range(m.neq):
        if int(m.eq_type[e]) != int(mujoco.mjtEq.mjEQ_JOINT) or not m.eq_active0[e]:
            continue
        j1, j2 = int(m.eq_obj1id[e]), int(m.eq_obj2id[e])
        if j1 not in movable or j2 not in movable:
            continue
        p = np.array(m.eq_data[e][:5], dtype=float)
        ref1, ref2 = float(m.qpos0[m.jnt_qposadr[j1]]), float(m.qpos0[m.jnt_qposadr[j2]])
        out.append(
            Coupling(
                movable[j1],
                movable[j2],
                float(p[1]),
                ref1 + float(p[0]) - float(p[1]) * ref2,
                "<equality joint>",
                nonlinear=bool(np.any(p[2:] != 0)),
            )
        )
    return out


def actuator_efforts(m) -> dict[int, tuple[float, str, tuple[tuple[float, str], ...]]]:
    """Joint id -> (the largest force or torque one of MuJoCo's actuators can put on that joint,
    how, each actuator's (bound, how) in MJCF order).

    An actuator on a joint or on a fixed tendon through it (coefficient c) transmits
    ``gear · c`` times its force. Its force is bounded by ``forcerange`` when force-limited, by
    ``ctrlrange × gain`` for a motor (fixed gain, no bias) with a control range, and unbounded
    otherwise (a position or velocity servo without ``forcerange``): ``inf``. Several actuators on
    one joint are read as alternative ways of driving it (a motor, a position servo, a velocity
    servo, each with its own controls), not as forces meant to add up: the joint's bound is the
    largest of theirs, and each is kept for the comparison with the URDF."""
    found: dict[int, list[tuple[float, str]]] = {}
    joint_trn = (int(mujoco.mjtTrn.mjTRN_JOINT), int(mujoco.mjtTrn.mjTRN_JOINTINPARENT))
    for a in range(m.nu):
        trn, target = int(m.actuator_trntype[a]), int(m.actuator_trnid[a][0])
        if trn in joint_trn:
            through = [(target, 1.0, "")]
        elif trn == int(mujoco.mjtTrn.mjTRN_TENDON):
            tname = m.tendon(target).name or f"#{target}"
            through = [
                (int(m.wrap_objid[w]), float(m.wrap_prm[w]), f" on tendon {tname} (coef {float(m.wrap_prm[w]):g})")
                for w in range(m.tendon_adr[target], m.tendon_adr[target] + m.tendon_num[target])
                if int(m.wrap_type[w]) == int(mujoco.mjtWrap.mjWRAP_JOINT)
            ]
        else:
            continue
        gear = float(m.actuator_gear[a][0])
        name = m.actuator(a).name or f"actuator #{a}"
        motor = int(m.actuator_gaintype[a]) == int(mujoco.mjtGain.mjGAIN_FIXED) and int(m.actuator_biastype[a]) == int(
            mujoco.mjtBias.mjBIAS_NONE
        )
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
    return {j: (float(max(e for e, _ in items)), "; ".join(h for _, h in items), tuple(items)) for j, items in found.items()}
