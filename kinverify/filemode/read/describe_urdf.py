"""Pinocchio's reading of a URDF as a :class:`~kinverify.filemode.read.model.ModelDesc`: movable
joints in chain order with their world axis lines at q = 0, limits, joint dynamics, ``<mimic>``
couplings; links with their world poses at q = 0; each link's inertial in its own frame and in the
world at q = 0. Pinocchio resolves the URDF's conventions; kinverify only compares.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin

from kinverify.backends.pinocchio_ import build_urdf_model
from kinverify.filemode.read.model import INF, BodyInertial, Coupling, JointDesc, ModelDesc, inertial_world
from kinverify.filemode.read.prepare import continuous_joints, prepare_urdf


def describe_urdf(urdf_text: str) -> ModelDesc:
    """Pinocchio's reading of the URDF (fixed base, every joint at 0). Continuous joints are read
    as unlimited revolute joints (see :func:`kinverify.filemode.read.prepare.prepare_urdf`)."""

    model = build_urdf_model(prepare_urdf(urdf_text))
    data = model.createData()
    q = pin.neutral(model)
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    root = ET.fromstring(urdf_text)
    xml_joints = {j.get("name"): j for j in root.findall("joint")}
    unlimited = continuous_joints(urdf_text)
    movable, skipped, held = {}, [], []
    for jid in range(1, model.njoints):
        jm = model.joints[jid]
        if jm.nq != 1 or jm.nv != 1:
            skipped.append(
                f"{model.names[jid]}: {jm.shortname()} has {jm.nq} coordinates; only 1-DOF joints are compared (held at neutral)"
            )
            held.append(model.names[jid])
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
        joints.append(
            JointDesc(
                name,
                "revolute" if revolute else "prismatic",
                _movable_ancestor(model, model.parents[jid], movable),
                _child_link(model, jid),
                _parent_link(model, jid),
                axis / np.linalg.norm(axis),
                data.oMi[jid].translation.copy(),
                lo if abs(lo) < 1e300 else -INF,
                up if abs(up) < 1e300 else INF,
                damping=float(model.damping[jm.idx_v]),
                friction=float(model.friction[jm.idx_v]),
                armature=None,
                effort=float(model.effortLimit[jm.idx_v]) if stated else None,
                velocity=float(model.velocityLimit[jm.idx_v]) if limit is not None and limit.get("velocity") else None,
                effort_how="URDF <limit effort>" if stated else "no effort in the URDF",
            )
        )
    bodies = _urdf_bodies(model, data, movable)
    couplings = []
    for name, el in xml_joints.items():
        mimic = el.find("mimic")
        if mimic is not None and (leader := mimic.get("joint")):
            couplings.append(
                Coupling(name, leader, float(mimic.get("multiplier", 1.0)), float(mimic.get("offset", 0.0)), "<mimic>")  # type: ignore[arg-type]  # joints are named
            )
    return ModelDesc(
        "urdf",
        "pinocchio",
        joints,
        frames,
        owner,
        depth,
        bodies,
        skipped,
        kind,
        couplings,
        extensions=_urdf_extensions(root),
        held=held,
    )


def _urdf_bodies(model, data, movable: dict) -> list[BodyInertial]:
    """One inertial per URDF link: Pinocchio fuses fixed links into their joint's inertia and keeps
    each fixed link's own inertia on its fixed-joint frame; a moving link is its joint's inertia
    minus the fixed links fused into it."""
    fused: dict = {}
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
        com_w, ine_w = inertial_world(pose, com_l, ine_l)
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

    for f in model.frames:
        if f.type == pin.FrameType.BODY and f.parentJoint == jid:
            return f.name
    return model.names[jid]


def _parent_link(model, jid: int) -> str:

    jframe = model.getFrameId(model.names[jid], pin.FrameType.JOINT)
    fid = model.frames[jframe].parentFrame
    while fid > 0 and model.frames[fid].type != pin.FrameType.BODY:
        fid = model.frames[fid].parentFrame
    return model.frames[fid].name
