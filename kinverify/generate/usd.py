"""OpenUSD text (``.usda``) from a spec, authored with usd-core's ``UsdPhysics`` schema API.

Layout (Isaac Lab's flat articulation): the root ``Xform`` ``/<name>`` carries
``PhysicsArticulationRootAPI``; every link is a rigid body directly under it
(``/<name>/<link>``, ``PhysicsRigidBodyAPI`` + ``PhysicsMassAPI``) placed by double-precision
``xformOp:translate`` / ``xformOp:orient`` at its world pose at the home configuration; each
joint is a ``PhysicsRevoluteJoint`` / ``PhysicsPrismaticJoint`` under its parent link
(``body0`` the parent, ``body1`` the child); each tool is a plain ``Xform`` under its link. A
fixed base is the ``PhysicsFixedJoint`` ``world_to_base`` (no ``body0``: the world) at the base
origin; a floating base has no joint to the world. Stage: ``metersPerUnit`` 1,
``kilogramsPerUnit`` 1, ``upAxis`` Z, and a ``/physicsScene`` with the spec's gravity.

Joint frames: UsdPhysics axes are the tokens X, Y, Z of the joint frame, so a joint frame is the
child link frame rotated to put the spec's axis on the token axis (the one nearest to it; the
rotation is exact when the axis is ±X, ±Y or ±Z): ``localPos1`` 0, ``localRot1`` that rotation,
``localPos0`` / ``localRot0`` the joint origin composed with it. The schema stores these in single
precision (``point3f``, ``quatf``), as it does limits and masses: read back they agree with the
spec to about 1e-7 relative; the body ``xformOp`` poses are double.

Values and units (angles in degrees wherever the schemas say so):

- ``physics:lowerLimit`` / ``upperLimit``: degrees (revolute) or metres (prismatic);
- ``PhysicsDriveAPI:angular`` / ``:linear``: a ``force`` drive, stiffness 0 and damping 0 (torque
  or force control, as the MJCF's ``motor`` actuators), ``maxForce`` = the effort limit [N·m, N];
- ``PhysicsMassAPI``: mass [kg], ``centerOfMass`` [m], ``diagonalInertia`` [kg·m²] and
  ``principalAxes`` (the inertia tensor's eigenvectors in the link frame);
- ``PhysxJointAPI`` attributes (Isaac Sim / Isaac Lab's names, authored without the PhysX schema
  plugin): ``physxJoint:armature`` [kg·m² or kg], ``physxJoint:maxJointVelocity`` [deg/s or
  m/s]. ``physxJoint:jointFriction`` is not written: it is a unitless PhysX coefficient, not the
  spec's Coulomb friction;
- ``NewtonJointAPI`` attributes (the names NVIDIA's ``urdf-usd-converter`` writes):
  ``newton:damping`` [N·m·s/deg or N·s/m], ``newton:friction`` [N·m or N], ``newton:armature``
  and ``newton:velocityLimit`` (the same values as the two ``physxJoint`` ones).

The arm has no collision shapes (``PhysicsCollisionAPI``), like the MJCF's contype 0: shapes are
visual ``UsdGeom`` capsules, cylinders, spheres and cubes. Prim names are kinverify's names; a name
USD cannot take (``.`` or ``-``) becomes a valid identifier
(:func:`~kinverify.generate.usd_names.prim_names`) and keeps the original as its ``displayName``.
"""

from __future__ import annotations

import math

import numpy as np
from pxr import Gf, Sdf, Usd, UsdGeom, UsdPhysics

from kinverify.generate._fmt import PALETTE, segment_placement
from kinverify.generate.usd_names import BASE_JOINT, identifier, prim_names, unique
from kinverify.model.kinematics import link_poses
from kinverify.model.spec import ArmSpec, Geometry, Joint, Link
from kinverify.model.transforms import make_transform, matrix_to_quat, rpy_to_matrix

AXES = ("X", "Y", "Z")
# 180° turns taking +X, +Y, +Z to minus themselves (quaternions with components 0 and 1: exact)
FLIPS = (np.diag([-1.0, -1.0, 1.0]), np.diag([-1.0, -1.0, 1.0]), np.diag([1.0, -1.0, -1.0]))


def axis_frame(axis) -> tuple[str, np.ndarray]:
    """The token (X, Y or Z) and the rotation ``R`` (child link frame <- joint frame) with
    ``R @ e_token = axis``: the nearest token axis, flipped by a half turn when the axis points
    the other way, then turned onto the axis by the smallest rotation (≤ 54.8°, well conditioned)."""
    a = np.asarray(axis, dtype=float)
    k = int(np.argmax(np.abs(a)))
    flip = np.eye(3) if a[k] > 0 else FLIPS[k]
    b = flip[:, k]  # ±e_k
    v, c = np.cross(b, a), float(b @ a)
    vx = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    turn = np.eye(3) + vx + vx @ vx / (1.0 + c)
    return AXES[k], turn @ flip


