"""The real pairs in ../shared/real-robots (skipped when absent; never copied here): each known
difference found once, by value, with the right verdict, and nothing above information that is
not a real difference (the ground truth a maintainer's reading of each pair gives).

``KINVERIFY_REAL_ROBOTS`` points elsewhere when the folder is not beside the project."""

from __future__ import annotations

import math
import os
import re
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

from kinverify.filemode.pipeline import verify_files
from kinverify.run import VerifyOptions
from tests.filemode.pairs import NO_PICTURES
from tests.paths import REAL_ROBOTS
from kinverify.filemode.read.loading import given_packages

REAL = Path(os.environ.get("KINVERIFY_REAL_ROBOTS", REAL_ROBOTS))
FILES = {
    "panda": ("panda_erd.urdf", "panda_menagerie.xml"),
    "iiwa14": ("iiwa14_no_collision_drake.urdf", "iiwa14_menagerie.xml"),
    "z1": ("z1_erd.urdf", "z1_menagerie.xml"),
    "go2": ("go2_erd.urdf", "go2_menagerie.xml"),
    "a1": ("a1_unitree_ros.urdf", "a1_menagerie.xml"),
    "anymal_c": ("anymal_c_anybotics.urdf", "anymal_c_menagerie.xml"),
    "leap_hand": ("leap_hand_dexurdf.urdf", "leap_hand_menagerie.xml"),
    "ur5e": ("ur5e_ur_description.urdf", "ur5e_menagerie.xml"),
}
SAME_WORLD = ("panda", "iiwa14", "z1", "go2", "a1")  # every library reads both files, whose worlds coincide
OPTIONS = VerifyOptions(samples=12, fd_samples=4, extra={"dynamics_samples": 20}, suites=NO_PICTURES)


@lru_cache(maxsize=None)
def result(robot: str):
    folder = REAL / robot
    if not folder.is_dir():
        pytest.skip(f"{folder} absent")
    return verify_files(*(str(folder / f) for f in FILES[robot]), OPTIONS)


def findings(robot: str, kind: str) -> list:
    return [f for f in result(robot).findings if f.kind == kind]


def one(robot: str, kind: str):
    hits = findings(robot, kind)
    assert len(hits) == 1, [(f.kind, f.label) for f in result(robot).findings]
    return hits[0]


def drake_reading(f) -> bool:
    """Drake's notes on its own reading (what its parsers ignore, a reading standing apart): tested below."""
    return str(f.values.get("backend") or f.values.get("apart") or "").startswith("drake")


def serious(robot: str) -> list[tuple[str, str]]:
    return sorted((f.kind, f.severity) for f in result(robot).findings if f.severity != "info" and not drake_reading(f))


@pytest.mark.parametrize("robot", SAME_WORLD)
def test_every_library_reads_each_file_and_every_failing_check_has_its_finding(robot):
    r = result(robot)
    assert r.verdict == "fail" and r.exit_code == 1 and not r.internal_errors
    assert {"pinocchio-urdf", "yourdfpy", "mujoco-urdf", "mujoco", "pinocchio-mjcf"} <= set(r.backends)
    assert not r.failed, [(c.property, c.frame, c.backends, c.max_error) for c in r.failed]
    assert not [f for f in findings(robot, "parser_refused") if not drake_reading(f)] and not findings(
        robot, "disagreement_starts"
    )
    assert np.allclose(r.sections["filemode"].data["alignment"]["T_mjcf_from_urdf"], np.eye(4), atol=1e-12)


def test_panda_differs_in_joint_damping_and_the_finger_force_only():
    assert serious("panda") == [
        ("damping_difference", "error"),
        ("damping_difference", "error"),
        ("effort_difference", "error"),
        ("inexpressible", "warning"),
    ]
    arm, fingers = sorted(findings("panda", "damping_difference"), key=lambda f: len(f.subject), reverse=True)
    assert (arm.values["urdf"], arm.values["mjcf"]) == (0.003, 1.0) and arm.subject.count("panda_joint") == 7
    assert (fingers.values["urdf"], fingers.values["mjcf"]) == (0.3, 1.0)
    effort = one("panda", "effort_difference")  # 100 N per finger vs actuator8's ±100 N on a tendon of coefficient 0.5
    assert effort.values["urdf"] == [100.0, 100.0] and effort.values["mjcf"] == [50.0, 50.0] and "tendon split" in effort.message
    assert one("panda", "inexpressible").magnitude == pytest.approx(0.1)


