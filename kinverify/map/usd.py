"""A USD robot (``.usd``, ``.usda``, ``.usdc``) as pxr reads it, as a :class:`~kinverify.map.side.Side`.

Order: breadth-first from the articulation's root body (the tree UsdPhysics' parse gives,
:func:`kinverify.backends.usd_stage.read_robot`), a body's children in prim (stage traversal)
order. Breadth-first is PhysX's articulation order: Isaac Lab's ``ordering_resolvers`` emulates it
with a breadth-first walk ("breadth-first reproduces PhysX order and depth-first reproduces MJWarp
order"); the order among siblings is the prims' here, which is not established to be PhysX's.

Per joint, what :func:`kinverify.filemode.read.describe_usd.joint_values` reads, per radian: the
default position from ``PhysicsJointStateAPI`` (``state:angular:physics:position``, degrees), the
PD gains from ``PhysicsDriveAPI`` (``stiffness``/``damping``, per degree for an angular drive,
converted: k per degree is k·180/π per radian; an ``acceleration`` drive's gains are per unit of
inertia: not compared; a drive with stiffness and damping 0 is torque control, its gains live in the
controller, as an MJCF ``motor``'s: not compared), its ``maxForce`` as the effort, the velocity limit
(``physxJoint:maxJointVelocity``, else ``newton:velocityLimit``, degrees per second), armature
(``physxJoint:armature``, ``newton:armature``, ``mjc:armature``), friction (``newton:friction``,
``mjc:frictionloss``) and passive damping (``newton:damping``, ``mjc:damping``). A joint with a
drive or an ``MjcActuator`` prim (MuJoCo's USD schema, read in MuJoCo's units, per radian, as an
MJCF actuator: kp = −biasPrm[1]·gear², kd = −biasPrm[2]·gear², ``forceRange`` the effort where the
joint states none) is driven (when no joint has one, which joints are driven is left to the simulator's
configuration, as a URDF without transmissions leaves it: not compared). Mimic followers: ``NewtonMimicAPI`` and
``PhysxMimicJointAPI``.

Actuators (control order): the driven joints (a ``PhysicsDriveAPI`` or an ``MjcActuator`` on the joint), one
actuator each, in the articulation's joint order: a drive acts on its joint, and PhysX's control vector (Isaac
Lab's joint targets) follows its joint order. Newton's own order is not read: its ``add_usd`` orders joints
depth-first by default (``joint_ordering="dfs"``), siblings in its own joint list's order, which is not the
prims' (measured: a depth-first walk in prim order is Newton's on the shared Go2 and ANYmal C USDs, not on
Apollo's nor the LEAP hand's). The ``MjcActuator`` prims' own order (MuJoCo's) is not read."""

from __future__ import annotations

import math

from kinverify.backends.usd_stage import MOVABLE, read_robot
from kinverify.filemode.read.describe_usd import describe_usd, joint_values
from kinverify.map.side import Actuator, Follows, MapJoint, Side

EXPRESSES = frozenset({"default", "stiffness", "damping", "effort", "velocity", "armature", "friction", "joint_damping"})
ORDER = "breadth-first articulation order (PhysX's, per Isaac Lab; siblings in prim order)"


def articulation_order(robot) -> list:
    """The articulation's joints breadth-first from the root body, siblings in prim order."""
    rank = {str(p.GetPath()): i for i, p in enumerate(robot.stage.Traverse())}
    children: dict[str, list] = {}
    for body in robot.bodies[1:]:
        j = robot.parent_joint[body]
        up = j.body0 if body == j.body1 else j.body1
        children.setdefault(up, []).append((rank.get(j.path, math.inf), body, j))
    order, queue = [], [robot.root]
    while queue:
        body = queue.pop(0)
        for _, child, j in sorted(children.get(body, []), key=lambda c: (c[0], c[2].path)):
            order.append(j)
            queue.append(child)
    return order


