"""OpenUSD in file mode, read by usd-core (pxr): the shared conversions of each URDF by NVIDIA's
urdf-usd-converter, the Isaac Lab ANYmal C (with the URDF and Menagerie's MJCF), the Apollo pair
(MJCF and its structured USD), planted changes named with their size, and bad USD refused with
one line (exit 2). Skipped without the ``usd`` extra; the shared-file tests without
../shared/real-robots."""

from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest

pytest.importorskip("pxr")

from kinverify.backends.pinocchio_ import PinocchioBackend  # noqa: E402
from kinverify.backends.usd_ import UsdBackend  # noqa: E402
from kinverify.backends.usd_stage import read_robot  # noqa: E402
from kinverify.cli import main  # noqa: E402
from kinverify.errors import InputError  # noqa: E402
from kinverify.filemode.audit import audit_file  # noqa: E402
from kinverify.filemode.pipeline import verify_files, verify_three  # noqa: E402
from kinverify.filemode.read.describe_usd import describe_usd  # noqa: E402
from kinverify.run import VerifyOptions  # noqa: E402
from tests.filemode.pairs import small_usda  # noqa: E402
from tests.paths import REAL_ROBOTS  # noqa: E402

FAST = VerifyOptions(samples=5, fd_samples=2)
IIWA = REAL_ROBOTS / "iiwa14"
IIWA_EFFORT = {
    "iiwa_joint_1": 320,
    "iiwa_joint_2": 320,
    "iiwa_joint_3": 176,
    "iiwa_joint_4": 176,
    "iiwa_joint_5": 110,
    "iiwa_joint_6": 40,
    "iiwa_joint_7": 40,
}


def shared(*parts):
    path = REAL_ROBOTS.joinpath(*parts)
    if not path.exists():
        pytest.skip(f"{path} absent")
    return path


def errors(result) -> list[tuple[str, str]]:
    return sorted((f.kind, f.subject) for f in result.findings if f.fails)


def one(result, kind: str):
    found = [f for f in result.findings if f.kind == kind]
    assert len(found) == 1, [(f.kind, f.message) for f in result.findings]
    return found[0]


def test_the_usd_fk_agrees_with_pinocchio_on_the_urdf_it_was_converted_from():
    """The joint frames composed (USD side) against Pinocchio's FK of the URDF, at random
    configurations: single precision apart, nothing more; the authored xforms at q = 0 too."""
    usd = shared("iiwa14", "iiwa14_urdf-usd-converter.usda")
    urdf = (IIWA / "iiwa14_no_collision_drake.urdf").read_text()
    joints = list(IIWA_EFFORT)
    frames = [f"iiwa_link_{i}" for i in range(8)] + ["iiwa_link_ee"]
    q = np.random.default_rng(0).uniform(-2.0, 2.0, (20, 7))
    a, b = UsdBackend.from_usd(str(usd), joints, frames), PinocchioBackend.from_urdf(urdf, joints, frames)
    assert np.abs(a.poses(q) - b.poses(q)).max() < 1e-6
    assert np.abs(a.jacobians(q) - b.jacobians(q)).max() < 1e-6
    robot = read_robot(str(usd))
    zero = b.poses(np.zeros((1, 7)))[0]
    for k, name in enumerate(frames[:8]):
        body = next(p for p, n in robot.names.items() if n == name)
        assert np.abs(robot.authored[body] - zero[k]).max() < 1e-6


def test_the_reading_honours_units_and_degrees(tmp_path):
    """centimetres and grams (metersPerUnit 0.01, kilogramsPerUnit 0.001), limits in degrees, a
    drive's gains per degree: read in metres, kilograms, radians."""
    text = shared("iiwa14", "iiwa14_urdf-usd-converter.usda").read_text()
    text = text.replace("kilogramsPerUnit = 1", "kilogramsPerUnit = 0.001").replace("metersPerUnit = 1", "metersPerUnit = 0.01")
    (tmp_path / "cm.usda").write_text(text)
    desc = describe_usd(read_robot(str(tmp_path / "cm.usda")))
    j = desc.joint("iiwa_joint_1")
    assert j.anchor[2] == pytest.approx(0.001575) and j.upper == pytest.approx(math.radians(170))
    assert desc.body("iiwa_link_3").mass == pytest.approx(0.0035)


def test_a_y_up_stage_is_turned_z_up(tmp_path):
    """upAxis "Y": the stage's y is the world's z (a quarter turn about x), the gravity along -z."""
    text = shared("iiwa14", "iiwa14_urdf-usd-converter.usda").read_text().replace('upAxis = "Z"', 'upAxis = "Y"')
    (tmp_path / "y.usda").write_text(text)
    desc = describe_usd(read_robot(str(tmp_path / "y.usda")))
    j = desc.joint("iiwa_joint_1")  # along the stage's z, 0.1575 up it
    assert j.axis == pytest.approx([0, -1, 0]) and j.anchor == pytest.approx([0, -0.1575, 0])
    assert desc.gravity == pytest.approx([0, 0, -9.81])