def test_panda_rounding_convention_and_tool_frame_are_information():
    rounding = one("panda", "rounding")  # the hand quaternion: −π/4 written to 7 decimals
    assert rounding.subject == "panda_hand" and rounding.values["rotation_rad"] == pytest.approx(3.49e-8, rel=0.01)
    assert rounding.values["position_m"] == pytest.approx(1.4e-9, rel=0.05)
    finger = one("panda", "frame_convention")
    assert finger.subject == "panda_rightfinger" and finger.magnitude == pytest.approx(math.pi, abs=1e-6)
    tcp = one("panda", "frame_twin")
    assert tcp.subject == "panda_hand_tcp" and tcp.magnitude == pytest.approx(0.1034, abs=1e-12)
    assert one("panda", "joint_names").values["pairs"][0][:2] == ["panda_joint1", "joint1"]


def test_iiwa14_has_three_swapped_inertias_damping_and_unbounded_actuators():
    # the MJCF states no damping and its position servos no force bound: unset, so warnings
    assert serious("iiwa14") == [("damping_unset", "warning"), ("effort_unset", "warning")] + [("inertia_rotated", "error")] * 3
    swaps = {f.subject: f.magnitude for f in findings("iiwa14", "inertia_rotated")}
    assert swaps == pytest.approx({"iiwa_link_1": 3e-4, "iiwa_link_2": 0.0194, "iiwa_link_4": 0.0104}, rel=1e-9)
    assert all(f.values["axes"] and "90°" in f.message for f in findings("iiwa14", "inertia_rotated"))
    effort = one("iiwa14", "effort_unset")
    assert effort.magnitude == math.inf and effort.values["urdf"] == [320.0, 320.0, 176.0, 176.0, 110.0, 40.0, 40.0]
    assert effort.values["unset_in"] == "MJCF" and "the MJCF leaves the force on 7 joints unbounded" in effort.message
    damping = one("iiwa14", "damping_unset")
    assert (damping.values["urdf"], damping.values["mjcf"], damping.values["unset_in"]) == (0.5, 0.0, "MJCF")


def test_iiwa14_limits_rounding_end_effector_and_drake_rotors_are_information():
    limits = one("iiwa14", "rounding")
    assert limits.values["file"] == "MJCF" and limits.magnitude == pytest.approx(4.9e-6, rel=0.01)
    twins = {f.subject: f for f in findings("iiwa14", "frame_twin")}
    assert twins["iiwa_link_ee_kuka"].other == "attachment_site" and twins["iiwa_link_ee_kuka"].magnitude < 1e-12
    assert twins["iiwa_link_ee"].values["rotation_rad"] == pytest.approx(math.pi / 2, abs=1e-9)
    assert one("iiwa14", "format_extension").magnitude == pytest.approx(160**2 * 1.321e-4, rel=1e-9)


def test_z1_lacks_the_gripper_in_the_mjcf_and_bounds_no_torque():
    assert serious("z1") == [("effort_unset", "warning"), ("extra_parts", "error")]
    gripper = one("z1", "extra_parts")
    assert gripper.values["file"] == "URDF" and gripper.values["joints"] == ["jointGripper"]
    assert {p["name"]: p["mass"] for p in gripper.values["links"]} == {"gripperStator": 0.52603655, "gripperMover": 0.27621302}
    assert gripper.magnitude == pytest.approx(0.80224957, abs=1e-8)
    effort = one("z1", "effort_unset")  # motors with no ctrlrange and no forcerange
    assert effort.magnitude == math.inf and effort.values["urdf"] == [30.0, 60.0, 30.0, 30.0, 30.0, 30.0]
    total = one("z1", "total_mass")
    assert (total.values["urdf"], total.values["mjcf"]) == pytest.approx((5.22096983, 4.418719), abs=1e-9)
    assert {f.values["file"] for f in findings("z1", "rounding")} == {"MJCF"}  # limits and inertials, 6 digits


