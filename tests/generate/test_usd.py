"""The generated OpenUSD, read back with usd-core's own UsdPhysics parser and schema API (not
kinverify's reader): the spec's joints, axes, limits in degrees, drives, masses, centres of mass,
inertias, and world poses at q = 0 composed from the joints' localPos/localRot equal to the
spec's analytic FK, for every shipped model and for random trees and floating bases. The schema
stores joint frames, limits and masses in single precision (tolerance ~1e-6 relative); the bodies'
and tools' double-precision xformOps agree with FK to 1e-12."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings

from kinverify import load_spec, spec_from_dict
from kinverify.backends import ModelSources, backend_info, names_reading
from kinverify.model.kinematics import frame_poses, link_poses
from kinverify.testing import strategies as kst

pxr = pytest.importorskip("pxr")
from pxr import Gf, Sdf, Usd, UsdGeom, UsdPhysics  # noqa: E402

from kinverify.generate.usd import generate_usd  # noqa: E402

MODELS = sorted(str(p) for p in Path("models").glob("*.toml"))
FLOAT = 2e-6  # single precision, relative, after a few compositions


def stage_of(text: str) -> Usd.Stage:
    stage = Usd.Stage.CreateInMemory()
    assert stage.GetRootLayer().ImportFromString(text)
    return stage


def physics_of(stage) -> dict:
    """UsdPhysics' parse of the stage: {object type: {prim path: description}}."""
    out = UsdPhysics.UsdPhysicsLoadStageFromPrimRange(stage, [Sdf.Path.absoluteRootPath])
    return {kind: {str(p): d for p, d in zip(paths, descs, strict=True)} for kind, (paths, descs) in out.items()}


def rotation_of(quat) -> np.ndarray:
    """Column-vector rotation matrix of a Gf quaternion (Gf's matrices act on row vectors). Not
    through ``Gf.Rotation``, whose angle (2·acos w) loses ~1e-6 rad of a float quaternion near 1."""
    return np.array(Gf.Matrix3d().SetRotate(Gf.Quatd(quat).GetNormalized())).T


def pose_of(pos, quat) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3], t[:3, 3] = rotation_of(quat), np.array(pos)
    return t


def joint_poses(parsed: dict) -> dict:
    """World pose of every rigid body at rest, composed from the joints alone: body1 = body0 · L0 ·
    L1⁻¹, from the world (a joint whose body0 is no rigid body) or from a body no joint moves (a
    floating base: its pose as parsed)."""
    bodies = parsed[UsdPhysics.ObjectType.RigidBody]
    joints = [
        d
        for kind in ("FixedJoint", "RevoluteJoint", "PrismaticJoint")
        for d in parsed.get(getattr(UsdPhysics.ObjectType, kind), {}).values()
    ]
    moved = {str(j.body1) for j in joints}
    poses = {p: pose_of(b.position, b.rotation) for p, b in bodies.items() if p not in moved}
    while len(poses) < len(bodies):
        grown = False
        for j in joints:
            parent = str(j.body0) if str(j.body0) in bodies else ""
            if str(j.body1) in poses or (parent and parent not in poses):
                continue
            local = pose_of(j.localPose0Position, j.localPose0Orientation) @ np.linalg.inv(
                pose_of(j.localPose1Position, j.localPose1Orientation)
            )
            poses[str(j.body1)] = (poses[parent] if parent else np.eye(4)) @ local
            grown = True
        assert grown, f"bodies no joint reaches: {sorted(set(bodies) - set(poses))}"
    return poses


def _world(stage, path: str) -> np.ndarray:
    return np.array(UsdGeom.XformCache().GetLocalToWorldTransform(stage.GetPrimAtPath(path))).T


