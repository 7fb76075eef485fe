"""Opening a USD robot safely with ``usd-core`` (pxr), and its articulation as plain arrays.

The file is opened by :func:`kinverify.backends.usd_layers.open_stage` (every layer checked before
pxr opens it; absent layers tolerated and named).

The physics is read by ``UsdPhysics.UsdPhysicsLoadStageFromPrimRange`` (the schema's own parser:
each joint's bodies resolved to rigid bodies and its local frames expressed in them), then
arranged as a tree from the articulation's root body. Lengths are scaled by ``metersPerUnit``, a
Y-up stage is turned Z-up, angles are radians (USD writes degrees).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from kinverify.backends.usd_layers import open_stage, quiet_stderr
from kinverify.errors import InputError
from kinverify.pipeline.limits import MAX_JOINTS, MAX_LINKS

try:  # the optional extra "usd" (usd-core)
    from pxr import Gf, Sdf, UsdGeom, UsdPhysics
except ImportError:  # pragma: no cover - exercised without the extra (open_stage says so)
    Gf = Sdf = UsdGeom = UsdPhysics = None

MOVABLE = ("revolute", "prismatic")
KINDS = {
    "RevoluteJoint": "revolute",
    "PrismaticJoint": "prismatic",
    "FixedJoint": "fixed",
    "SphericalJoint": "spherical",
    "D6Joint": "d6",
    "DistanceJoint": "distance",
    "CustomJoint": "custom",
}
Y_UP = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]])  # +90° about x: a Y-up world's y is z


@dataclass
class UsdJoint:
    name: str  # the joint prim's name (its path when two joints share a name)
    path: str
    kind: str  # "revolute", "prismatic", "fixed", "spherical", "d6", ...
    body0: str  # rigid body path, "" for the world
    body1: str
    x0: np.ndarray  # joint frame in body0 (4x4, metres)
    x1: np.ndarray  # joint frame in body1
    axis: int = 0  # 0, 1, 2: X, Y, Z of the joint frame
    lower: float = -math.inf  # rad or m
    upper: float = math.inf
    excluded: bool = False  # physics:excludeFromArticulation (a loop closure)


@dataclass
class UsdRobot:
    """A USD articulation: bodies (rigid body paths) in tree order from the root, each with the
    joint holding it to its parent (``parent_joint``, oriented: ``flipped`` when the tree runs from
    body1 to body0); ``root_pose``: the root body's world pose at q = 0 (identity when it floats)."""

    path: str
    stage: Any  # Usd.Stage (pxr is untyped)
    bodies: list[str]
    names: dict[str, str]  # body path -> name
    joints: list[UsdJoint]
    parent_joint: dict[str, UsdJoint]
    flipped: set[str]  # joint paths the tree runs through from body1 to body0
    root: str
    floating: bool
    root_pose: np.ndarray
    authored: dict[str, np.ndarray]  # body path -> its xform's world pose (metres, Z-up)
    meters: float = 1.0
    kilograms: float = 1.0
    up: str = "Z"
    gravity: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -9.81]))
    absent: list[str] = field(default_factory=list)  # layers named but absent
    # frames on bodies: prims with a site schema ("site") and plain Xforms ("link": a URDF link with no
    # mass the converter keeps as an Xform, a visual's holder), name -> (body path, pose in the body, kind)
    sites: dict[str, tuple[str, np.ndarray, str]] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    layers: list[Any] = field(default_factory=list, repr=False, compare=False)  # the opened layers, kept alive with the stage

    def joint(self, name: str) -> UsdJoint:
        return next(j for j in self.joints if j.name == name)


def applied_schemas(prim) -> list[str]:
    """The API schemas a prim's ``apiSchemas`` metadata applies, registered or not (pxr's
    ``GetAppliedSchemas`` leaves out schemas it has no definition of: ``MjcSiteAPI``, ``NewtonMimicAPI``,
    ``PhysxMimicJointAPI:rotX`` without their plugins)."""
    listop = prim.GetMetadata("apiSchemas")
    return [str(s) for s in listop.GetAddedOrExplicitItems()] if listop else []


def f32(x) -> float:
    """A single-precision value as the decimal it was written as (``0.1575``, not 0.15749999880790710):
    the shortest decimal that reads back as the same float32."""
    return float(str(np.float32(x)))


