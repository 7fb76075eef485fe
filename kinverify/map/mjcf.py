"""An MJCF as MuJoCo compiles it, as a :class:`~kinverify.map.side.Side`.

Order: MuJoCo's joint order (its ``qpos``/``qvel`` order; each joint's ``qposadr`` and ``dofadr``
are kept, a free base takes ``qpos[0:7]``), and the actuator order (``ctrl``). Per joint: the
default position (``qpos0``, which is the joint's ``ref``, or the keyframe named by ``--keyframe``),
armature, ``frictionloss`` and damping as MuJoCo resolves them from default classes (a value no
class states is *unset*: MuJoCo uses 0), the effort bound of its actuators (``forcerange``,
``ctrlrange × gain`` of a motor, times ``gear``; the joint's ``actuatorfrcrange``), and the PD
gains in joint space: an affine-bias actuator (``position``, ``velocity``, ``general``) puts
``gear · (gain·ctrl + b0 + b1·gear·q + b2·gear·q̇)`` on its joint, so kp = −b1·gear² and
kd = −b2·gear² (several actuators on one joint add). A ``motor`` is torque control: its gains live
in the controller, not the file. An actuator through a tendon drives the joints of the tendon
(its gains are not joint gains: not compared). MuJoCo has no velocity limit. Active
``<equality joint>`` constraints are couplings; inactive ones are not."""

from __future__ import annotations

import math

import mujoco

from kinverify.errors import InputError
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.filemode.read.loading import load_mjcf
from kinverify.filemode.read.prepare import fix_free_bases
from kinverify.filemode.read.stated import mjcf_joint_values
from kinverify.map.side import Actuator, Follows, MapJoint, Side

EXPRESSES = frozenset({"default", "stiffness", "damping", "effort", "armature", "friction", "joint_damping"})
STATED = {"armature": "armature", "friction": "friction", "joint_damping": "damping"}  # ours -> read.stated's


def read_mjcf(path: str, options) -> Side:
    loaded = load_mjcf(path, keep_meshes=False)
    try:
        m = mujoco.MjModel.from_xml_string(loaded.text)
        desc = describe_mjcf(fix_free_bases(loaded.text)[0])
    except ValueError as err:
        raise InputError(f"{path}: MuJoCo cannot load it: {' '.join(str(err).split())}") from None
    qpos, how_default = _default_qpos(m, path, getattr(options, "keyframe", None))
    stated = mjcf_joint_values(loaded.tree)
    movable = (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE))
    joints, by_id = [], {}
    for jid in range(m.njnt):
        if int(m.jnt_type[jid]) not in movable:
            continue
        name, adr, dof = m.joint(jid).name or f"joint #{jid}", int(m.jnt_qposadr[jid]), int(m.jnt_dofadr[jid])
        kind = "revolute" if int(m.jnt_type[jid]) == movable[0] else "prismatic"
        j = MapJoint(name, kind, adr, dof, default=float(qpos[adr]), driven=False, how={"default": how_default})
        said = stated.get(name, frozenset())
        for ours, theirs in STATED.items():
            if theirs in said:
                field = {"armature": m.dof_armature, "friction": m.dof_frictionloss, "joint_damping": m.dof_damping}[ours]
                setattr(j, ours, float(field[dof]))
                j.how[ours] = f"joint {'frictionloss' if ours == 'friction' else theirs} (its own or its default class's)"
        if desc.has_joint(name):
            d = desc.joint(name)
            if d.effort is not None and math.isfinite(d.effort):
                j.effort, j.how["effort"] = d.effort, d.effort_how
        joints.append(j)
        by_id[jid] = j
    actuators = _actuators(m, by_id)
    for c in desc.couplings:
        follower = next((j for j in joints if j.name == c.follower), None)
        if follower is not None:
            follower.follows = Follows(c.leader, c.multiplier, c.offset, c.source)
    keys = [m.key(k).name or f"#{k}" for k in range(m.nkey)]
    notes = list(loaded.warnings)
    if keys and not getattr(options, "keyframe", None):
        notes.append(
            f"keyframes: {', '.join(keys)} (the default position is qpos0, the joints' ref; --keyframe NAME "
            "takes a keyframe instead)"
        )
    if m.nq != sum(1 for _ in joints):
        notes.append(f"qpos has {m.nq} coordinates, {len(joints)} of them 1-DOF joints (a free base takes 7, a ball 4)")
    return Side(path, path, "mjcf", "MuJoCo qpos order", joints, actuators, EXPRESSES, desc, notes)


