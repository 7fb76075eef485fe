"""pxr's reading of a USD robot as a :class:`~kinverify.filemode.read.model.ModelDesc` (the same
description Pinocchio gives of a URDF and MuJoCo of an MJCF): movable joints in chain order with
their world axis lines at q = 0, limits, joint dynamics, mimic couplings and force bounds; rigid
bodies (and site prims) with their world poses at q = 0; each body's inertial from ``MassAPI``.

Which attributes count (docs/file-mode.md, "USD"), each in SI units and radians:

- limits: ``physics:lowerLimit``/``upperLimit`` (degrees for a revolute joint), ``±inf`` unlimited;
- force bound (``effort``): the joint's ``PhysicsDriveAPI`` ``maxForce``, else MuJoCo's
  ``mjc:actuatorfrcrange`` on the joint; a custom ``urdf:limit:effort`` (what ``urdf-usd-converter``
  keeps of a URDF's effort) is read by no simulator: it is named, not counted (the effort is unset);
- damping: ``newton:damping`` (per degree for an angular joint), else ``mjc:damping``; friction:
  ``newton:friction``, else ``mjc:frictionloss`` (PhysX's ``physxJoint:jointFriction`` is a
  unitless coefficient, named, not compared); armature: ``physxJoint:armature``, else
  ``newton:armature``, else ``mjc:armature``; velocity: ``physxJoint:maxJointVelocity``, else
  ``newton:velocityLimit`` (degrees per second for an angular joint);
- couplings: ``NewtonMimicAPI`` (``follower = coef0 + coef1 · leader``, coef0 in degrees for an
  angular joint) and ``PhysxMimicJointAPI`` (``follower + gearing · leader + offset = 0``, the
  offset in degrees for an angular joint, as every USD angle);
- inertials: ``physics:mass``, ``centerOfMass``, ``diagonalInertia`` and ``principalAxes``. A body
  with no ``MassAPI`` mass leaves it unset: the simulator derives it from the colliders' volume
  (compared as a link that states no inertial); a mass with no inertia or centre of mass: the mass
  is compared, not where it sits.

Drives (stiffness, damping per radian, target), initial joint positions (``PhysicsJointStateAPI``)
and the rest are described in :func:`usd_notes`, not compared.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from kinverify.backends.usd_stage import MOVABLE, UsdRobot, applied_schemas, f32, forward, frame_matrix
from kinverify.filemode.read.model import BodyInertial, Coupling, JointDesc, ModelDesc, inertial_world
from kinverify.filemode.read.precision import Precision

DEG = math.pi / 180


def _get(prim, name: str):
    """An attribute's authored value (None when it is not authored)."""
    attr = prim.GetAttribute(name)
    if not attr or not attr.HasAuthoredValue():
        return None
    return attr.Get()


def _number(prim, name: str) -> float | None:
    """A scalar attribute's authored value; a ``float`` (single precision) as the decimal written."""
    value = _get(prim, name)
    try:
        return None if value is None else f32(value) if prim.GetAttribute(name).GetTypeName() == "float" else float(value)
    except (TypeError, ValueError):
        return None


def _per_degree(value: float | None, unit: float) -> float | None:
    """A value per degree (a single-precision number: 7 significant digits) per radian, to its 7 digits."""
    return None if value is None else float(f"{value * unit:.7g}")