def read_usd(path: str, options) -> Side:
    robot = read_robot(path, "USD")
    desc = describe_usd(robot)
    joints = []
    for uj in articulation_order(robot):
        if uj.kind not in MOVABLE:
            continue
        v = joint_values(robot, uj)
        kind = "angular" if uj.kind == "revolute" else "linear"
        j = MapJoint(uj.name, uj.kind, driven=v["drive"] is not None)
        if v["initial"] is not None:
            j.default, j.how["default"] = v["initial"], f"state:{kind}:physics:position"
        for ours, key, attribute in (
            ("velocity", "velocity", "physxJoint:maxJointVelocity / newton:velocityLimit"),
            ("armature", "armature", "physxJoint:armature / newton:armature / mjc:armature"),
            ("friction", "friction", "newton:friction / mjc:frictionloss"),
            ("joint_damping", "damping", "newton:damping / mjc:damping"),
        ):
            if v[key] is not None:
                setattr(j, ours, v[key])
                j.how[ours] = attribute
        if v["effort"] is not None and math.isfinite(v["effort"]):
            j.effort, j.how["effort"] = v["effort"], v["effort_how"]
        drive = v["drive"]
        if drive is not None:
            pre = f"drive:{kind}:physics:"
            if drive["type"] == "acceleration":
                j.apart["stiffness"] = j.apart["damping"] = f"{pre}type = acceleration: gains per unit of inertia"
                j.mode = "acceleration drive"
            elif not drive["stiffness"] and not drive["damping"]:  # torque control, as an MJCF motor
                j.apart["stiffness"] = j.apart["damping"] = (
                    f"{pre}stiffness and damping 0: a force (torque) drive, the "
                    "gains live in the controller (Isaac Lab's actuator model)"
                )
                j.mode = "force drive (torque)"
            else:
                j.stiffness, j.damping = drive["stiffness"] or 0.0, drive["damping"] or 0.0
                j.how["stiffness"], j.how["damping"] = (
                    f"{pre}stiffness" + (" (per degree, ×180/π)" if kind == "angular" else ""),
                    f"{pre}damping" + (" (per degree, ×180/π)" if kind == "angular" else ""),
                )
                j.mode = "position drive" if j.stiffness else "velocity drive"
            if drive.get("targetPosition"):
                j.how["target"] = f"{pre}targetPosition = {drive['targetPosition']:.6g} {'rad' if kind == 'angular' else 'm'}"
        joints.append(j)
    _mjc_actuators(robot, {uj.path: j for uj in robot.joints for j in joints if j.name == uj.name})
    for c in desc.couplings:
        follower = next((j for j in joints if j.name == c.follower), None)
        if follower is not None:
            follower.follows = Follows(c.leader, c.multiplier, c.offset, c.source)
    notes = [f"layer {a} is absent" for a in robot.absent] + list(robot.notes)
    # the actuators: the driven joints, in the articulation's order (a drive acts on its joint: PhysX's and
    # Newton's control vectors follow their joint order)
    actuators: list[Actuator] | None = [Actuator(j.name, (j.name,), j.mode or "drive") for j in joints if j.driven]
    if joints and not actuators:  # as a URDF without transmissions
        for j in joints:
            j.driven = None
        actuators = None
        notes.append(
            "no joint has a PhysicsDriveAPI: which joints are driven is the simulator's configuration "
            "(Isaac Lab's actuators), not compared"
        )
    if robot.floating:
        notes.append("floating base: the root body's 6 coordinates come before the joints in the simulator's state")
    return Side(path, path, "usd", ORDER, joints, actuators, EXPRESSES, desc, notes)


def _values(prim, name: str, size: int) -> list[float]:
    value = prim.GetAttribute(name).Get() if prim.GetAttribute(name) else None
    out = [float(x) for x in (value or [])][:size]
    return out + [0.0] * (size - len(out))


def _mjc_actuators(robot, by_path: dict) -> None:
    """``MjcActuator`` prims (MuJoCo's USD schema, what ``mujoco-usd-converter`` writes and Newton's
    MuJoCo solver reads), in MuJoCo's units (per radian): an affine-bias actuator on a joint
    drives it with kp = −biasPrm[1]·gear², kd = −biasPrm[2]·gear², as in an MJCF (several add)."""
    for prim in robot.stage.Traverse():
        if prim.GetTypeName() != "MjcActuator":
            continue
        rel = prim.GetRelationship("mjc:target")
        j = by_path.get(str(rel.GetTargets()[0])) if rel and rel.GetTargets() else None
        if j is None:
            continue
        name = prim.GetName()
        bias = str(prim.GetAttribute("mjc:biasType").Get() or "none") if prim.GetAttribute("mjc:biasType") else "none"
        gain = str(prim.GetAttribute("mjc:gainType").Get() or "fixed") if prim.GetAttribute("mjc:gainType") else "fixed"
        gear = _values(prim, "mjc:gear", 1)[0] if prim.GetAttribute("mjc:gear").HasAuthoredValue() else 1.0
        j.driven = True
        if bias == "affine" and gain == "fixed":
            b1, b2 = _values(prim, "mjc:biasPrm", 3)[1:]
            kind = "position" if b1 else "velocity" if b2 else "general"
            j.stiffness, j.damping = (j.stiffness or 0.0) - b1 * gear**2, (j.damping or 0.0) - b2 * gear**2
            j.how["stiffness"] = j.how["damping"] = f"MjcActuator {name}: −mjc:biasPrm[1:3] × gear²"
        else:
            kind = "motor (torque)" if bias == "none" and gain == "fixed" else "general"
            j.apart.setdefault("stiffness", f"MjcActuator {name} is a {kind}: the gains live in the controller")
            j.apart.setdefault("damping", j.apart["stiffness"])
        j.mode = "+".join(x for x in (j.mode, f"MjcActuator {kind}") if x)
        high = prim.GetAttribute("mjc:forceRange:max")
        if j.effort is None and high and high.HasAuthoredValue():
            low = prim.GetAttribute("mjc:forceRange:min").Get() or 0.0
            j.effort = max(abs(float(low)), abs(float(high.Get()))) * abs(gear)
            j.how["effort"] = f"MjcActuator {name}: mjc:forceRange × gear"