def frame_matrix(pos, rot, meters: float) -> np.ndarray:
    """4x4 from a position (stage units; float32 components as written) and a GfQuat (w, x, y, z)."""
    t = np.eye(4)
    # normalized first: GfRotation takes the angle from the real part as written, so a quaternion a rounding
    # away from unit length near the identity turns by ~sqrt(rounding) (|q| = 1 - 2e-7: 0.07°)
    t[:3, :3] = np.array(Gf.Matrix3d(Gf.Rotation(Gf.Quatd(rot).GetNormalized())), dtype=float).T  # row-vector Gf: transposed
    t[:3, 3] = np.array([f32(x) for x in pos], dtype=float) * meters
    return t


def _finite(label: str, prim: str, what: str, values) -> None:
    if not np.all(np.isfinite(np.asarray(values, dtype=float))):
        raise InputError(f"{label}: prim {prim}: {what} is not a finite number ({tuple(values)})")


def read_robot(path: str, label: str = "--usd") -> UsdRobot:
    """The articulation of the USD file ``path`` (see the module docstring)."""
    stage, absent, layers = open_stage(path, label)
    if not stage.GetPseudoRoot().GetChildren():
        raise InputError(f"{label}: {path}: no prim in the stage")
    meters = float(UsdGeom.GetStageMetersPerUnit(stage))
    kilograms = float(UsdPhysics.GetStageKilogramsPerUnit(stage))
    up = str(UsdGeom.GetStageUpAxis(stage))
    if not (meters > 0 and math.isfinite(meters) and kilograms > 0 and math.isfinite(kilograms)):
        raise InputError(f"{label}: {path}: metersPerUnit {meters} / kilogramsPerUnit {kilograms} must be positive numbers")
    world = Y_UP if up == "Y" else np.eye(4)
    with quiet_stderr():
        load = getattr(UsdPhysics, "UsdPhysicsLoadStageFromPrimRange", None) or UsdPhysics.LoadUsdPhysicsFromRange  # < 26
        parsed = load(stage, [Sdf.Path("/")])
    types = UsdPhysics.ObjectType
    objects = {name: parsed.get(getattr(types, name), ([], [])) for name in ("Articulation", "RigidBody", "Scene", *KINDS)}
    articulations = objects["Articulation"][1]
    if not articulations:
        raise InputError(
            f"{label}: {path}: no articulation (no prim has PhysicsArticulationRootAPI): kinverify compares articulated robots"
        )
    art = articulations[0]
    bodies_all = {str(p): d for p, d in zip(*objects["RigidBody"], strict=True)}
    joints: list[UsdJoint] = []
    names: dict[str, int] = {}
    for kind_name, kind in KINDS.items():
        for p, d in zip(*objects[kind_name], strict=True):
            prim = str(p)
            rel = {0: d.rel0, 1: d.rel1}
            for side, body in ((0, d.body0), (1, d.body1)):
                target = str(rel[side])
                if target and not stage.GetPrimAtPath(target).IsValid():
                    raise InputError(f"{label}: {path}: joint {prim}: physics:body{side} names {target}, which does not exist")
                if str(body) and str(body) not in bodies_all:
                    raise InputError(f"{label}: {path}: joint {prim}: physics:body{side} {body} is not a rigid body")
            _finite(
                label,
                prim,
                "physics:localPos0/localRot0/localPos1/localRot1",
                [
                    *d.localPose0Position,
                    *d.localPose1Position,
                    *d.localPose0Orientation.imaginary,
                    d.localPose0Orientation.real,
                    *d.localPose1Orientation.imaginary,
                    d.localPose1Orientation.real,
                ],
            )
            j = UsdJoint(
                p.name,
                prim,
                kind,
                str(d.body0),
                str(d.body1),
                frame_matrix(d.localPose0Position, d.localPose0Orientation, meters),
                frame_matrix(d.localPose1Position, d.localPose1Orientation, meters),
                excluded=bool(d.excludeFromArticulation),
            )
            if kind in MOVABLE:
                j.axis = {"X": 0, "Y": 1, "Z": 2}.get(str(d.axis), 0)
                if d.limit.enabled:
                    scale = math.pi / 180 if kind == "revolute" else meters
                    lo, up_ = f32(d.limit.lower), f32(d.limit.upper)
                    if math.isnan(lo) or math.isnan(up_):
                        raise InputError(f"{label}: {path}: joint {prim}: physics:lowerLimit/upperLimit is NaN")
                    j.lower, j.upper = lo * scale if lo > -1e37 else -math.inf, up_ * scale if up_ < 1e37 else math.inf
            joints.append(j)
            names[j.name] = names.get(j.name, 0) + 1
    for j in joints:
        if names[j.name] > 1:
            j.name = j.path
    if len([j for j in joints if j.kind in MOVABLE]) > MAX_JOINTS or len(bodies_all) > MAX_LINKS:
        raise InputError(
            f"{label}: {path} has {len(joints)} joints and {len(bodies_all)} rigid bodies, above the "
            f"{MAX_JOINTS} movable joints and {MAX_LINKS} bodies kinverify compares (see docs/robustness.md)"
        )
    robot = _tree(path, label, stage, art, bodies_all, [j for j in joints if j.kind != "distance"], world)
    robot.meters, robot.kilograms, robot.up, robot.absent = meters, kilograms, up, absent
    robot.notes += [
        f"the stage states no {key}: USD's fallback, {value}, is used"
        for key, value in (("upAxis", up), ("metersPerUnit", meters))
        if not stage.HasAuthoredMetadata(key)
    ]
    robot.authored = {
        b: world @ frame_matrix(np.array(bodies_all[b].position), bodies_all[b].rotation, meters) for b in robot.bodies
    }
    scenes = objects["Scene"][1]
    if scenes:
        g = np.array(scenes[0].gravityDirection, dtype=float)
        mag = f32(scenes[0].gravityMagnitude)
        g = g if np.linalg.norm(g) > 0 else -np.eye(3)[1 if up == "Y" else 2]  # unset: down the stage's up axis
        mag = mag * meters if math.isfinite(mag) and mag >= 0 else 9.81  # -inf: the earth's gravity
        robot.gravity = world[:3, :3] @ (g / np.linalg.norm(g)) * mag
    robot.layers = layers  # kept alive with the stage
    robot.sites = _sites(stage, robot, world)
    return robot