def _default_qpos(m, path: str, keyframe: str | None):
    if not keyframe:
        return m.qpos0, "qpos0 (joint ref)"
    names = [m.key(k).name for k in range(m.nkey)]
    if keyframe not in names:
        listed = ", ".join(n or "(unnamed)" for n in names) or "none"
        raise InputError(f"{path}: --keyframe {keyframe!r}: no such keyframe; keyframes: {listed}")
    return m.key_qpos[names.index(keyframe)], f"keyframe {keyframe!r}"


def _actuators(m, by_id: dict) -> list[Actuator]:
    """The actuators in ``ctrl`` order; the joints they act on marked driven, with their gains."""
    joint_trn = (int(mujoco.mjtTrn.mjTRN_JOINT), int(mujoco.mjtTrn.mjTRN_JOINTINPARENT))
    affine, none = int(mujoco.mjtBias.mjBIAS_AFFINE), int(mujoco.mjtBias.mjBIAS_NONE)
    out = []
    for a in range(m.nu):
        name = m.actuator(a).name or f"actuator #{a}"
        trn, target = int(m.actuator_trntype[a]), int(m.actuator_trnid[a][0])
        bias, gear = int(m.actuator_biastype[a]), float(m.actuator_gear[a][0])
        fixed_gain = int(m.actuator_gaintype[a]) == int(mujoco.mjtGain.mjGAIN_FIXED)
        if trn in joint_trn and target in by_id:
            j = by_id[target]
            b1, b2 = float(m.actuator_biasprm[a][1]), float(m.actuator_biasprm[a][2])
            if bias == affine and fixed_gain:
                kind = "position" if b1 else "velocity" if b2 else "general"
                j.stiffness = (j.stiffness or 0.0) - b1 * gear**2
                j.damping = (j.damping or 0.0) - b2 * gear**2
                j.how["stiffness"] = j.how["damping"] = f"{name}: −biasprm[1:3] × gear²" + (
                    f" (gear {gear:g})" if gear != 1 else ""
                )
                gain = float(m.actuator_gainprm[a][0])
                if b1 and abs(gain + b1) > 1e-9 * abs(b1):  # the target is ctrl scaled: a policy's action is not a joint angle
                    j.how["target"] = f"{name}: target = ctrl × {gain / (-b1 * gear):.6g} (gainprm[0] / (−biasprm[1]·gear))"
                elif gear != 1 and b1:
                    j.how["target"] = f"{name}: target = ctrl / gear {gear:g}"
            else:
                kind = "motor (torque)" if bias == none and fixed_gain else "general"
                j.apart.setdefault("stiffness", f"{name} is a {kind}: the gains live in the controller")
                j.apart.setdefault("damping", j.apart["stiffness"])
            j.driven, j.mode = True, "+".join(x for x in (j.mode, kind) if x)
            out.append(Actuator(name, (j.name,), kind))
        elif trn == int(mujoco.mjtTrn.mjTRN_TENDON):
            tendon = m.tendon(target).name or f"#{target}"
            joints = tuple(
                by_id[int(m.wrap_objid[w])].name
                for w in range(m.tendon_adr[target], m.tendon_adr[target] + m.tendon_num[target])
                if int(m.wrap_type[w]) == int(mujoco.mjtWrap.mjWRAP_JOINT) and int(m.wrap_objid[w]) in by_id
            )
            for jn in joints:
                j = next(x for x in by_id.values() if x.name == jn)
                j.driven, j.mode = True, "+".join(x for x in (j.mode, f"tendon {tendon}") if x)
                j.apart.setdefault("stiffness", f"{name} drives tendon {tendon}: its gains are not joint gains")
                j.apart.setdefault("damping", j.apart["stiffness"])
            out.append(Actuator(name, joints, f"tendon {tendon}", direct=False))
        else:
            out.append(Actuator(name, (), "site or body transmission", direct=False))
    return out
