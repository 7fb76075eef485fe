"""What NVIDIA's mujoco-usd-converter (0.8.0) makes of the MJCF kinverify generates for each
shipped spec (``tests/data/usd/``, made by ``tests/data/usd/make_mujoco_usd_converter.py``), read
with usd-core's UsdPhysics: the kinematics, limits in degrees and mass properties survive (to
single precision); damping (per degree), friction and armature become ``newton:`` joint attributes;
the effort limits survive only as each ``MjcActuator``'s ``mjc:ctrlRange``, with no UsdPhysics
drive, so the physics schema reads no force limit; the MJCF's zero-pose ``world_mount`` body (1 kg)
becomes the articulation's root, fixed to the world. A failure after a spec changed: run the script
again."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from kinverify import load_spec
from kinverify.model.kinematics import link_poses

pytest.importorskip("pxr")
from pxr import Usd, UsdPhysics  # noqa: E402

from tests.generate.test_usd import FLOAT, joint_poses, physics_of, rotation_of  # noqa: E402

DATA = Path("tests/data/usd")
MODELS = sorted(p.stem for p in Path("models").glob("*.toml"))


def test_every_shipped_spec_has_its_conversion():
    assert sorted(p.name for p in DATA.glob("*.usda")) == sorted(f"{m}_mujoco-usd-converter.usda" for m in MODELS)


@pytest.mark.parametrize("model", MODELS)
def test_what_the_converter_keeps_and_what_it_moves(model):
    spec = load_spec(f"models/{model}.toml")
    stage = Usd.Stage.Open(str(DATA / f"{model}_mujoco-usd-converter.usda"))
    assert stage.GetRootLayer().documentation.startswith(f"Converted from {model}.xml (kinverify generate models/{model}.toml)")
    parsed = physics_of(stage)
    prims = {p.GetName(): p for p in stage.Traverse()}
    paths = {name: str(prims[name].GetPath()) for name in spec.link_names}
    (root,) = parsed[UsdPhysics.ObjectType.Articulation]
    assert Path(root).name == (spec.base_link.name if spec.floating else "world_mount")
    poses, fk = joint_poses(parsed), link_poses(spec, spec.home())[0]
    for k, link in enumerate([spec.base_link] + [j.link for j in spec.joints]):
        np.testing.assert_allclose(poses[paths[link.name]], fk[k], atol=FLOAT, err_msg=link.name)
        i, mass = link.inertial, UsdPhysics.MassAPI(prims[link.name])
        np.testing.assert_allclose(mass.GetMassAttr().Get(), i.mass, rtol=FLOAT)
        np.testing.assert_allclose(np.array(mass.GetCenterOfMassAttr().Get()), i.com, atol=FLOAT)
        axes = rotation_of(mass.GetPrincipalAxesAttr().Get())
        np.testing.assert_allclose(
            axes @ np.diag(np.array(mass.GetDiagonalInertiaAttr().Get())) @ axes.T, i.matrix, atol=FLOAT * np.abs(i.matrix).max()
        )
    if not spec.floating:
        assert UsdPhysics.MassAPI(prims["world_mount"]).GetMassAttr().Get() == 1.0
    joints = {
        Path(p).name: d
        for kind in (UsdPhysics.ObjectType.RevoluteJoint, UsdPhysics.ObjectType.PrismaticJoint)
        for p, d in parsed.get(kind, {}).items()
    }
    assert sorted(joints) == sorted(spec.joint_names)
    actuators = {
        str(p.GetRelationship("mjc:target").GetTargets()[0]): p for p in stage.Traverse() if p.GetTypeName() == "MjcActuator"
    }
    for joint in spec.joints:
        d, prim = joints[joint.name], prims[joint.name]
        per = math.degrees(1.0) if joint.type == "revolute" else 1.0
        np.testing.assert_allclose(rotation_of(d.localPose1Orientation) @ np.eye(3)[int(d.axis)], joint.axis, atol=FLOAT)
        np.testing.assert_allclose(
            [d.limit.lower, d.limit.upper], [joint.limits.lower * per, joint.limits.upper * per], rtol=FLOAT
        )
        stated = {a: prim.GetAttribute(a).Get() or 0.0 for a in ("newton:damping", "newton:friction", "newton:armature")}
        np.testing.assert_allclose(list(stated.values()), [joint.damping / per, joint.friction, joint.armature], rtol=FLOAT)
        assert not d.drive.enabled and not prim.HasAttribute("newton:velocityLimit")  # no force limit, no speed limit
        motor = actuators[str(prim.GetPath())]
        assert (motor.GetAttribute("mjc:ctrlRange:min").Get(), motor.GetAttribute("mjc:ctrlRange:max").Get()) == (
            -joint.limits.effort,
            joint.limits.effort,
        )