def _tree(path, label, stage, art, bodies_all: dict, joints: list[UsdJoint], world: np.ndarray) -> UsdRobot:
    """The articulation as a tree from its root body, every body reached once (a loop is refused)."""
    members = {str(b) for b in art.articulatedBodies} or set(bodies_all)
    tree_joints = [j for j in joints if not j.excluded and (j.body0 in members or j.body1 in members)]
    to_world = [j for j in tree_joints if not j.body0 or not j.body1]
    roots = [str(p) for p in art.rootPrims]
    root: str | None
    if to_world:
        root = to_world[0].body1 or to_world[0].body0
    else:  # floating: the tree's root is the body no joint moves (never a joint's body1; PhysX's own root
        # choice, art.rootPrims, may be another body, such as the one with the most joints); else the root
        # the parse names, else any body a joint holds
        children = {j.body1 for j in tree_joints}
        held = children | {j.body0 for j in tree_joints}
        root = next(
            (b for b in sorted(members) if b in held and b not in children),
            next(
                (r for r in roots if r in bodies_all),
                next((b for b in sorted(members) if b in held), next(iter(sorted(members)), None)),
            ),
        )
    if root is None:
        raise InputError(f"{label}: {path}: articulation {art.primPath} has no rigid body")
    order, parent_joint, flipped, queue = [root], {}, set(), [root]
    used = set(id(j) for j in to_world[:1])
    while queue:
        body = queue.pop(0)
        for j in tree_joints:
            if id(j) in used or body not in (j.body0, j.body1) or not j.body0 or not j.body1:
                continue
            other = j.body1 if j.body0 == body else j.body0
            used.add(id(j))
            if other in parent_joint or other == root:
                raise InputError(
                    f"{label}: {path}: joint {j.path} closes a loop (body {other} is reached twice); mark "
                    "the loop-closing joint physics:excludeFromArticulation = true"
                )
            parent_joint[other] = j
            if other == j.body0:
                flipped.add(j.path)
            order.append(other)
            queue.append(other)
    extra = [j for j in to_world[1:]]
    notes = [f"joint {j.path} also holds body {j.body1 or j.body0} to the world: not compared (the tree holds it)" for j in extra]
    pose = np.eye(4)
    floating = not to_world
    if to_world:
        j = to_world[0]
        pose = j.x0 @ np.linalg.inv(j.x1) if j.body1 == root else j.x1 @ np.linalg.inv(j.x0)
        if j.kind != "fixed":
            notes.append(f"joint {j.path} ({j.kind}) holds the root body {root} to the world: held at 0")
    names: dict[str, str] = {}
    for b in order:
        name = b.rsplit("/", 1)[-1]
        names[b] = name if name not in names.values() else b
    return UsdRobot(
        path,
        stage,
        order,
        names,
        [j for j in joints if id(j) in used or j in to_world[:1]],
        parent_joint,
        flipped,
        root,
        floating,
        world @ pose,
        {},
        notes=notes,
    )