def test_go2_differs_in_rotor_masses_calves_and_joint_dynamics():
    assert serious("go2") == [
        ("damping_unset", "warning"),
        ("extra_parts", "error"),
        ("friction_unset", "warning"),
        ("inexpressible", "warning"),
        ("mass_difference", "error"),
    ]
    rotors = one("go2", "extra_parts")
    assert len(rotors.values["links"]) == 12 and all(
        p["name"].endswith("_rotor") and p["mass"] == 0.089 for p in rotors.values["links"]
    )
    assert rotors.magnitude == pytest.approx(1.068, abs=1e-9)
    calves = one("go2", "mass_difference")
    assert calves.subject == "FL_calf, FR_calf, RL_calf, RR_calf"
    assert calves.magnitude == pytest.approx(0.047352, abs=1e-9) and calves.values["com_distance_m"] == pytest.approx(
        6.5e-3, abs=1e-4
    )
    damping, friction = one("go2", "damping_unset"), one("go2", "friction_unset")  # the URDF has no <dynamics>
    assert (damping.values["mjcf"], friction.values["mjcf"]) == (2.0, 0.2)
    assert damping.values["unset_in"] == friction.values["unset_in"] == "URDF"
    assert one("go2", "total_mass").values["difference_kg"] == pytest.approx(-0.878592, abs=1e-9)


def test_go2_free_base_is_fixed_at_the_same_pose_in_both_files():
    assert one("go2", "floating_base").severity == "info"
    assert one("go2", "frame_twin").subject == "radar"  # only in the URDF
    assert "imu" in result("go2").frames


@pytest.mark.parametrize("robot", list(FILES))
def test_drake_reads_both_files_and_says_what_its_mjcf_parser_ignores(robot):
    if "drake-mjcf" not in result(robot).backends and not findings(robot, "parser_disagreement"):
        pytest.skip("Drake (the drake extra) is not installed")
    ignored = [
        f
        for f in result(robot).findings
        if f.kind in ("parser_refused", "parser_ignores") and f.values.get("backend") == "drake-mjcf"
    ]
    assert 1 <= len(ignored) <= 2 and all(f.values["elements"] for f in ignored)
    for f in ignored:  # named element by element; a warning only for what is compared through Drake (sites)
        assert all(e in f.message for e in f.values["elements"])
        assert f.severity == ("warning" if f.kind == "parser_refused" else "info")
        assert (f.kind == "parser_refused") == any("<site>" in e or "<equality>" in e for e in f.values["elements"])
    assert "drake-urdf" in result(robot).backends


def test_go2_thigh_axes_drake_stands_apart_from_mujoco_and_pinocchio():
    """Drake 1.51.1's MJCF parser does not take the joint axis from a grandparent default class
    (front_hip in hip in go2): the thigh joints turn about z, not y. Three readings of one MJCF:
    the finding names the two that agree and the one that stands apart."""
    apart = [f for f in findings("go2", "parser_disagreement") if f.values.get("apart") == "drake-mjcf"]
    if not apart:
        pytest.skip("Drake (the drake extra) is not installed")
    (f,) = apart
    # with the newton extra, Newton's reading joins the majority
    assert [a for a in f.values["agree"] if a != "newton-mjcf"] == ["mujoco", "pinocchio-mjcf"] and f.values["file"] == "MJCF"
    assert re.search(
        r"read alike by mujoco(, pinocchio-mjcf and newton-mjcf| and pinocchio-mjcf), and differently by drake-mjcf", f.message
    ), f.message
    assert f.values["rotation_rad"] > 3.0 and f.values["position_m"] > 0.1  # the thigh turned about another axis
    assert "drake-mjcf" not in result("go2").backends  # left out of the comparison between the files