def check_usd(spec) -> None:
    """Every stated value of ``spec`` in its generated USD, as usd-core reads it."""
    text = generate_usd(spec)
    stage = stage_of(text)
    assert UsdGeom.GetStageMetersPerUnit(stage) == 1.0 and UsdPhysics.GetStageKilogramsPerUnit(stage) == 1.0
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.z
    parsed = physics_of(stage)
    root = f"/{spec.name}"
    (articulation,) = parsed[UsdPhysics.ObjectType.Articulation].values()
    assert str(articulation.primPath) == root
    bodies = {f"{root}/{link}" for link in spec.link_names}
    assert set(parsed[UsdPhysics.ObjectType.RigidBody]) == bodies
    fixed = parsed.get(UsdPhysics.ObjectType.FixedJoint, {})
    assert len(fixed) == (0 if spec.floating else 1)  # only the weld to the world
    joints = {**parsed.get(UsdPhysics.ObjectType.RevoluteJoint, {}), **parsed.get(UsdPhysics.ObjectType.PrismaticJoint, {})}
    assert len(joints) == spec.dof
    links = [f"{root}/{link}" for link in spec.link_names]
    for i, (joint, parent) in enumerate(zip(spec.joints, spec.parent_indices, strict=True)):
        path = f"{links[parent]}/{joint.name}"
        d = joints[path]
        assert (type(d).__name__, str(d.body0), str(d.body1)) == (
            "RevoluteJointDesc" if joint.type == "revolute" else "PrismaticJointDesc",
            links[parent],
            links[i + 1],
        )
        token = np.eye(3)[int(d.axis)]  # UsdPhysics.Axis X, Y, Z = 0, 1, 2
        np.testing.assert_allclose(rotation_of(d.localPose1Orientation) @ token, joint.axis, atol=FLOAT)
        per = math.degrees(1.0) if joint.type == "revolute" else 1.0
        lim = joint.limits
        np.testing.assert_allclose(
            [d.limit.lower, d.limit.upper], [lim.lower * per, lim.upper * per], rtol=FLOAT, atol=1e-30
        )  # below float32 subnormals
        assert d.limit.enabled and d.drive.enabled
        assert (d.drive.stiffness, d.drive.damping) == (0.0, 0.0)
        np.testing.assert_allclose(d.drive.forceLimit, lim.effort, rtol=FLOAT)
        prim = stage.GetPrimAtPath(path)
        stated = {
            name: prim.GetAttribute(name).Get()
            for name in (
                "physxJoint:armature",
                "physxJoint:maxJointVelocity",
                "newton:armature",
                "newton:damping",
                "newton:friction",
                "newton:velocityLimit",
            )
        }
        np.testing.assert_allclose(
            list(stated.values()),
            [joint.armature, lim.velocity * per, joint.armature, joint.damping / per, joint.friction, lim.velocity * per],
            rtol=FLOAT,
        )
    for link, path in zip([spec.base_link] + [j.link for j in spec.joints], links, strict=True):
        mass = UsdPhysics.MassAPI(stage.GetPrimAtPath(path))
        i = link.inertial
        np.testing.assert_allclose(mass.GetMassAttr().Get(), i.mass, rtol=FLOAT)
        np.testing.assert_allclose(np.array(mass.GetCenterOfMassAttr().Get()), i.com, atol=FLOAT * max(1.0, *np.abs(i.com)))
        axes = rotation_of(mass.GetPrincipalAxesAttr().Get())
        tensor = axes @ np.diag(np.array(mass.GetDiagonalInertiaAttr().Get())) @ axes.T
        np.testing.assert_allclose(tensor, i.matrix, atol=FLOAT * np.abs(i.matrix).max())
    fk = link_poses(spec, spec.home())[0]
    composed = joint_poses(parsed)
    for k, path in enumerate(links):
        scale = max(1.0, float(np.abs(fk[k, :3, 3]).max()))
        np.testing.assert_allclose(composed[path], fk[k], atol=FLOAT * scale * (spec.dof + 1), err_msg=path)
        np.testing.assert_allclose(_world(stage, path), fk[k], atol=1e-12 * scale, err_msg=path)  # the double xformOps
    frames = frame_poses(spec, spec.home())[0]
    for k, tool in enumerate(spec.tools):
        path = f"{links[spec.link_index(tool.parent)]}/{tool.name}"
        scale = max(1.0, float(np.abs(frames[spec.dof + 1 + k, :3, 3]).max()))
        np.testing.assert_allclose(_world(stage, path), frames[spec.dof + 1 + k], atol=1e-12 * scale, err_msg=path)


@pytest.mark.parametrize("path", MODELS)
def test_shipped_models_read_back_with_usd_core(path):
    spec = load_spec(path)
    check_usd(spec)
    assert generate_usd(spec) == generate_usd(load_spec(path))  # deterministic


@settings(max_examples=15, deadline=None)
@given(kst.arm_specs(max_joints=5, trees=True, floating=True))
def test_random_specs_read_back_with_usd_core(spec):
    check_usd(spec)


def test_names_usd_cannot_take_become_identifiers_and_keep_theirs():
    spec = spec_from_dict(
        {
            "name": "two.arms",
            "base": {"link": {"name": "base-link"}},
            "joints": [
                {
                    "name": "j.1",
                    "type": "revolute",
                    "axis": [0, -1, 0],
                    "xyz": [0, 0, 0.1],
                    "limits": {"lower": -1, "upper": 1, "unit": "rad"},
                },
                {
                    "name": "j_1",
                    "type": "prismatic",
                    "axis": [0.6, 0.8, 0],
                    "xyz": [0, 0, 0.1],
                    "limits": {"lower": 0, "upper": 0.2},
                },
            ],
            "tools": [{"name": "tip-0", "xyz": [0.1, 0, 0]}],
        }
    )
    stage = stage_of(generate_usd(spec))
    shown = {prim.GetName(): (prim.GetTypeName(), prim.GetDisplayName()) for prim in stage.Traverse()}
    assert shown["two_arms"] == ("Xform", "two.arms") and shown["base_link"] == ("Xform", "base-link")
    assert shown["j_1_1"] == ("PhysicsRevoluteJoint", "j.1") and shown["j_1"] == ("PhysicsPrismaticJoint", "")
    assert shown["tip_0"] == ("Xform", "tip-0")
    check_usd_names = [p for p in stage.Traverse() if p.IsA(UsdPhysics.Joint)]
    assert len(check_usd_names) == 3  # the weld, j.1, j_1
    sources = ModelSources.from_spec(spec)
    assert sources.usd_joint_names == ("j_1_1", "j_1")
    assert sources.usd_frames[0] == "base_link" and sources.usd_frames[-1] == "tip_0"


def test_model_sources_carry_the_usd_and_the_registry_names_its_backend():
    spec = load_spec("models/arm3.toml")
    sources = ModelSources.from_spec(spec)
    assert sources.usd == generate_usd(spec) and sources.usd_joint_names is None and sources.usd_frames is None
    assert names_reading("usd") == ("usd", "newton-usd")  # Newton's with the newton extra
    info = backend_info("usd")
    assert (info.source, info.extra, info.cls) == ("usd", "usd", "UsdBackend")
    # the adapter module may be absent: the registry then treats it as an extra not installed
    assert info.available or "pip install 'kinverify[usd]'" in info.reason
