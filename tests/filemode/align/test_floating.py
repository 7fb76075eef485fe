"""Floating bases in file mode: a URDF floating root against an MJCF free joint is compared with
the base pose among the coordinates (FK of every frame, Jacobians with the base columns, mass
matrix and gravity), through every library; a difference is named per body or joint; floating
in one file only is one finding; a URDF root link with no joint reads as floating beside an
MJCF free joint (ROS describes both kinds of robot so)."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import tests.filemode.pairs as P
from kinverify.filemode.align.floating import conjugated, urdf_base
from kinverify.filemode.pipeline import verify_files
from kinverify.model.floating import BASE_COORDINATES, base_transforms
from kinverify.run import VerifyOptions
from tests.filemode.pairs import write_pair

ALL = VerifyOptions(samples=10, fd_samples=4, extra={"dynamics_samples": 10}, suites=P.NO_PICTURES)
FAST = VerifyOptions(
    samples=10, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], extra={"dynamics_samples": 10}, suites=P.NO_PICTURES
)


def floating_arm3() -> tuple[str, str]:
    """arm3 with its root joint floating, and its MJCF's base free (the mount body gone), starting
    at the pose the URDF's root joint gives it."""
    urdf, mjcf = P.generated_pair("arm3")
    urdf = P.sub_once(r'<joint name="world_to_base" type="fixed">', '<joint name="world_to_base" type="floating">', urdf)
    mjcf = P.sub_once(r'<body name="world_mount">\s*<inertial[^>]*/>\s*', "", mjcf)
    end = mjcf.rindex("</body>")
    mjcf = mjcf[:end] + mjcf[end + len("</body>") :]
    return urdf, P.sub_once(r'(<body name="base" pos="[^"]*">)', r"\1<freejoint/>", mjcf)


def run(tmp_path, urdf, mjcf, options=FAST):
    return verify_files(*write_pair(tmp_path, urdf, mjcf), options)


def kinds(result, severity=None) -> list[str]:
    return [f.kind for f in result.findings if severity is None or f.severity == severity]


def test_a_floating_arm3_pair_agrees_with_the_base_pose_among_the_compared_coordinates(tmp_path):
    result = run(tmp_path, *floating_arm3(), ALL)
    assert result.passed, ([c.property for c in result.failed], kinds(result))
    assert result.exit_code == 0 and not kinds(result, "error")
    assert tuple(result.joint_names[:6]) == BASE_COORDINATES and result.joint_names[6:] == ["joint1", "joint2", "joint3"]
    assert {"pinocchio-urdf", "yourdfpy", "mujoco-urdf", "mujoco", "pinocchio-mjcf"} <= set(result.backends)
    props = {c.property for c in result.checks}
    assert {"fk.position", "jacobian.linear", "jacobian.angular", "dynamics.mass_matrix", "dynamics.gravity"} <= props
    assert "floating_base" in kinds(result, "info") and "base_transform" not in kinds(result)
    # the base moved: the compared poses are not the fixed arm's (a base held at zero would not vary)
    assert np.ptp(np.asarray(result.lower[:3])) == 0 and result.upper[0] - result.lower[0] >= 1.0


def test_the_space_arm_spec_pair_passes_in_file_mode(tmp_path):
    result = run(tmp_path, *P.generated_pair("space_arm"))
    assert result.passed and not kinds(result, "error"), kinds(result)
    assert tuple(result.joint_names[:6]) == BASE_COORDINATES


def test_the_base_mass_and_a_flipped_joint_axis_are_named(tmp_path):
    urdf, mjcf = floating_arm3()
    heavier = P.sub_once(
        r'(<body name="base" pos="[^"]*"><freejoint/>\s*<inertial[^>]*? mass=")([^"]*)',
        lambda m: m[1] + repr(float(m[2]) * 1.2),
        mjcf,
    )
    result = run(tmp_path, urdf, heavier)
    named = [f for f in result.findings if f.severity != "info" and "base" in f.subject]
    assert named and named[0].kind in ("mass_difference", "base_inertial_difference"), kinds(result)
    assert not result.passed or named[0].severity != "error"
    flipped = P.flipped_axis(urdf, mjcf, "joint2")[1]
    result = run(tmp_path, urdf, flipped)
    sign = [f for f in result.findings if f.kind == "axis_sign_flip"]
    assert len(sign) == 1 and sign[0].subject == "joint2"
    assert not [c for c in result.failed if c.property.startswith(("fk.", "jacobian."))]  # compared after the flip


def test_an_axis_turned_in_one_file_fails_with_the_base_floating(tmp_path):
    urdf, mjcf = floating_arm3()
    turned = P.joint_attr(mjcf, "joint3", "axis", lambda s: "0.0 0.0 1.0")
    result = run(tmp_path, urdf, turned)
    assert result.exit_code == 1
    assert any(f.severity == "error" and "joint3" in f.subject for f in result.findings), kinds(result)


def test_a_free_joint_against_a_urdf_welded_to_the_world_is_one_error(tmp_path):
    urdf, _ = P.generated_pair("arm3")
    result = run(tmp_path, urdf, floating_arm3()[1])
    assert kinds(result, "error") == ["floating_one_file"], kinds(result)
    (one,) = [f for f in result.findings if f.kind == "floating_one_file"]
    assert one.message == (
        "the MJCF's body base floats (free joint) but the URDF welds its root link to the world (world_to_base is fixed): "
        "the files describe different robots; the rest is compared with the MJCF's base held fixed where the URDF's is"
    )
    assert "base:x" not in result.joint_names  # the rest compared with the base fixed
    assert not [c for c in result.failed if c.property.startswith("fk.")]