@pytest.mark.parametrize("robot", list(FILES))
def test_every_pair_reaches_its_verdict_with_every_failing_check_explained(robot):
    r = result(robot)
    assert r.verdict == "fail" and r.exit_code == 1 and not r.internal_errors
    assert not r.failed, [(c.property, c.frame, c.backends, c.max_error) for c in r.failed]
    assert not findings(robot, "disagreement_starts") and not findings(robot, "dynamics_difference")


def test_a1_hips_sit_2_5_mm_further_out_on_all_four_legs():
    """The base bodies fix the frame (both float): the hips 2.5 mm further out along x (their own
    axis), front and rear alike, and the thighs 1.25 mm further out along y (theirs), each said once
    of all four legs as a moved joint frame (nothing they carry blamed for it), with the trunk
    1.288 kg lighter in the MJCF."""
    assert serious("a1") == [
        ("damping_difference", "error"),
        ("damping_difference", "error"),
        ("inexpressible", "warning"),
        ("joint_origin_moved", "error"),
        ("joint_origin_moved", "error"),
        ("mass_difference", "error"),
    ]
    assert not findings("a1", "base_frame_offset")
    hips, thighs = sorted(findings("a1", "joint_origin_moved"), key=lambda f: f.magnitude, reverse=True)
    assert hips.subject == "FL_hip_joint, FR_hip_joint, RL_hip_joint, RR_hip_joint"
    assert hips.magnitude == pytest.approx(2.5e-3, abs=1e-9)
    assert sum(hips.values["xyz_each"], []) == pytest.approx([2.5e-3, 0, 0] * 2 + [-2.5e-3, 0, 0] * 2, abs=1e-9)
    assert thighs.subject == "FL_thigh_joint, FR_thigh_joint, RL_thigh_joint, RR_thigh_joint"
    assert sum(thighs.values["xyz_each"], []) == pytest.approx([0, 1.25e-3, 0, 0, -1.25e-3, 0] * 2, abs=1e-9)
    trunk = one("a1", "mass_difference")
    assert (trunk.subject, trunk.values["urdf"]["mass"], trunk.values["mjcf"]["mass"]) == ("trunk", 6.001, 4.713)
    assert trunk.values["com_distance_m"] < 1e-6  # the trunk's centre of mass is where it is in both
    dampings = sorted((f.values["urdf"], f.values["mjcf"]) for f in findings("a1", "damping_difference"))
    assert dampings == [(0.01, 1.0), (0.01, 2.0)]


def test_anymal_c_base_lacks_7_kg_and_states_joint_damping_and_friction():
    assert serious("anymal_c") == [
        ("damping_difference", "error"),
        ("friction_difference", "error"),
        ("mass_difference", "error"),
    ] + [("nonphysical_inertia", "error")] * 5 + [("parser_refused", "warning")]
    base = one("anymal_c", "mass_difference")
    assert base.subject == "base" and base.values["urdf"]["mass"] == pytest.approx(26.37317, abs=1e-9)
    assert base.values["mjcf"]["mass"] == pytest.approx(19.2035, abs=1e-9)
    assert {f.subject for f in findings("anymal_c", "nonphysical_inertia")} == {
        "depth_camera_front_camera",
        "depth_camera_rear_camera",
        "depth_camera_left_camera",
        "depth_camera_right_camera",
        "hatch",
    }
    assert one("anymal_c", "parser_refused").values["backend"] == "mujoco-urdf"  # MuJoCo refuses those inertias
    damping, friction = one("anymal_c", "damping_difference"), one("anymal_c", "friction_difference")
    assert (damping.values["urdf"], damping.values["mjcf"], friction.values["urdf"], friction.values["mjcf"]) == (
        0.0,
        1.0,
        0.0,
        0.1,
    )
    assert damping.values["unset_in"] is None  # the URDF writes damping="0.0": stated, so an error