def motion(kind: str, axis: int, q: np.ndarray) -> np.ndarray:
    """(N, 4, 4): a joint's motion by ``q`` (rad or m) about or along its frame's axis."""
    out = np.tile(np.eye(4), (len(q), 1, 1))
    if kind == "prismatic":
        out[:, axis, 3] = q
    elif kind == "revolute":
        a, b = (axis + 1) % 3, (axis + 2) % 3
        c, s = np.cos(q), np.sin(q)
        out[:, a, a], out[:, a, b], out[:, b, a], out[:, b, b] = c, -s, s, c
    return out


def forward(robot: UsdRobot, values: dict[str, np.ndarray], n: int) -> dict[str, np.ndarray]:
    """World poses (N, 4, 4) of every body, each movable joint at ``values[name]`` (rad or m; absent: 0):
    ``T_body1 = T_body0 · localPose0 · motion(q) · localPose1⁻¹``."""
    out = {robot.root: np.tile(robot.root_pose, (n, 1, 1))}
    zero = np.zeros(n)
    for body in robot.bodies[1:]:
        j = robot.parent_joint[body]
        m = motion(j.kind, j.axis, np.asarray(values.get(j.name, zero), dtype=float))
        if j.path in robot.flipped:  # the tree runs body1 -> body0
            out[body] = out[j.body1] @ j.x1 @ np.linalg.inv(m) @ np.linalg.inv(j.x0)
        else:
            out[body] = out[j.body0] @ j.x0 @ m @ np.linalg.inv(j.x1)
    return out


def _sites(stage, robot: UsdRobot, world: np.ndarray) -> dict[str, tuple[str, np.ndarray, str]]:
    """Prims with a site schema (``MjcSiteAPI``, ``NewtonSiteAPI``) and plain Xforms under a body (or, the
    root held to the world, under no body: fixed in the world): their pose in it. A name taken by a
    body is left out, and so is a name two such prims share (which one a file means is not known)."""
    out: dict[str, tuple[str, np.ndarray, str]]
    cache, out, seen = UsdGeom.XformCache(), {}, set()
    members = set(robot.bodies)
    for prim in stage.Traverse():
        site = any("SiteAPI" in s for s in applied_schemas(prim))
        if not site and (prim.GetTypeName() != "Xform" or str(prim.GetPath()) in members or prim.HasAPI(UsdPhysics.RigidBodyAPI)):
            continue
        body = prim.GetParent()
        while body and body.IsValid() and str(body.GetPath()) not in members:
            body = body.GetParent()
        name = prim.GetName()
        if name in seen:
            out.pop(name, None)
            continue
        seen.add(name)
        if name in robot.names.values():
            continue
        if body and body.IsValid():
            rel = np.array(cache.ComputeRelativeTransform(prim, body)[0], dtype=float).T
            rel[:3, 3] *= robot.meters
            out[name] = (str(body.GetPath()), rel, "site" if site else "link")
        elif not robot.floating:
            pose = np.array(cache.GetLocalToWorldTransform(prim), dtype=float).T
            pose[:3, 3] *= robot.meters
            pose = world @ pose
            out[name] = (robot.root, np.linalg.inv(robot.authored[robot.root]) @ pose, "link")
    return out