def principal_inertia(inertia: tuple) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments and the rotation whose columns are the principal axes in the link frame
    (identity for a diagonal tensor; otherwise eigenvectors with their largest component
    positive, right-handed) of ``(ixx, iyy, izz, ixy, ixz, iyz)``."""
    ixx, iyy, izz, ixy, ixz, iyz = inertia
    if ixy == ixz == iyz == 0.0:
        return np.array([ixx, iyy, izz]), np.eye(3)
    moments, axes = np.linalg.eigh(np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]))
    for j in range(3):
        if axes[int(np.argmax(np.abs(axes[:, j]))), j] < 0:
            axes[:, j] *= -1.0
    if np.linalg.det(axes) < 0:
        axes[:, 2] *= -1.0
    return moments, axes


def _vec3d(v) -> Gf.Vec3d:
    return Gf.Vec3d(*(float(x) + 0.0 for x in v))  # + 0.0: no -0 in the text


def _vec3f(v) -> Gf.Vec3f:
    return Gf.Vec3f(*(float(x) + 0.0 for x in v))


def _quat(rotation: np.ndarray, cls=Gf.Quatf):
    w, x, y, z = (float(c) + 0.0 for c in matrix_to_quat(rotation))
    return cls(w, x, y, z)


def _place(xformable, transform: np.ndarray, scale=None) -> None:
    """Double-precision translate and orient ops (and a scale) for a local transform."""
    xformable.AddTranslateOp(UsdGeom.XformOp.PrecisionDouble).Set(_vec3d(transform[:3, 3]))
    xformable.AddOrientOp(UsdGeom.XformOp.PrecisionDouble).Set(_quat(transform[:3, :3], Gf.Quatd))
    if scale is not None:
        xformable.AddScaleOp(UsdGeom.XformOp.PrecisionDouble).Set(_vec3d(scale))


def _shape(stage, path: Sdf.Path, geom: Geometry, index: int) -> None:
    """A visual shape (no collision API) in its link, coloured as the MJCF's."""
    scale = None
    if geom.shape in ("capsule", "cylinder"):
        centre, rpy, length = segment_placement(geom.fromto)
        gprim = (UsdGeom.Capsule if geom.shape == "capsule" else UsdGeom.Cylinder).Define(stage, path)
        gprim.CreateAxisAttr(UsdGeom.Tokens.z)
        gprim.CreateHeightAttr(length)
        gprim.CreateRadiusAttr(geom.radius)
        placement = make_transform(rpy_to_matrix(rpy), centre)
    elif geom.shape == "sphere":
        gprim = UsdGeom.Sphere.Define(stage, path)
        gprim.CreateRadiusAttr(geom.radius)
        placement = make_transform(np.eye(3), geom.pos)
    else:  # a unit cube scaled to the box's edges
        gprim = UsdGeom.Cube.Define(stage, path)
        gprim.CreateSizeAttr(1.0)
        placement, scale = make_transform(np.eye(3), geom.pos), geom.size
    _place(gprim, placement, scale)
    gprim.CreateExtentAttr(UsdGeom.Boundable.ComputeExtentFromPlugins(gprim, Usd.TimeCode.Default()))
    rgb = [float(c) for c in PALETTE[index % len(PALETTE)].split()[:3]]
    gprim.CreateDisplayColorAttr([Gf.Vec3f(*rgb)])


def _body(stage, path: Sdf.Path, link: Link, pose: np.ndarray, index: int, shape_name: str) -> None:
    xform = UsdGeom.Xform.Define(stage, path)
    _place(xform, pose)
    UsdPhysics.RigidBodyAPI.Apply(xform.GetPrim())
    mass = UsdPhysics.MassAPI.Apply(xform.GetPrim())
    i = link.inertial
    moments, axes = principal_inertia(i.inertia)
    mass.CreateMassAttr(i.mass)
    mass.CreateCenterOfMassAttr(_vec3f(i.com))
    mass.CreateDiagonalInertiaAttr(_vec3f(moments))
    mass.CreatePrincipalAxesAttr(_quat(axes))
    if link.geometry is not None:
        _shape(stage, path.AppendChild(shape_name), link.geometry, index)


def _set(prim, name: str, value: float) -> None:
    prim.CreateAttribute(name, Sdf.ValueTypeNames.Float, False).Set(float(value))