def test_leap_hand_fingers_matched_by_place_differ_in_centres_of_mass_and_two_thumb_limits():
    r = result("leap_hand")
    pairs = {a: b for a, b, *_ in r.model_info["joint_pairs"]}
    assert (pairs["1"], pairs["0"], pairs["12"], pairs["13"], pairs["5"], pairs["9"]) == (
        "if_mcp",
        "if_rot",
        "th_cmc",
        "th_axl",
        "mf_mcp",
        "rf_mcp",
    )
    assert serious("leap_hand") == [("base_inertial_difference", "warning"), ("base_transform", "error")] + [
        ("com_difference", "error")
    ] * 7 + [
        ("damping_unset", "warning"),
        ("effort_unset", "warning"),
        ("friction_unset", "warning"),
        ("limit_difference", "error"),
        ("limit_difference", "error"),
    ]
    limits = {f.subject: (f.values["urdf"], f.values["mjcf"]) for f in findings("leap_hand", "limit_difference")}
    assert limits == {"13": ([-0.47, 2.443], [-0.349, 2.094]), "14": ([-1.2, 1.9], [-0.47, 2.443])}
    coms = {f.subject: f.magnitude for f in findings("leap_hand", "com_difference")}
    assert coms["mcp_joint, mcp_joint_2, mcp_joint_3"] == pytest.approx(0.04385, abs=1e-5)  # three fingers alike
    assert one("leap_hand", "damping_unset").values["unset_in"] == "URDF"


def test_ur5e_world_turned_forearm_longer_and_every_link_a_different_mass():
    """ur_description against Menagerie: the world turned by π, wrist 1's axis 0.2 mm further
    (forearm 0.3922 against 0.392 m), wrist 2's 0.7 mm further along the parallel axes (d4 0.1333
    against 0.138 − 0.131 + 0.127 m) and wrist 3's 0.3 mm (d5 0.0997 against 0.1 m), each measured
    in its own right, and every link's mass; the wrist bodies' centres of mass 16-21 mm apart, and
    wrist 1's inertia turned about its centre of mass."""
    assert (
        serious("ur5e")
        == [("axis_position", "error")] * 3
        + [
            ("base_inertial_difference", "warning"),
            ("base_transform", "error"),
            ("inexpressible", "warning"),
            ("limit_difference", "error"),
        ]
        + [("mass_difference", "error")] * 6
    )
    turn = one("ur5e", "base_transform")
    assert turn.values["rotation_rad"] == pytest.approx(math.pi, abs=1e-9)
    axes = {f.subject: f.magnitude for f in findings("ur5e", "axis_position")}
    assert axes == pytest.approx({"wrist_1_joint": 2e-4, "wrist_2_joint": 7e-4, "wrist_3_joint": 3e-4}, abs=1e-9)
    coms = {f.subject: f.values["com_distance_m"] for f in findings("ur5e", "mass_difference")}
    assert coms == pytest.approx(
        {
            "shoulder_link": 0.02568,
            "upper_arm_link": 0.02464,
            "forearm_link": 0.05015,
            "wrist_1_link": 0.01653,
            "wrist_2_link": 0.01647,
            "wrist_3_link": 0.02127,
        },
        abs=1e-5,
    )
    wrist = next(f for f in findings("ur5e", "mass_difference") if f.subject == "wrist_1_link")
    assert wrist.values["inertia_difference_kgm2"] == pytest.approx(3.657e-4, rel=1e-3) and "turned 90°" in wrist.message


def test_ur5e_from_its_xacro_sources_gives_the_same_findings():
    """The same URDF compiled from ur_description's xacro (name:=ur5e ur_type:=ur5e)."""
    folder = REAL / "ur5e"
    if not folder.is_dir():
        pytest.skip(f"{folder} absent")
    with given_packages({"ur_description": str(folder / "ur_description")}, {"name": "ur5e", "ur_type": "ur5e"}):
        r = verify_files(str(folder / "ur_description" / "urdf" / "ur.urdf.xacro"), str(folder / "ur5e_menagerie.xml"), OPTIONS)
    assert sorted((f.kind, f.subject) for f in r.findings if f.severity == "error") == sorted(
        (f.kind, f.subject) for f in result("ur5e").findings if f.severity == "error"
    )