def joint_values(robot: UsdRobot, joint) -> dict:
    """What the USD states of one movable joint, in SI units and radians (None: not stated)."""
    prim = robot.stage.GetPrimAtPath(joint.path)
    angular = joint.kind == "revolute"
    per = 180 / math.pi if angular else 1.0 / robot.meters  # a value per degree (per stage unit) -> per radian (metre)
    k, m = robot.kilograms, robot.meters
    force = k * m * m if angular else k * m  # torque or force unit
    kind = "angular" if angular else "linear"
    out: dict[str, Any] = {"drive": None, "custom_effort": _number(prim, "urdf:limit:effort"), "initial": None}
    if f"PhysicsDriveAPI:{kind}" in applied_schemas(prim):
        pre = f"drive:{kind}:physics:"
        drive: dict[str, Any] = {
            key: _number(prim, pre + key) for key in ("stiffness", "damping", "maxForce", "targetPosition", "targetVelocity")
        }
        drive["type"] = str(_get(prim, pre + "type") or "force")
        for key in ("stiffness", "damping"):
            drive[key] = _per_degree(drive[key], force * per) if angular else _scaled(drive[key], force * per)
        if drive["maxForce"] is not None:
            drive["maxForce"] = drive["maxForce"] * force if math.isfinite(drive["maxForce"]) else math.inf
        for key in ("targetPosition", "targetVelocity"):
            drive[key] = None if drive[key] is None else drive[key] * (DEG if angular else m)
        out["drive"] = drive
    state = _number(prim, f"state:{kind}:physics:position")
    out["initial"] = None if state is None else state * (DEG if angular else m)
    effort, how = None, ""
    if out["drive"] is not None:
        effort = out["drive"]["maxForce"] if out["drive"]["maxForce"] is not None else math.inf
        how = (
            f"USD drive:{kind}:physics:maxForce"
            if out["drive"]["maxForce"] is not None
            else f"USD PhysicsDriveAPI:{kind} without maxForce (unbounded)"
        )
    else:
        lo, hi = _number(prim, "mjc:actuatorfrcrange:min"), _number(prim, "mjc:actuatorfrcrange:max")
        if hi is not None and str(_get(prim, "mjc:actuatorfrclimited")).lower() not in ("false", "0"):
            effort, how = max(abs(lo or 0.0), abs(hi)) * force, "USD mjc:actuatorfrcrange"
    if effort is None:
        how = (
            f"no drive: urdf:limit:effort = {out['custom_effort']:g} is a custom attribute no simulator reads"
            if out["custom_effort"] is not None
            else "no drive and no force range in the USD"
        )
    out["effort"], out["effort_how"] = effort, how
    damping = _number(prim, "newton:damping")
    out["damping"] = (
        (_per_degree(damping, force * per) if angular else _scaled(damping, force * per))
        if damping is not None
        else _scaled(_number(prim, "mjc:damping"), force)
    )
    friction = _number(prim, "newton:friction")
    out["friction"] = _scaled(friction if friction is not None else _number(prim, "mjc:frictionloss"), force)
    armature = next(
        (v for v in (_number(prim, a) for a in ("physxJoint:armature", "newton:armature", "mjc:armature")) if v is not None), None
    )
    out["armature"] = _scaled(armature, k * m * m if angular else k)
    velocity = next(
        (v for v in (_number(prim, a) for a in ("physxJoint:maxJointVelocity", "newton:velocityLimit")) if v is not None), None
    )
    out["velocity"] = (
        None if velocity is None or not math.isfinite(velocity) else _per_degree(velocity, DEG) if angular else velocity * m
    )
    out["physx_friction"] = _number(prim, "physxJoint:jointFriction")
    out["range"] = _get(prim, "physics:lowerLimit") is not None or _get(prim, "physics:upperLimit") is not None
    return out


def _scaled(value: float | None, unit: float) -> float | None:
    return None if value is None else value * unit


def _couplings(robot: UsdRobot, names: dict[str, str]) -> list[Coupling]:
    out = []
    for j in robot.joints:
        if j.kind not in MOVABLE:
            continue
        prim = robot.stage.GetPrimAtPath(j.path)
        rel = prim.GetRelationship("newton:mimicJoint")
        if rel and rel.GetTargets() and _get(prim, "newton:mimicEnabled") is not False:
            leader = names.get(str(rel.GetTargets()[0]))
            coef0, coef1 = _number(prim, "newton:mimicCoef0") or 0.0, _number(prim, "newton:mimicCoef1")
            if leader:
                offset = coef0 * (DEG if j.kind == "revolute" else robot.meters)
                out.append(Coupling(j.name, leader, 1.0 if coef1 is None else coef1, offset, "NewtonMimicAPI"))
                continue
        for schema in applied_schemas(prim):
            if schema.startswith("PhysxMimicJointAPI:"):
                axis = schema.split(":", 1)[1]
                rel = prim.GetRelationship(f"physxMimicJoint:{axis}:referenceJoint")
                leader = names.get(str(rel.GetTargets()[0])) if rel and rel.GetTargets() else None
                if leader:
                    gearing = _number(prim, f"physxMimicJoint:{axis}:gearing") or 0.0
                    offset = (_number(prim, f"physxMimicJoint:{axis}:offset") or 0.0) * (
                        DEG if j.kind == "revolute" else robot.meters
                    )
                    out.append(Coupling(j.name, leader, -gearing, -offset, "PhysxMimicJointAPI"))
    return out