CONVERTED = {
    "a1": "a1_unitree_ros.urdf",
    "anymal_c": "anymal_c_anybotics.urdf",
    "go2": "go2_erd.urdf",
    "iiwa14": "iiwa14_no_collision_drake.urdf",
    "leap_hand": "leap_hand_dexurdf.urdf",
    "panda": "panda_erd.urdf",
    "ur5e": "ur5e_ur_description.urdf",
    "z1": "z1_erd.urdf",
}


@pytest.mark.parametrize("folder", sorted(CONVERTED))
def test_each_conversion_keeps_the_urdf_effort_only_as_a_custom_attribute(folder):
    """Every urdf-usd-converter output: no drive on any joint, each URDF effort kept (same value)
    as urdf:limit:effort, and the same masses on the links both state (the rest is file mode's)."""
    usd = shared(folder, f"{folder}_urdf-usd-converter.usda")
    urdf = ET.parse(REAL_ROBOTS / folder / CONVERTED[folder]).getroot()
    effort = {
        j.get("name"): float(j.find("limit").get("effort"))
        for j in urdf.findall("joint")
        if j.get("type") in ("revolute", "continuous", "prismatic") and j.find("limit") is not None
    }
    mass = {
        link.get("name"): float(link.find("inertial/mass").get("value"))
        for link in urdf.findall("link")
        if link.find("inertial/mass") is not None
    }
    desc = describe_usd(read_robot(str(usd)))
    assert all(j.effort is None and "effort" not in j.stated for j in desc.joints)
    custom = {j.name: desc.extensions[j.name]["custom_effort"] for j in desc.joints}
    names = {j.name: j.name.replace("tn__", "").rstrip("_") for j in desc.joints}  # leap_hand: "1" is written tn__1_
    assert {names[n]: v for n, v in custom.items()} == pytest.approx({n: effort[n] for n in names.values()}, rel=1e-7)
    both = [b for b in desc.bodies if b.name in mass]
    assert both and all(b.mass == pytest.approx(mass[b.name], rel=1e-7) for b in both)


def test_a_converted_urdf_passes_naming_the_effort_kept_only_as_a_custom_attribute():
    usd = shared("iiwa14", "iiwa14_urdf-usd-converter.usda")
    result = verify_files(str(IIWA / "iiwa14_no_collision_drake.urdf"), str(usd), FAST, kinds=("urdf", "usd"))
    assert result.verdict == "pass" and not result.internal_errors and not errors(result)
    f = one(result, "effort_unset")
    assert f.severity == "warning" and f.values["unset_in"] == "USD" and f.values["urdf"] == list(IIWA_EFFORT.values())
    assert "custom attribute urdf:limit:effort (320, 320, 176, 176, 110, 40, 40)" in f.message
    assert "usd" in result.backends and result.model_info["files"] == {
        "urdf": str(IIWA / "iiwa14_no_collision_drake.urdf"),
        "usd": str(usd),
    }


def test_the_panda_conversion_keeps_the_mimic_finger():
    usd = shared("panda", "panda_urdf-usd-converter.usda")
    result = verify_files(str(REAL_ROBOTS / "panda" / "panda_erd.urdf"), str(usd), FAST, kinds=("urdf", "usd"))
    assert result.verdict == "pass" and not errors(result) and not result.internal_errors
    coupling = describe_usd(read_robot(str(usd))).couplings
    assert [(c.follower, c.leader, c.multiplier, c.offset) for c in coupling] == [
        ("panda_finger_joint2", "panda_finger_joint1", 1.0, 0.0)
    ]