def test_a_urdf_root_link_without_a_joint_floats_beside_a_free_joint(tmp_path):
    urdf, mjcf = floating_arm3()
    bare = P.sub_once(r'\s*<link name="world"/>\s*<joint name="world_to_base".*?</joint>', "", urdf)
    assert urdf_base(bare).kind == "unstated" and urdf_base(urdf).kind == "floating"
    result = run(tmp_path, bare, mjcf)
    assert result.passed and not kinds(result, "error"), kinds(result)
    found = [f for f in result.findings if f.kind == "floating_base"]
    assert len(found) == 1 and "has no joint" in found[0].message
    assert tuple(result.joint_names[:6]) == BASE_COORDINATES


def test_another_base_body_frame_is_one_warning_and_compared_after_it(tmp_path):
    urdf, mjcf = floating_arm3()
    wrapped = P.sub_once(
        r'<body name="base" pos="[^"]*"><freejoint/>',
        '<body name="float_root" pos="0 0 0.3"><freejoint/>'
        '<inertial pos="0 0 0" mass="0" diaginertia="0 0 0"/>'
        f'<body name="base" pos="0.1 0 0.12" quat="{math.cos(0.3)!r} {math.sin(0.3)!r} 0 0">',
        mjcf,
    )
    end = wrapped.rindex("</worldbody>")
    result = run(tmp_path, urdf, wrapped[:end] + "</body>" + wrapped[end:])
    offset = [f for f in result.findings if f.kind == "base_frame_offset"]
    assert len(offset) == 1 and offset[0].severity == "warning" and "base_transform" not in kinds(result)
    assert np.allclose(offset[0].values["xyz"], [0.1, 0.0, 0.12]) and np.isclose(offset[0].values["rpy"][0], 0.6)
    assert result.passed, [(c.property, c.max_error) for c in result.failed]


@settings(max_examples=40, deadline=None)
@given(st.lists(st.floats(-3.0, 3.0), min_size=6, max_size=6), st.lists(st.floats(-1.4, 1.4), min_size=6, max_size=6))
def test_the_conjugated_base_and_its_derivative(t6, b6):
    t = base_transforms(np.array(t6))
    b = np.array([b6])
    new, d = conjugated(t, b)
    assert np.allclose(base_transforms(new)[0], t @ base_transforms(b)[0] @ np.linalg.inv(t), atol=1e-12)
    h, numeric = 1e-6, np.zeros((6, 6))
    for k in range(6):
        step = np.zeros((1, 6))
        step[0, k] = h
        plus, minus = conjugated(t, b + step)[0], conjugated(t, b - step)[0]
        diff = plus - minus
        diff[0, 3:] = (diff[0, 3:] + np.pi) % (2 * np.pi) - np.pi  # angles wrap
        numeric[:, k] = diff[0] / (2 * h)
    pitch = abs(new[0, 4])
    if pitch < 1.5:  # away from the pitch singularity of roll-pitch-yaw
        assert np.allclose(d[0], numeric, atol=1e-5 / math.cos(pitch) ** 2)


@pytest.mark.parametrize(
    "text, kind",
    [
        (
            '<robot name="r"><link name="world"/><joint name="j" type="fixed"><parent link="world"/><child link="b"/></joint>'
            '<link name="b"/></robot>',
            "fixed",
        ),
        ('<robot name="r"><link name="b"/></robot>', "unstated"),
        (
            '<robot name="r"><link name="w"/><joint name="f" type="floating"><parent link="w"/><child link="b"/></joint>'
            '<link name="b"/></robot>',
            "floating",
        ),
    ],
)
def test_how_a_urdf_holds_its_root(text, kind):
    assert urdf_base(text).kind == kind
    assert re.search(r"\w", urdf_base(text).link)


def test_a_free_mount_body_above_the_base_is_its_extra_mass_and_nothing_else(tmp_path):
    """The MJCF's free body is a 1 kg mount the base hangs 0.42 m above (the URDF floats the base
    itself): one base-frame warning, the mount's mass as the one error, and every configuration,
    pitch near ±π/2 included, compared after the offset without a kinematic finding."""
    urdf, mjcf = P.generated_pair("arm3")
    urdf = P.sub_once(r'<joint name="world_to_base" type="fixed">', '<joint name="world_to_base" type="floating">', urdf)
    mjcf = P.sub_once(r'<body name="world_mount">', '<body name="world_mount"><freejoint name="root"/>', mjcf)
    result = run(tmp_path, urdf, mjcf, ALL)
    assert kinds(result, "error") == ["extra_parts"] and "base_frame_offset" in kinds(result, "warning")
    assert not result.failed and {c.property for c in result.explained} <= {"inertia.mass", "inertia.com", "inertia.tensor"}


def test_armature_and_damping_a_free_joint_takes_from_its_class_are_named_and_left_out(tmp_path):
    """The MJCF's free joint gets armature 0.1 and damping 1 (as a class meant for the legs gives
    them to it too): a floating URDF has neither. One warning says so, and the mass matrices agree
    once they are left out."""
    urdf, mjcf = floating_arm3()
    mjcf = P.sub_once(r"<freejoint/>", '<joint name="root" type="free" armature="0.1" damping="1"/>', mjcf)
    result = run(tmp_path, urdf, mjcf, ALL)
    (f,) = [f for f in result.findings if "free joint" in f.message and f.kind == "inexpressible"]
    assert f.severity == "warning" and f.values["armature"] == 0.1 and f.values["damping"] == 1.0
    assert not kinds(result, "error") and result.passed, ([c.property for c in result.failed], kinds(result))