def _inertial(robot: UsdRobot, body: str, pose: np.ndarray, owner) -> tuple[BodyInertial | None, str]:
    """The body's inertial from MassAPI, or None and why it is unset."""
    prim = robot.stage.GetPrimAtPath(body)
    name = robot.names[body]
    mass = _number(prim, "physics:mass")
    if mass is None or mass <= 0:
        return None, f"{name}: no MassAPI mass (the simulator derives it from the colliders)"
    mass *= robot.kilograms
    com, diag = _get(prim, "physics:centerOfMass"), _get(prim, "physics:diagonalInertia")
    known = bool(
        com is not None and diag is not None and np.all(np.isfinite(np.array(com, float))) and any(float(x) > 0 for x in diag)
    )
    com_l = np.array([f32(x) for x in com], dtype=float) * robot.meters if known else np.zeros(3)
    ine_l = np.zeros((3, 3))
    if known:
        axes = _get(prim, "physics:principalAxes")
        rot = np.eye(3)
        if axes is not None and (axes.GetReal() != 0 or any(axes.GetImaginary())):
            rot = frame_matrix((0, 0, 0), axes, 1.0)[:3, :3]
        ine_l = rot @ np.diag([f32(x) for x in diag]) @ rot.T * robot.kilograms * robot.meters**2
    com_w, ine_w = inertial_world(pose, com_l, ine_l)
    why = "" if known else f"{name}: mass {mass:g} kg with no centre of mass or inertia (derived from the colliders)"
    return BodyInertial(owner, mass, com_w, ine_w, name, com_l, ine_l, com_known=known), why


def describe_usd(robot: UsdRobot) -> ModelDesc:
    """pxr's reading of the USD articulation, every joint at 0 (a floating root held at the identity)."""
    poses = {b: t[0] for b, t in forward(robot, {}, 1).items()}
    joint_names = {j.path: j.name for j in robot.joints}
    owner: dict[str, str | None]
    owner, depth, tree_parent = {robot.root: None}, {robot.root: 0}, {}
    joints, skipped, held, extensions = [], [], [], {}
    for body in robot.bodies[1:]:
        j = robot.parent_joint[body]
        up = j.body0 if body == j.body1 else j.body1
        tree_parent[body], depth[body] = up, depth[up] + 1
        owner[body] = j.name if j.kind in MOVABLE else owner[up]
        if j.kind in ("spherical", "d6", "custom"):
            skipped.append(f"{j.name}: {j.kind} joint; only 1-DOF joints are compared (held at 0)")
            held.append(j.name)
        if j.kind not in MOVABLE:
            continue
        flipped = j.path in robot.flipped
        frame = poses[j.body0] @ j.x0 if not flipped else poses[j.body1] @ j.x1
        axis = frame[:3, j.axis] * (-1.0 if flipped else 1.0)
        v = joint_values(robot, j)
        stated = {
            name
            for name, key in (("damping", "damping"), ("friction", "friction"), ("armature", "armature"), ("effort", "effort"))
            if v[key] is not None
        }
        if v["range"]:
            stated.add("range")
        joints.append(
            JointDesc(
                j.name,
                j.kind,
                owner[up],
                robot.names[body],
                robot.names[up],
                axis / np.linalg.norm(axis),
                frame[:3, 3].copy(),
                j.lower,
                j.upper,
                damping=v["damping"] or 0.0,
                friction=v["friction"] or 0.0,
                armature=v["armature"] or 0.0,
                stiffness=None,  # unset: the simulators' default, 0 (``stated`` says which are unset)
                effort=v["effort"],
                velocity=v["velocity"],
                effort_how=v["effort_how"],
                stated=frozenset(stated),
            )
        )
        extensions[j.name] = {
            k: v[k] for k in ("drive", "custom_effort", "initial", "physx_friction", "velocity") if v[k] is not None
        }
    frames = {robot.names[b]: poses[b] for b in robot.bodies}
    frame_owner = {robot.names[b]: owner[b] for b in robot.bodies}
    frame_depth = {robot.names[b]: depth[b] for b in robot.bodies}
    kinds = {robot.names[b]: "link" for b in robot.bodies}
    for site, (body, local, kind) in robot.sites.items():
        frames[site], frame_owner[site], frame_depth[site], kinds[site] = poses[body] @ local, owner[body], depth[body] + 1, kind
    bodies, unset, no_inertial = [], [], set()
    for b in robot.bodies:
        inertial, why = _inertial(robot, b, poses[b], owner[b])
        if inertial is not None:
            bodies.append(inertial)
        else:
            no_inertial.add(robot.names[b])
        if why:
            unset.append(why)
    if unset:
        skipped.append(f"{len(unset)} bodies leave their inertial to the simulator: " + "; ".join(unset))
    desc = ModelDesc(
        "usd",
        "usd-core",
        joints,
        frames,
        frame_owner,
        frame_depth,
        bodies,
        skipped + robot.notes,
        kinds,
        _couplings(robot, joint_names),
        robot.gravity,
        extensions=extensions,
        held=held,
        no_inertial=no_inertial,
        native=robot,
    )
    return desc