def test_the_anymal_c_triple_names_the_isaac_lab_usd_s_unlimited_and_faster_joints():
    """URDF, Menagerie MJCF and Isaac Lab USD at once: the USD's joints are unlimited (±inf) where
    the URDF limits them, and allowed 20 rad/s where the URDF says 7.5; its drives' maxForce (80)
    agrees with the URDF's effort; two bodies' xforms hold a quaternion off unit length."""
    usd = shared("anymal_c", "anymal_c_isaaclab.usda")
    folder = REAL_ROBOTS / "anymal_c"
    quick = VerifyOptions(samples=5, fd_samples=2, suites=["kinematics", "limits", "inertia"])  # no dynamics, no drawing
    result = verify_three(
        str(folder / "anymal_c_anybotics.urdf"), str(folder / "anymal_c_menagerie.xml"), None, quick, usd=str(usd)
    )
    usd_errors = {f.kind: f for f in result.findings if f.fails and "USD" in f.message}
    assert sorted(usd_errors) == ["limit_difference", "velocity_difference"], [(f.kind, f.message) for f in usd_errors.values()]
    limits, velocity = usd_errors["limit_difference"], usd_errors["velocity_difference"]
    assert limits.magnitude == math.inf and len(limits.subject.split(", ")) == 12 and "LF_HAA [-0.72, 0.49]" in limits.message
    assert (velocity.values["urdf"], velocity.values["mjcf"]) == pytest.approx((7.5, 20.0))  # maxJointVelocity 1145.9156 °/s
    assert len(velocity.subject.split(", ")) == 12 and velocity.magnitude == pytest.approx(12.5)
    assert not [f for f in result.findings if f.kind == "effort_difference" and "USD" in f.message]
    pose = one(result, "usd_pose_mismatch")
    assert pose.subject == "LH_FOOT, RH_FOOT" and pose.magnitude == pytest.approx(0.0012, abs=1e-4)
    assert set(result.model_info["files"]) == {"urdf", "mjcf", "usd"} and "usd:filemode" in result.sections


def test_apollo_usd_agrees_with_the_mjcf_it_was_converted_from():
    usd = shared("apollo", "apptronik_apollo.usda")
    result = verify_files(str(usd), str(REAL_ROBOTS / "apollo" / "apollo_menagerie.xml"), FAST, kinds=("usd", "mjcf"))
    assert result.verdict == "pass" and not errors(result) and not result.internal_errors
    assert not [
        f
        for f in result.findings
        if f.kind in ("inexpressible", "armature_difference", "damping_difference") and "armature" in f.message
    ]  # the USD states armature, 0.231424 on torso_yaw as the MJCF
    desc = describe_usd(read_robot(str(usd)))
    torso = desc.joint("torso_yaw")
    assert (torso.armature, torso.damping, torso.friction, torso.effort) == pytest.approx((0.231424, 200.0, 0.7, 120.0))
    assert any("GeometryLibrary.usdc" in n and "absent" in n for n in result.notes)


def _plant(tmp_path, joint: str | None, old: str, new: str) -> str:
    text = (IIWA / "iiwa14_urdf-usd-converter.usda").read_text()
    start = text.index(f'PhysicsRevoluteJoint "{joint}"') if joint else 0
    end = text.index("\n        }", start) if joint else len(text)
    assert old in text[start:end]
    path = tmp_path / "planted.usda"
    path.write_text(text[:start] + text[start:end].replace(old, new, 1) + text[end:])
    return str(path)


@pytest.mark.parametrize(
    "joint, old, new, kind, subject, size",
    [
        ("iiwa_joint_4", 'physics:axis = "Z"', 'physics:axis = "X"', "axis_direction", "iiwa_joint_4", math.pi / 2),
        ("iiwa_joint_3", "0.2045, 1.2325952e-32)", "0.2145, 1.2325952e-32)", "joint_origin_moved", "iiwa_joint_3", 0.01),
        ("iiwa_joint_2", "upperLimit = 120", "upperLimit = 110", "limit_difference", "iiwa_joint_2", math.radians(10)),
        (None, "float physics:mass = 3.5\n", "float physics:mass = 4\n", "mass_difference", "iiwa_link_3", 0.5),
        (
            "iiwa_joint_1",
            "custom float urdf:limit:effort = 320",
            "float drive:angular:physics:maxForce = 300",
            "effort_difference",
            "iiwa_joint_1",
            20.0,
        ),
    ],
)
def test_a_planted_change_in_the_usd_is_named_with_its_size(tmp_path, joint, old, new, kind, subject, size):
    shared("iiwa14", "iiwa14_urdf-usd-converter.usda")
    path = _plant(tmp_path, joint, old, new)
    if kind == "effort_difference":  # the drive's schema applied too
        text = open(path).read()
        start = text.index('PhysicsRevoluteJoint "iiwa_joint_1"')
        text = text[:start] + text[start:].replace('["NewtonJointAPI"]', '["NewtonJointAPI", "PhysicsDriveAPI:angular"]', 1)
        open(path, "w").write(text)
    result = verify_files(str(IIWA / "iiwa14_no_collision_drake.urdf"), path, FAST, kinds=("urdf", "usd"))
    assert result.verdict == "fail"
    f = next(f for f in result.findings if f.kind == kind)
    assert f.subject == subject and f.magnitude == pytest.approx(size, rel=1e-6, abs=1e-9)