def _joint(stage, path: Sdf.Path, joint: Joint, parent: Sdf.Path, child: Sdf.Path) -> None:
    revolute = joint.type == "revolute"
    token, rotation = axis_frame(joint.axis)
    usd = (UsdPhysics.RevoluteJoint if revolute else UsdPhysics.PrismaticJoint).Define(stage, path)
    usd.CreateAxisAttr(token)
    usd.CreateBody0Rel().SetTargets([parent])
    usd.CreateBody1Rel().SetTargets([child])
    origin = joint.origin.transform
    usd.CreateLocalPos0Attr(_vec3f(origin[:3, 3]))
    usd.CreateLocalRot0Attr(_quat(origin[:3, :3] @ rotation))
    usd.CreateLocalPos1Attr(Gf.Vec3f(0.0, 0.0, 0.0))
    usd.CreateLocalRot1Attr(_quat(rotation))
    per = math.degrees(1.0) if revolute else 1.0  # degrees per radian, or metres per metre
    lim = joint.limits
    usd.CreateLowerLimitAttr(lim.lower * per)
    usd.CreateUpperLimitAttr(lim.upper * per)
    prim = usd.GetPrim()
    drive = UsdPhysics.DriveAPI.Apply(prim, "angular" if revolute else "linear")
    drive.CreateTypeAttr(UsdPhysics.Tokens.force)
    drive.CreateStiffnessAttr(0.0)
    drive.CreateDampingAttr(0.0)
    drive.CreateMaxForceAttr(lim.effort)
    prim.AddAppliedSchema("PhysxJointAPI")
    _set(prim, "physxJoint:armature", joint.armature)
    _set(prim, "physxJoint:maxJointVelocity", lim.velocity * per)
    prim.AddAppliedSchema("NewtonJointAPI")
    _set(prim, "newton:armature", joint.armature)
    _set(prim, "newton:damping", joint.damping / per)  # N·m·s/deg: per degree per second
    _set(prim, "newton:friction", joint.friction)
    _set(prim, "newton:velocityLimit", lim.velocity * per)


def _display(stage, path: Sdf.Path, name: str) -> None:
    if path.name != name:
        stage.GetPrimAtPath(path).SetDisplayName(name)


def generate_usd(spec: ArmSpec) -> str:
    """The ``.usda`` text of ``spec``; the same spec always gives the same bytes."""
    stage = Usd.Stage.CreateInMemory()
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    UsdPhysics.SetStageKilogramsPerUnit(stage, 1.0)
    stage.GetRootLayer().documentation = (
        f"Generated by kinverify from the spec {spec.name!r}. Units: m, kg, s; "
        "angles in degrees where UsdPhysics says so. Same names as the URDF and MJCF."
    )
    root = UsdGeom.Xform.Define(stage, Sdf.Path.absoluteRootPath.AppendChild(identifier(spec.name)))
    stage.SetDefaultPrim(root.GetPrim())
    _display(stage, root.GetPath(), spec.name)
    UsdPhysics.ArticulationRootAPI.Apply(root.GetPrim())
    g = np.asarray(spec.gravity)
    scene = UsdPhysics.Scene.Define(stage, "/physicsScene")
    norm = float(np.linalg.norm(g))
    scene.CreateGravityDirectionAttr(_vec3f(g / norm if norm > 0 else (0.0, 0.0, -1.0)))
    scene.CreateGravityMagnitudeAttr(norm)

    names = prim_names(spec)
    taken = set(names.values())
    links = [spec.base_link] + [j.link for j in spec.joints]
    paths = [root.GetPath().AppendChild(names[link.name]) for link in links]
    poses = link_poses(spec, spec.home())[0]
    for index, (link, path, pose) in enumerate(zip(links, paths, poses, strict=True)):
        _body(stage, path, link, pose, index, unique(identifier(f"{link.name}_visual"), taken))
        _display(stage, path, link.name)
    if not spec.floating:
        weld = UsdPhysics.FixedJoint.Define(stage, root.GetPath().AppendChild(names[BASE_JOINT]))
        weld.CreateBody1Rel().SetTargets([paths[0]])
        weld.CreateLocalPos0Attr(_vec3f(spec.base_origin.xyz))
        weld.CreateLocalRot0Attr(_quat(rpy_to_matrix(spec.base_origin.rpy)))
        weld.CreateLocalPos1Attr(Gf.Vec3f(0.0, 0.0, 0.0))
        weld.CreateLocalRot1Attr(Gf.Quatf(1.0, 0.0, 0.0, 0.0))
    for i, (joint, parent) in enumerate(zip(spec.joints, spec.parent_indices, strict=True)):
        path = paths[parent].AppendChild(names[joint.name])
        _joint(stage, path, joint, paths[parent], paths[i + 1])
        _display(stage, path, joint.name)
    for tool in spec.tools:
        path = paths[spec.link_index(tool.parent)].AppendChild(names[tool.name])
        _place(UsdGeom.Xform.Define(stage, path), tool.origin.transform)
        _display(stage, path, tool.name)
    return stage.GetRootLayer().ExportToString()
