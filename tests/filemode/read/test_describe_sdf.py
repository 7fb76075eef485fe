"""Drake's reading of an SDFormat file: each joint's damping and armature (Drake's reflected
inertia) as the file states them, its axis taken to the world by its joint frame's rotation, and
file mode naming an SDF joint whose damping differs from the URDF's. Skipped without Drake."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("pydrake")

from kinverify.filemode.pipeline import verify_files  # noqa: E402
from kinverify.filemode.read.describe_sdf import describe_sdf  # noqa: E402
from kinverify.generate import generate_sdf, generate_urdf  # noqa: E402
from kinverify.model.specfile import load_spec  # noqa: E402
from kinverify.run import VerifyOptions  # noqa: E402
from tests.paths import MODELS  # noqa: E402

FAST = VerifyOptions(samples=8, fd_samples=4, extra={"dynamics_samples": 8})


@pytest.fixture(scope="module")
def arm3() -> tuple[str, str]:
    """The generated arm3 URDF and SDF (damping 0.1 and armature 0.01 on every joint)."""
    spec = load_spec(MODELS / "arm3.toml")
    return generate_urdf(spec), generate_sdf(spec)


def damped(sdf: str, joint_index: int, value: float) -> str:
    """The SDF with the ``joint_index``-th joint's (0-based, chain order) damping set to ``value``."""
    parts = sdf.split("<damping>")
    assert len(parts) == 4
    head, rest = parts[joint_index + 1].split("</damping>", 1)
    parts[joint_index + 1] = f"{value!r}</damping>{rest}"
    return "<damping>".join(parts)


def test_damping_and_armature_are_read_as_the_sdf_states_them(arm3):
    desc = describe_sdf(damped(arm3[1], 1, 0.3))
    assert [(j.name, j.damping, j.armature, j.friction) for j in desc.joints] == [
        ("joint1", 0.1, 0.01, None),
        ("joint2", 0.3, 0.01, None),
        ("joint3", 0.1, 0.01, None),
    ]


def test_a_joint_axis_is_taken_to_the_world_by_its_frame_rotation():
    """A joint frame turned +90° about z with its axis along the frame's x: in the world, +y (the
    inverse rotation would give -y, the same line the other way round)."""
    sdf = f"""<?xml version="1.0"?><sdf version="1.9"><model name="m">
      <joint name="weld" type="fixed"><parent>world</parent><child>base</child></joint>
      <link name="base"><inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz>
        </inertia></inertial></link>
      <joint name="j" type="revolute"><pose relative_to="base">0 0 0.1 0 0 {math.pi / 2!r}</pose>
        <parent>base</parent><child>arm</child>
        <axis><xyz>1 0 0</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint>
      <link name="arm"><pose relative_to="j"/><inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy>
        <izz>0.01</izz></inertia></inertial></link>
    </model></sdf>"""
    (j,) = describe_sdf(sdf).joints
    assert np.allclose(j.axis, [0.0, 1.0, 0.0], atol=1e-12), j.axis
    assert np.allclose(j.anchor, [0.0, 0.0, 0.1], atol=1e-12)


def test_an_sdf_damping_other_than_the_urdfs_fails_naming_the_joint_and_the_size(tmp_path, arm3):
    urdf, sdf = arm3
    (tmp_path / "arm3.urdf").write_text(urdf)
    (tmp_path / "arm3.sdf").write_text(damped(sdf, 1, 0.3))
    result = verify_files(str(tmp_path / "arm3.urdf"), str(tmp_path / "arm3.sdf"), FAST, kinds=("urdf", "sdf"))
    failing = [f for f in result.findings if f.fails]
    assert result.verdict == "fail" and [(f.kind, f.subject, f.severity) for f in failing] == [
        ("damping_difference", "joint2", "error")
    ]
    assert failing[0].magnitude == pytest.approx(0.2, abs=1e-12) and failing[0].unit == "N·m·s/rad"
    assert "0.1 in the URDF, 0.3 in the SDF" in failing[0].message


def test_an_sdf_whose_damping_agrees_with_the_urdfs_passes(tmp_path, arm3):
    urdf, sdf = arm3
    (tmp_path / "arm3.urdf").write_text(urdf)
    (tmp_path / "arm3.sdf").write_text(sdf)
    result = verify_files(str(tmp_path / "arm3.urdf"), str(tmp_path / "arm3.sdf"), FAST, kinds=("urdf", "sdf"))
    assert result.verdict == "pass" and not result.internal_errors
    assert not [f for f in result.findings if "damping" in f.kind]
    (armature,) = [f for f in result.findings if f.kind == "inexpressible" and f.property == "dynamics.armature"]
    assert armature.severity == "warning" and armature.magnitude == pytest.approx(0.01)  # the SDF's, a URDF has none