def test_the_one_file_audit_says_what_the_usd_states_and_leaves_unset():
    usd = shared("a1", "a1_urdf-usd-converter.usda")
    result = audit_file(str(usd), "usd", FAST)
    assert result.verdict == "pass" and not result.internal_errors
    assert one(result, "effort_unset").values["custom"]["FR_hip_joint"] == 33.5
    assert one(result, "inertial_unset").values["bodies"] == [
        "FL_thigh_shoulder",
        "FR_thigh_shoulder",
        "RL_thigh_shoulder",
        "RR_thigh_shoulder",
        "base",
    ]
    rows = {r[0]: r for r in result.sections["usd"].tables[0].rows}
    assert rows["FR_hip_joint"][3] == "unset" and rows["FR_hip_joint"][5] == "0.01"
    assert any(c.property == "jacobian.fd" for c in result.checks)


LOOP = 'def PhysicsRevoluteJoint "j2"\n    {\n        rel physics:body0 = </r/b0>\n        rel physics:body1 = </r/b1>\n    }'


@pytest.mark.parametrize(
    "case, expected",
    [
        (dict(art=False), "no articulation"),
        (dict(body1="/r/nothere"), "joint /r/j1: physics:body1 names /r/nothere, which does not exist"),
        (dict(extra=LOOP), "joint /r/j2 closes a loop"),
        (dict(pos0="(nan, 0, 0)"), "prim /r/j1: physics:localPos0"),
        (dict(header="\n    subLayers = [@./self.usda@]"), "composition cycle"),
        (dict(header="\n    subLayers = [@/dev/zero@]"), "layer /dev/zero (named by bad.usda) is a device"),
        (dict(header="\n    subLayers = [@./pipe.usda@]"), "(named by bad.usda) is a FIFO (named pipe)"),
        (dict(header="\n    subLayers = [@./huge.usda@]"), "MB, above the 8 MB"),
    ],
)
def test_bad_usd_is_refused_naming_the_prim_or_layer(tmp_path, case, expected):
    os.mkfifo(tmp_path / "pipe.usda")
    with open(tmp_path / "huge.usda", "wb") as f:
        f.truncate(9 * 2**20)
    name = "self" if "self.usda" in case.get("header", "") else "bad"
    with pytest.raises(InputError) as err:
        read_robot(small_usda(tmp_path, name, **case))
    assert expected in str(err.value) and "\n" not in str(err.value)


def test_bad_usd_exits_2_with_one_line(tmp_path, capsys):
    path = small_usda(tmp_path, "bad", body1="/r/nothere")
    assert main(["verify", "--usd", path, "--json", str(tmp_path / "o.json"), "--report", str(tmp_path / "o.html")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "/r/j1" in err and not (tmp_path / "o.json").exists()


def test_a_small_usd_alone_passes_the_audit(tmp_path):
    result = audit_file(small_usda(tmp_path, "ok"), "usd", FAST)
    assert result.verdict == "pass" and [r[0] for r in result.sections["usd"].tables[0].rows] == ["j1"]


MIMIC = """def Xform "b2" (apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsMassAPI"])
    {
        float physics:mass = 1
    }
    def Xform "b3" (apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsMassAPI"])
    {
        float physics:mass = 1
    }
    def PhysicsRevoluteJoint "newton" (apiSchemas = ["NewtonMimicAPI"])
    {
        uniform token physics:axis = "X"
        rel physics:body0 = </r/b1>
        rel physics:body1 = </r/b2>
        rel newton:mimicJoint = </r/j1>
        float newton:mimicCoef0 = 10
        float newton:mimicCoef1 = -2
    }
    def PhysicsRevoluteJoint "physx" (apiSchemas = ["PhysxMimicJointAPI:rotX"])
    {
        uniform token physics:axis = "Y"
        rel physics:body0 = </r/b2>
        rel physics:body1 = </r/b3>
        rel physxMimicJoint:rotX:referenceJoint = </r/j1>
        float physxMimicJoint:rotX:gearing = -0.5
        float physxMimicJoint:rotX:offset = 30
    }"""


def test_mimic_joints_are_read_with_their_offsets_in_degrees(tmp_path):
    """NewtonMimicAPI: follower = coef0 + coef1 · leader; PhysxMimicJointAPI: follower + gearing ·
    leader + offset = 0; offsets written in degrees."""
    desc = describe_usd(read_robot(small_usda(tmp_path, "mimic", extra=MIMIC)))
    got = {c.follower: (c.leader, c.multiplier, c.offset, c.source) for c in desc.couplings}
    assert got == {
        "newton": ("j1", -2.0, pytest.approx(math.radians(10)), "NewtonMimicAPI"),
        "physx": ("j1", 0.5, pytest.approx(-math.radians(30)), "PhysxMimicJointAPI"),
    }
    assert desc.joint("physx").axis == pytest.approx([0, 1, 0]) and desc.joint("newton").parent == "j1"
