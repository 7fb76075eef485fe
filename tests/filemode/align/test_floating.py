"""Floating bases in file mode: a URDF floating root against an MJCF free joint is compared with
the base pose among the coordinates (FK of every frame, Jacobians with the base columns, mass
matrix and gravity), through every library; a difference is named per body or joint; floating
in one file only is one finding; a URDF root link with no joint reads as floating beside an
MJCF free joint (ROS describes both kinds of robot so)."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import tests.filemode.pairs as P
from kinverify.filemode.align.floating import (
    ADDED_JOINT,
    ADDED_ROOT,
    UrdfBase,
    base_findings,
    base_samples,
    conjugated,
    decide,
    fixed_urdf,
    floating_urdf,
    urdf_base,
)
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.files import BaseDecision
from kinverify.filemode.pipeline import verify_files
from kinverify.model.floating import BASE_COORDINATES, base_limits, base_transforms
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


# --- each decision of the module on its own, with small texts and the project's dataclasses ---

WORLD_FIXED = (
    '<robot name="r"><link name="world"/><joint name="weld" type="fixed"><parent link="world"/><child link="b"/>'
    '</joint><link name="b"/><joint name="j1" type="revolute"><parent link="b"/><child link="c"/></joint>'
    '<link name="c"/></robot>'
)
FLOATING = (
    '<robot name="r"><link name="c"/><joint name="j1" type="revolute"><parent link="b"/><child link="c"/></joint>'
    '<link name="w"/><joint name="weld" type="fixed"><parent link="w"/><child link="x"/></joint><link name="x"/>'
    '<joint name="float" type="floating"><parent link="w"/><child link="b"/><origin xyz="1 2 3"/>'
    '<limit effort="1"/><axis xyz="0 0 1"/></joint><link name="b"/></robot>'
)


def test_urdf_base_floating_names_the_joint_and_its_child():
    base = urdf_base(FLOATING)
    assert base == UrdfBase("floating", "w", "float", "b")


def test_urdf_base_floating_without_a_child_keeps_the_root_link():
    text = '<robot name="r"><link name="w"/><joint name="f" type="floating"><parent link="w"/></joint></robot>'
    assert urdf_base(text) == UrdfBase("floating", "w", "f", "w")


def test_urdf_base_world_welded_is_fixed():
    assert urdf_base(WORLD_FIXED) == UrdfBase("fixed", "world", "weld", "world")


@pytest.mark.parametrize(
    "text",
    [
        # a root called world with a moving joint below: not welded
        '<robot name="r"><link name="world"/><joint name="j" type="revolute"><parent link="world"/><child link="b"/>'
        '</joint><link name="b"/></robot>',
        # a root called world with nothing below it
        '<robot name="r"><link name="world"/></robot>',
        # welded with fixed joints, but the root is not called world
        '<robot name="r"><link name="ground"/><joint name="j" type="fixed"><parent link="ground"/><child link="b"/>'
        '</joint><link name="b"/></robot>',
        # world welded by one fixed joint and held by a moving one beside it
        '<robot name="r"><link name="world"/><joint name="a" type="fixed"><parent link="world"/><child link="b"/></joint>'
        '<joint name="j" type="prismatic"><parent link="world"/><child link="c"/></joint><link name="b"/><link name="c"/>'
        "</robot>",
    ],
)
def test_urdf_base_unstated(text):
    base = urdf_base(text)
    assert base.kind == "unstated" and base.joint is None and base.link == base.root
    assert base.root in ("world", "ground")


def test_urdf_base_of_a_robot_without_a_root():
    assert urdf_base('<robot name="r"/>') == UrdfBase("unstated", "", None, "")


def test_fixed_urdf_keeps_the_origin_or_drops_it():
    assert isinstance(fixed_urdf(FLOATING, keep_origin=True), str)  # text, as the readers take it
    kept = ET.fromstring(fixed_urdf(FLOATING, keep_origin=True))
    (joint,) = [j for j in kept.findall("joint") if j.get("name") == "float"]
    assert joint.get("type") == "fixed"
    assert [el.tag for el in joint] == ["parent", "child", "origin"]
    assert joint.find("origin").get("xyz") == "1 2 3"
    assert [j.get("type") for j in kept.findall("joint")] == ["revolute", "fixed", "fixed"]
    dropped = ET.fromstring(fixed_urdf(FLOATING, keep_origin=False))
    (joint,) = [j for j in dropped.findall("joint") if j.get("name") == "float"]
    assert [el.tag for el in joint] == ["parent", "child"]
    assert urdf_base(fixed_urdf(FLOATING, keep_origin=False)).kind == "unstated"


def test_fixed_urdf_leaves_a_non_floating_urdf_alone():
    assert fixed_urdf(WORLD_FIXED, keep_origin=False) is WORLD_FIXED


def test_floating_urdf_adds_a_floating_joint_above_an_unstated_root():
    text = '<robot name="r"><link name="b"/></robot>'
    out = floating_urdf(text)
    assert isinstance(out, str)
    assert urdf_base(out) == UrdfBase("floating", ADDED_ROOT, ADDED_JOINT, "b")
    joint = ET.fromstring(out).find("joint")
    assert (joint.find("parent").get("link"), joint.find("child").get("link")) == ("world", "b")
    assert floating_urdf(FLOATING) is FLOATING and floating_urdf(WORLD_FIXED) is WORLD_FIXED


@pytest.mark.parametrize("kind", ["floating", "unstated"])
def test_decide_both_float(kind):
    base = UrdfBase(kind, "root_link", "float" if kind == "floating" else None, "b")
    floating, found, message = decide(base, ["torso"])
    assert (floating, found) == (True, "floating_base")
    assert "torso" in message and "base:x, base:y, base:z, base:roll, base:pitch, base:yaw" in message
    assert "the free joint's initial value, not a property of the robot" in message
    if kind == "floating":
        assert "root joint float is floating" in message and "has no joint" not in message
    else:
        assert "root link root_link has no joint" in message


@pytest.mark.parametrize(("kind", "extra"), [("floating", True), ("unstated", False), ("fixed", False)])
def test_decide_several_free_bodies(kind, extra):
    base = UrdfBase(kind, "root_link", "float", "b")
    floating, found, message = decide(base, ["a", "b"])
    assert (floating, found) == (False, "floating_base")
    assert "has 2 free top-level bodies (a, b)" in message
    assert ("the URDF's floating root is held there too" in message) is extra


def test_decide_free_against_welded_and_floating_against_welded():
    floating, found, message = decide(UrdfBase("fixed", "world", "weld", "world"), ["torso"])
    assert (floating, found) == (False, "floating_one_file")
    assert "body torso floats" in message and "(weld is fixed)" in message
    floating, found, message = decide(UrdfBase("floating", "w", "float", "b"), [])
    assert (floating, found) == (False, "floating_one_file")
    assert "root joint float is floating but the MJCF has no free joint" in message


@pytest.mark.parametrize("kind", ["fixed", "unstated"])
def test_decide_nothing_to_say(kind):
    assert decide(UrdfBase(kind, "world", None, "world"), []) == (False, "", "")


def test_base_samples_within_the_limits_and_repeatable():
    lower, upper = base_limits(np.zeros(3))
    samples = base_samples(200, 3)
    assert samples.shape == (200, 6)
    assert np.all(samples >= lower) and np.all(samples <= upper)
    # they spread over the range (a sampler fixed at one bound or the origin would not)
    assert np.all(samples.max(axis=0) - samples.min(axis=0) > 0.8 * (upper - lower))
    assert np.array_equal(samples, base_samples(200, 3)) and not np.array_equal(samples, base_samples(200, 4))


def moved_finding():
    return finding("base_transform", "moved", {"xyz": [0.1, 0.0, 0.2], "rpy": [0.0, 0.0, 0.5]}, magnitude=0.3, unit="m|rad")


def decision(floating, kind):
    return BaseDecision(floating, kind, "", UrdfBase("floating", "w", "float", "base_link"), ["torso"])


def test_base_findings_both_float_the_transform_becomes_one_base_frame_offset():
    other = finding("axis_sign_flip", "flipped", joint="j1")
    out = base_findings([other, moved_finding()], decision(True, "floating_base"))
    assert [f.kind for f in out] == ["base_frame_offset", "axis_sign_flip"]
    offset = out[0]
    assert offset.subject == "base_link" and offset.magnitude == 0.3 and offset.unit == "m|rad"
    assert offset.values == {"xyz": [0.1, 0.0, 0.2], "rpy": [0.0, 0.0, 0.5]}
    assert "base link base_link" in offset.message and "base body torso" in offset.message
    assert "xyz = [0.1, 0, 0.2] m" in offset.message and "rpy = [0, 0, 0.5] rad" in offset.message
    assert "the files are compared after it" in offset.message


def test_base_findings_one_file_floating_drops_the_transform():
    other = finding("axis_sign_flip", "flipped", joint="j1")
    out = base_findings([moved_finding(), other], decision(False, "floating_one_file"))
    assert [f.kind for f in out] == ["axis_sign_flip"]


def test_base_findings_left_alone_without_a_base_decision():
    findings = [moved_finding()]
    assert base_findings(findings, decision(False, "")) is findings
    # several free bodies: held fixed, the transform stays a world transform
    assert base_findings(findings, decision(False, "floating_base")) is findings
    # both float without a transform: nothing to add
    assert base_findings([], decision(True, "floating_base")) == []