F32 = 2.0**-23  # a single-precision number as written: within this share of its value (one unit in the last place)


class UsdPrecision(Precision):
    def describe(self, categories=None) -> str:
        return f"the {self.file} writes single-precision numbers (float, point3f, quatf: about 7 significant digits)"


def usd_precision(robot: UsdRobot) -> Precision:
    """What single precision (USD's ``float``, ``point3f``, ``quatf``) allows: per body, the rotation
    (four quaternion components per joint frame) and position its path from the root may be off
    by; limits, masses, inertias and centres of mass within one unit in the last place."""
    out = UsdPrecision("USD")
    held = next((j for j in robot.joints if robot.root in (j.body0, j.body1) and not (j.body0 and j.body1)), None)
    bound = {
        robot.root: (0.0, 0.0)
        if held is None
        # a root held to the world by a joint: its two frames
        else (8 * F32, math.sqrt(3) * F32 * float(np.linalg.norm(held.x0[:3, 3]) + np.linalg.norm(held.x1[:3, 3])))
    }
    for body in robot.bodies[1:]:
        j = robot.parent_joint[body]
        up = j.body0 if body == j.body1 else j.body1
        rot, pos = bound[up]
        bound[body] = (rot + 8 * F32, pos + math.sqrt(3) * F32 * float(np.linalg.norm(j.x0[:3, 3]) + np.linalg.norm(j.x1[:3, 3])))
    out.frames = {robot.names[b]: v for b, v in bound.items()}
    out.frames.update({site: bound[body] for site, (body, _, _) in robot.sites.items()})
    limits = [abs(x) for j in robot.joints for x in (j.lower, j.upper) if math.isfinite(x)]
    for category, value in (
        ("limit", max(limits, default=0.0) * F32),
        ("relative", 2 * F32),
        ("inertial_angle", 8 * F32),
        ("angle", 8 * F32),
        ("com", F32 * max((float(np.linalg.norm(t[:3, 3])) for t in robot.authored.values()), default=0.0)),
    ):
        out.note(category, value, "float32")
    return out


def pose_mismatches(robot: UsdRobot) -> list[tuple[str, float, float]]:
    """Bodies whose authored transform (``xformOp``s, where a simulator starts them) is not where their
    joint frames put them, each joint at its initial position (``PhysicsJointStateAPI``, else 0),
    beyond single precision: (body, position [m], rotation [rad]), the root's pose taken as given."""
    initial = {}
    for j in robot.joints:
        if j.kind in MOVABLE:
            kind = "angular" if j.kind == "revolute" else "linear"
            value = _number(robot.stage.GetPrimAtPath(j.path), f"state:{kind}:physics:position")
            if value is not None:
                initial[j.name] = np.array([value * (DEG if kind == "angular" else robot.meters)])
    composed = forward(robot, initial, 1)
    bound = usd_precision(robot).frames
    root_a, root_c = np.linalg.inv(robot.authored[robot.root]), np.linalg.inv(composed[robot.root][0])
    out = []
    for body in robot.bodies[1:]:
        a, c = root_a @ robot.authored[body], root_c @ composed[body][0]
        rot_b, pos_b = bound.get(robot.names[body], (0.0, 0.0))
        pos = float(np.linalg.norm(a[:3, 3] - c[:3, 3]))
        rot = float(np.arccos(np.clip((np.trace(a[:3, :3].T @ c[:3, :3]) - 1) / 2, -1, 1)))
        reach = float(np.linalg.norm(c[:3, 3]))
        if pos > 2 * (pos_b + rot_b * reach) + 1e-9 or rot > 2 * rot_b + 1e-9:
            orient = _get(robot.stage.GetPrimAtPath(body), "xformOp:orient")
            norm = 1.0 if orient is None else math.sqrt(orient.GetReal() ** 2 + sum(x * x for x in orient.GetImaginary()))
            why = (
                f" (its xformOp:orient is not a unit quaternion, |q| = {norm:.9g}: pxr reads it as a turn)"
                if abs(norm - 1) > 1e-9
                else ""
            )
            out.append((robot.names[body] + why, pos, rot))
    return out
