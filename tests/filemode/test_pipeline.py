"""File mode on generated pairs: an identical pair agrees; each edit a real pair differs by is
found once, by value, naming the joint or link, with the right verdict; what alignment explains
is not a failure; bad input is one line (exit 2); kinverify's own failure exits 3 with a report."""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.cli import main
from kinverify.errors import InputError
from kinverify.backends import names_reading
from kinverify.filemode.pipeline import _failed, _guarded, _readers, add_map, diagnose_files, relabel, verify_files, verify_three
from kinverify.generate import generate_sdf
from kinverify.generate.usd import generate_usd
from kinverify.model.specfile import load_spec
from kinverify.results import VerifyResult
from kinverify.model.floating import BASE_COORDINATES
from kinverify.run import VerifyOptions
from kinverify.suites.base import Check, Finding, Section, Table
from kinverify.versions import library_versions
from tests.filemode.pairs import write_pair
from tests.paths import MODELS
import kinverify.filemode.align.run as align_stage

FAST = VerifyOptions(
    samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], extra={"dynamics_samples": 12}, suites=P.NO_PICTURES
)
ALL = VerifyOptions(samples=8, fd_samples=4, extra={"dynamics_samples": 12}, suites=P.NO_PICTURES)


def run(tmp_path, edit=None, model="panda", options=FAST, **kwargs):
    urdf, mjcf = P.generated_pair(model)
    if edit is not None:
        urdf, mjcf = edit(urdf, mjcf)
    return verify_files(*write_pair(tmp_path, urdf, mjcf), options, **kwargs)


def above_info(result) -> list:
    return [f for f in result.findings if f.severity != "info"]


def only(result, kind: str):
    hits = [f for f in result.findings if f.kind == kind]
    assert len(hits) == 1, [(f.kind, f.label) for f in result.findings]
    return hits[0]


@pytest.mark.parametrize("model", ["panda", "scara", "lift"])
def test_a_generated_pair_agrees_with_every_library(tmp_path, model):
    result = run(tmp_path, model=model, options=ALL)
    assert result.passed, ([c for c in result.failed], above_info(result))
    assert {f.kind for f in result.findings if not P.ignored_by_drake(f)} <= {
        "world_parts",
        "inexpressible",
    }  # mount body, armature
    assert {"pinocchio-urdf", "yourdfpy", "mujoco-urdf", "mujoco", "pinocchio-mjcf"} <= set(result.backends)
    assert {"kinematics", "limits", "inertia", "dynamics"} <= set(result.timings)
    data = result.to_dict()
    assert VerifyResult.from_dict(data).findings == result.findings
    assert np.allclose(data["sections"]["filemode"]["data"]["alignment"]["T_mjcf_from_urdf"], np.eye(4))


# --- what alignment solves: one finding each, the checks compare after it -----------------------


@pytest.mark.parametrize("angle,xyz", [(math.pi / 4, None), (math.pi, None), (0.3, [0.1, -0.2, 0.3])])
def test_a_turned_world_is_one_finding_and_the_rest_agrees(tmp_path, angle, xyz):
    result = run(tmp_path, lambda u, m: P.turned_world(u, m, angle, xyz))
    f = only(result, "base_transform")
    assert f.severity == "error" and f.magnitude == pytest.approx(max(angle, np.linalg.norm(xyz or [0])), abs=1e-12)
    assert f.values["rpy"] == pytest.approx([0, 0, angle], abs=1e-12)
    assert f.values["xyz"] == pytest.approx(xyz or [0, 0, 0], abs=1e-12)
    assert [x.kind for x in above_info(result)] == ["base_transform"]
    assert not result.failed and result.verdict == "fail"


def test_pinocchios_mjcf_parser_dropping_the_top_level_pose_is_information_with_its_size(tmp_path):
    result = run(tmp_path, lambda u, m: P.turned_world(u, m, math.pi / 4), options=ALL)
    quirk = only(result, "parser_quirk")
    assert quirk.severity == "info" and quirk.magnitude == pytest.approx(math.pi / 4, abs=1e-12) and "2782" in quirk.message
    assert "pinocchio-mjcf" in result.backends and not result.failed


@pytest.mark.parametrize("joint,offset", [("panda_joint4", 0.1), ("panda_joint1", -1.2), ("panda_joint6", math.pi / 2)])
def test_a_joint_zero_offset_is_one_finding_and_limits_are_compared_after_it(tmp_path, joint, offset):
    result = run(tmp_path, lambda u, m: P.offset_zero(u, m, joint, offset))
    f = only(result, "zero_offset")
    assert f.subject == joint and f.values["offset"] == pytest.approx(offset, abs=1e-12)
    assert [x.kind for x in above_info(result)] == ["zero_offset"] and not result.failed


def test_a_reversed_axis_is_one_finding(tmp_path):
    result = run(tmp_path, P.flipped_axis)
    assert only(result, "axis_sign_flip").subject == "panda_joint3"
    assert [x.kind for x in above_info(result)] == ["axis_sign_flip"] and not result.failed


def test_renamed_joints_are_matched_and_said_once(tmp_path):
    result = run(tmp_path, P.renamed_joints)
    assert result.passed and only(result, "joint_names").values["pairs"][0][:2] == ["panda_joint1", "J1"]


def test_a_frame_turned_by_a_constant_is_a_convention_compared_after_removing_it(tmp_path):
    def turned_flange(urdf, mjcf):
        return urdf, re.sub(r'(<site name="flange"[^>]*?)/>', r'\1 quat="0 0 0 1"/>', mjcf, count=1)

    result = run(tmp_path, turned_flange)
    f = only(result, "frame_convention")
    assert f.subject == "flange" and f.magnitude == pytest.approx(math.pi, abs=1e-12) and result.passed


# --- what one file has and the other lacks ----------------------------------------------------


def test_a_fixed_link_merged_into_its_parent_is_information(tmp_path):
    result = run(tmp_path, P.merged_fixed_link, model="arm3")
    f = only(result, "lumped_links")
    assert f.subject == "tool" and f.magnitude == pytest.approx(P.TOOL["mass"], rel=1e-12)
    assert result.passed, above_info(result)


def test_an_extra_flange_is_matched_by_position_with_its_offset(tmp_path):
    result = run(tmp_path, P.extra_flange)
    f = only(result, "frame_twin")
    assert (f.subject, f.other) == ("tool_flange", "flange") and f.magnitude == pytest.approx(0.0165, abs=1e-12)
    assert result.passed


def test_a_gripper_in_one_file_only_is_one_error_with_its_mass(tmp_path):
    result = run(tmp_path, P.gripper_in_mjcf)
    f = only(result, "extra_parts")
    assert f.severity == "error" and f.values["file"] == "MJCF" and f.values["joints"] == ["gripper_joint"]
    assert f.magnitude == pytest.approx(0.1, rel=1e-12)
    assert [x.kind for x in above_info(result)] == ["extra_parts"] and not result.failed and result.verdict == "fail"


# --- values: rounding passes, units and real differences fail, once ---------------------------


def test_values_rounded_to_six_digits_are_information_and_pass(tmp_path):
    result = run(tmp_path, P.rounded_mjcf)
    assert result.passed, above_info(result)
    assert [f.values["file"] for f in result.findings if f.kind == "rounding"] == ["MJCF"]


def test_joint_ranges_read_in_degrees_are_one_finding(tmp_path):
    result = run(tmp_path, P.degrees_mjcf)
    f = only(result, "limit_units")
    assert f.subject == ", ".join(f"panda_joint{i}" for i in range(1, 8)) and "degrees" in f.message
    assert [x.kind for x in above_info(result)] == ["limit_units"]


def test_masses_in_grams_are_one_finding(tmp_path):
    result = run(tmp_path, P.grams_mjcf)
    assert only(result, "mass_units").magnitude == pytest.approx(1000, rel=1e-9)
    assert [x.kind for x in above_info(result)] == ["mass_units"]


@pytest.mark.parametrize(
    "edit,kind,subject,magnitude",
    [
        (P.heavier_link, "mass_difference", "panda_link4", 0.2 * 3.587895),
        (P.upper_limit, "limit_difference", "panda_joint2", 0.2),
        (P.friction_added, "friction_difference", "panda_joint5", 0.3),
        (P.moved_axis, "joint_origin_moved", "panda_joint3", 1e-3),
    ],
)
def test_a_real_difference_fails_with_one_error_finding_by_value(tmp_path, edit, kind, subject, magnitude):
    result = run(tmp_path, edit)
    f = only(result, kind)
    assert f.severity == "error" and f.subject == subject and f.magnitude == pytest.approx(magnitude, rel=1e-6)
    assert [x.kind for x in above_info(result)] == [kind]
    assert result.verdict == "fail" and result.exit_code == 1 and not result.failed  # explained checks do not count twice


def test_swapped_inertia_axes_are_found_with_their_size(tmp_path):
    result = run(tmp_path, P.swapped_inertia)
    f = only(result, "inertia_rotated")
    assert f.subject == "panda_link3" and f.values["axes"] and f.magnitude > 1e-3
    explained = [c for c in result.checks if c.property == "inertia.tensor"]
    assert explained and explained[0].kind == "explained" and "inertia_rotated" in explained[0].note


def test_a_joint_type_difference_explains_the_kinematics_and_dynamics_it_breaks(tmp_path):
    result = run(tmp_path, P.slide_joint)
    assert only(result, "type_difference").subject == "panda_joint7"
    failing = [c for c in result.checks if not c.passed]
    assert failing and all(c.kind == "explained" for c in failing)


# --- acceptance ------------------------------------------------------------------------------


def test_accepted_differences_pass_and_a_changed_one_fails(tmp_path):
    accepted = tmp_path / "kinverify-accepted.toml"
    first = run(tmp_path, P.friction_added, write_accepted=str(accepted))
    assert first.verdict == "fail" and 'kind = "friction_difference"' in accepted.read_text()
    again = run(tmp_path, P.friction_added)  # the file beside the URDF is read by default
    assert again.passed and only(again, "friction_difference").accepted
    changed = run(tmp_path, lambda u, m: (u, P.joint_attr(m, "panda_joint5", "frictionloss", lambda v: "0.4")))
    f = only(changed, "friction_difference")
    assert not f.accepted and "accepted at 0.3" in f.message and changed.verdict == "fail"
    new = run(tmp_path, lambda u, m: P.upper_limit(*P.friction_added(u, m)))
    assert new.verdict == "fail" and [f.kind for f in new.failing_findings] == ["limit_difference"]


def test_a_broken_accepted_file_is_a_one_line_error(tmp_path, capsys):
    urdf, mjcf = write_pair(tmp_path, *P.generated_pair("arm3"))
    (tmp_path / "bad.toml").write_text("[[accepted]]\nkind = 3\n")
    code = main(
        [
            "verify",
            "--urdf",
            urdf,
            "--mjcf",
            mjcf,
            "--accept",
            str(tmp_path / "bad.toml"),
            "--quiet",
            "--json",
            str(tmp_path / "r.json"),
            "--report",
            str(tmp_path / "r.html"),
        ]
    )
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and "bad.toml" in err and not (tmp_path / "r.json").exists()


# --- never crash -----------------------------------------------------------------------------


def test_a_link_and_a_joint_named_alike_are_read_by_their_type(tmp_path):
    def clash(urdf, mjcf):
        return urdf.replace('"end_effector"', '"joint3"'), mjcf.replace('"end_effector"', '"joint3"')

    result = run(tmp_path, clash, model="arm3", options=ALL)
    assert result.passed and "joint3" in result.frames and "pinocchio-urdf" in result.backends


def test_mimic_joints_are_driven_by_their_leader_in_every_library(tmp_path):
    def gripper(urdf, mjcf):
        links = (
            '<link name="f1"><inertial><mass value="0.1"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" '
            'iyz="0"/></inertial></link><link name="f2"><inertial><mass value="0.1"/><inertia ixx="1e-5" iyy="1e-5" '
            'izz="1e-5" ixy="0" ixz="0" iyz="0"/></inertial></link>'
            '<joint name="g1" type="prismatic"><parent link="link3"/><child link="f1"/><axis xyz="0 1 0"/>'
            '<limit lower="0" upper="0.04" effort="10" velocity="1"/></joint>'
            '<joint name="g2" type="prismatic"><parent link="link3"/><child link="f2"/><axis xyz="0 -1 0"/>'
            '<limit lower="0" upper="0.04" effort="10" velocity="1"/><mimic joint="g1"/></joint>'
        )
        bodies = (
            '<body name="f1"><joint name="g1" type="slide" axis="0 1 0" range="0 0.04"/><inertial pos="0 0 0" '
            'mass="0.1" diaginertia="1e-5 1e-5 1e-5"/></body><body name="f2"><joint name="g2" type="slide" '
            'axis="0 -1 0" range="0 0.04"/><inertial pos="0 0 0" mass="0.1" diaginertia="1e-5 1e-5 1e-5"/></body>'
        )
        return (
            urdf.replace("</robot>", links + "</robot>"),
            P.sub_once(r'(<body name="link3"[^>]*>)', lambda m: m[1] + bodies, mjcf).replace(
                "</mujoco>", '<equality><joint joint1="g2" joint2="g1"/></equality></mujoco>'
            ),
        )

    result = run(tmp_path, gripper, model="arm3", options=ALL)
    assert "yourdfpy" in result.backends and not [
        f for f in result.findings if f.kind == "parser_refused" and not P.ignored_by_drake(f)
    ]
    assert result.joint_names == ["joint1", "joint2", "joint3", "g1"] and result.passed, above_info(result)


def test_a_mesh_mujoco_cannot_read_is_dropped_with_a_warning(tmp_path):
    (tmp_path / "broken.stl").write_bytes(b"not a mesh at all")

    def broken_mesh(urdf, mjcf):
        return urdf, mjcf.replace("<worldbody>", '<asset><mesh name="broken" file="broken.stl"/></asset><worldbody>', 1).replace(
            '<body name="link3" pos="0.0 0.0 0.25">',
            '<body name="link3" pos="0.0 0.0 0.25"><geom type="mesh" mesh="broken" mass="0"/>',
            1,
        )

    result = run(tmp_path, broken_mesh, model="arm3")
    refused = only(result, "parser_refused")
    assert refused.severity == "warning" and "mesh" in refused.message and result.passed


def test_a_joint_type_one_library_lacks_is_a_finding_not_a_crash(tmp_path):
    def planar(urdf, mjcf):
        extra = (
            '<link name="slider"><inertial><mass value="0.1"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" '
            'ixz="0" iyz="0"/></inertial></link><joint name="plane" type="planar"><parent link="link3"/>'
            '<child link="slider"/><axis xyz="0 0 1"/></joint>'
        )
        return urdf.replace("</robot>", extra + "</robot>"), mjcf

    result = run(tmp_path, planar, model="arm3", options=ALL)
    assert result.verdict in ("pass", "fail") and not result.internal_errors
    assert any("plane" in n for n in result.notes)


def test_kinverifys_own_failure_exits_3_and_still_writes_the_report(tmp_path, monkeypatch, capsys):
    def broken(*args, **kwargs):
        raise ZeroDivisionError("planted")

    monkeypatch.setattr(align_stage, "align", broken)
    urdf, mjcf = write_pair(tmp_path, *P.generated_pair("arm3"))
    code = main(
        [
            "verify",
            "--urdf",
            urdf,
            "--mjcf",
            mjcf,
            "--samples",
            "4",
            "--backends",
            "pinocchio-urdf,mujoco",
            "--quiet",
            "--json",
            str(tmp_path / "r.json"),
            "--report",
            str(tmp_path / "r.html"),
        ]
    )
    out = capsys.readouterr().out
    assert code == 3 and "internal error" in out and "planted" in out
    assert (tmp_path / "r.json").exists() and (tmp_path / "r.html").exists()
    monkeypatch.setattr("kinverify.filemode.pipeline.read_mjcf", broken)
    result = verify_files(urdf, mjcf, FAST)
    assert result.verdict == "error" and result.exit_code == 3 and "planted" in result.internal_errors[0]


# --- bad input -------------------------------------------------------------------------------

XXE = '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]><robot name="r">&x;</robot>'
FIXED_ONLY = '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint></robot>'
SLIDER = (
    '<mujoco model="s"><worldbody><body name="b"><joint name="slider" type="slide" axis="1 0 0"/>'
    '<inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/></body></worldbody></mujoco>'
)


@pytest.mark.parametrize(
    "case,message",
    [
        ("missing", "is not a file"),
        ("not_xml", "is not XML"),
        ("urdf_as_mjcf", "is a URDF, not an MJCF"),
        ("xxe", "entities"),
        ("no_movable", "no movable"),
        ("no_common", "no common joints"),
    ],
)
def test_bad_input_is_a_one_line_input_error(tmp_path, case, message, capsys):
    urdf, mjcf = write_pair(tmp_path, *P.generated_pair("arm3"))
    if case == "missing":
        urdf = str(tmp_path / "absent.urdf")
    elif case == "not_xml":
        Path(mjcf).write_text("this is not xml <")
    elif case == "urdf_as_mjcf":
        mjcf = urdf
    elif case == "xxe":
        Path(urdf).write_text(XXE)
    elif case == "no_movable":
        Path(urdf).write_text(FIXED_ONLY)
    elif case == "no_common":
        Path(mjcf).write_text(SLIDER)
    with pytest.raises(InputError, match=message):
        verify_files(urdf, mjcf, FAST)
    code = main(
        [
            "verify",
            "--urdf",
            urdf,
            "--mjcf",
            mjcf,
            "--samples",
            "5",
            "--json",
            str(tmp_path / "r.json"),
            "--report",
            str(tmp_path / "r.html"),
        ]
    )
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and message in err


def test_diagnose_files_reports_the_alignment_before_any_suite_runs(tmp_path):
    urdf, mjcf = P.turned_half(*P.generated_pair("panda"))
    diag = diagnose_files(*write_pair(tmp_path, urdf, mjcf))
    assert np.allclose(diag["alignment"].T[:3, :3], np.diag([-1, -1, 1]), atol=1e-12)
    assert diag["reference"] == "pinocchio-urdf" and [f.kind for f in diag["findings"]][:1] == ["base_transform"]


# --- the pipeline's own decisions, on cheap runs (limits only) and its helpers called directly ---

LIMITS = VerifyOptions(samples=4, fd_samples=2, suites=["limits"], backends=["pinocchio-urdf", "mujoco"])
SDF_NOTE = (
    "SDF: read by Drake, its only reader here; compared: kinematics, limits and inertials (dynamics and the "
    "drawings need Pinocchio and MuJoCo on both files)"
)


@pytest.fixture(scope="module")
def arm3_files(tmp_path_factory) -> tuple[str, str, str]:
    """The generated arm3 URDF, MJCF and SDF, written once."""
    folder = tmp_path_factory.mktemp("arm3")
    urdf, mjcf = write_pair(folder, *P.generated_pair("arm3"))
    (folder / "arm3.sdf").write_text(generate_sdf(load_spec(MODELS / "arm3.toml")))
    return urdf, mjcf, str(folder / "arm3.sdf")


def floating_arm3() -> tuple[str, str]:
    """arm3's URDF and MJCF texts with its root joint floating (the MJCF's base free)."""
    urdf, mjcf = P.generated_pair("arm3")
    urdf = P.sub_once(r'<joint name="world_to_base" type="fixed">', '<joint name="world_to_base" type="floating">', urdf)
    mjcf = P.sub_once(r'<body name="world_mount">\s*<inertial[^>]*/>\s*', "", mjcf)
    end = mjcf.rindex("</body>")
    mjcf = P.sub_once(r'(<body name="base" pos="[^"]*">)', r"\1<freejoint/>", mjcf[:end] + mjcf[end + len("</body>") :])
    return urdf, mjcf


@pytest.fixture(scope="module")
def floating_files(tmp_path_factory) -> tuple[str, str]:
    """arm3 with its root joint floating (the MJCF's base free), written once."""
    return write_pair(tmp_path_factory.mktemp("floating"), *floating_arm3())


@pytest.fixture  # per test: mutmut credits a call only to the test that makes it
def floating(floating_files) -> dict:
    return diagnose_files(*floating_files)


ARM3_LIMITS = ([-math.pi, -math.pi / 2, -3 * math.pi / 4], [math.pi, math.pi / 2, 3 * math.pi / 4])  # models/arm3.toml


def test_a_floating_base_samples_six_base_coordinates_first_pitch_kept_off_its_poles(floating):
    """x, y, z within ±1 m of the home position (0), roll and yaw over ±π, pitch ±(π/2 − 1e-3), then the joints."""
    margin = math.pi / 2 - 1e-3
    assert floating["lower"] == pytest.approx([-1, -1, -1, -math.pi, -margin, -math.pi, *ARM3_LIMITS[0]], abs=1e-12)
    assert floating["upper"] == pytest.approx([1, 1, 1, math.pi, margin, math.pi, *ARM3_LIMITS[1]], abs=1e-12)
    assert floating["revolute"] == [False, False, False, True, True, True, True, True, True]
    assert floating["info"].base_coordinates and floating["reference"] == "pinocchio-urdf"
    assert 'type="floating"' in floating["urdf_text"] and "<freejoint" in floating["mjcf_text"]  # the files as they float
    assert "world" not in [a for a, _, _ in floating["matching"].frames]  # the URDF's link above the floating root
    base = floating["findings"][0]  # said first, with what floats in each file
    assert (base.kind, base.severity) == ("floating_base", "info")
    assert base.values == {"urdf": "floating", "urdf_root": "world", "mjcf_free_bodies": ["base"]}


def test_a_floating_runs_coordinates_are_the_six_base_ones_then_the_joints(floating_files):
    result = verify_files(*floating_files, LIMITS)
    assert result.joint_names == [*BASE_COORDINATES, "joint1", "joint2", "joint3"]
    assert result.lower[4] == pytest.approx(-math.pi / 2 + 1e-3, abs=1e-12) and result.upper[6:] == pytest.approx(ARM3_LIMITS[1])
    assert result.passed and not result.internal_errors


def test_the_notes_say_each_sides_written_precision(floating):
    assert floating["notes"] == [
        "written precision: the URDF writes masses and inertias to 16 significant digits (0.0003333543964724129), "
        "joint limits to 15 decimals (-3.141592653589793); the MJCF writes masses and inertias to 16 significant "
        "digits (0.0003333543964724129), joint limits to 15 decimals (-3.141592653589793)"
    ]


def test_each_sides_joints_not_compared_are_notes_naming_the_side(tmp_path):
    """A planar joint in the URDF and a ball joint in the MJCF (each on its own extra body): notes prefixed by their file."""
    urdf, mjcf = P.generated_pair("arm3")
    urdf = urdf.replace(
        "</robot>",
        '<link name="slider"><inertial><mass value="0.1"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" '
        'iyz="0"/></inertial></link><joint name="plane" type="planar"><parent link="link3"/><child link="slider"/>'
        '<axis xyz="0 0 1"/></joint></robot>',
    )
    mjcf = P.sub_once(
        r'(<body name="link3"[^>]*>)',
        r'\1<body name="knob"><joint name="knob_ball" type="ball"/><inertial pos="0 0 0" mass="0.1" diaginertia="1e-5 1e-5 1e-5"/></body>',
        mjcf,
    )
    diag = diagnose_files(*write_pair(tmp_path, urdf, mjcf))
    notes = diag["notes"]
    assert "URDF: plane: JointModelPlanar has 4 coordinates; only 1-DOF joints are compared (held at neutral)" in notes
    assert "MJCF: knob_ball: mjJNT_BALL joints are not compared (held at 0)" in notes
    assert notes[-1].startswith("written precision: the URDF writes")
    assert diag["lower"] == pytest.approx(ARM3_LIMITS[0]) and diag["upper"] == pytest.approx(ARM3_LIMITS[1])
    assert diag["revolute"] == [True, True, True]


def test_readers_put_each_formats_own_library_first_and_yourdfpy_last():
    assert _readers("urdf")[0] == "pinocchio-urdf" and _readers("urdf")[-1] == "yourdfpy"
    assert sorted(_readers("urdf")) == sorted(names_reading("urdf"))
    assert _readers("mjcf")[0] == "mujoco" and "yourdfpy" not in _readers("mjcf")


def test_guarded_returns_the_value_or_records_kinverifys_own_failure():
    internal: list[str] = []
    assert _guarded(internal, "step", lambda: 5, 0) == 5 and internal == []
    assert _guarded(internal, "step", lambda: 1 / 0, "fallback") == "fallback"
    assert internal == ["file mode, step: ZeroDivisionError: division by zero"]

    def bad_input():
        raise InputError("x.urdf: bad")

    with pytest.raises(InputError, match="x.urdf: bad"):  # the user's error is not kinverify's
        _guarded(internal, "step", bad_input, None)

    def interrupted():
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        _guarded(internal, "step", interrupted, None)
    assert len(internal) == 1


def test_a_failed_run_names_both_files_and_exits_3():
    result = _failed("a/x.urdf", "b/y.sdf", VerifyOptions(seed=7), ["boom"], "kinverify verify", ("urdf", "sdf"))
    assert (result.model, result.source, result.seed, result.command) == ("x-vs-y", "a/x.urdf + b/y.sdf", 7, "kinverify verify")
    assert result.internal_errors == ["boom"] and result.model_info == {"files": {"urdf": "a/x.urdf", "sdf": "b/y.sdf"}}
    assert (result.verdict, result.exit_code, result.samples, result.checks) == ("error", 3, 0, [])
    assert result.versions == library_versions()  # what the report names of the libraries
    assert _failed("x.urdf", "y.xml", VerifyOptions(), [], "").model_info == {"files": {"urdf": "x.urdf", "mjcf": "y.xml"}}


def _labelled_result() -> VerifyResult:
    message = "the MJCF's body b has a free joint; the MJCF's free joint says q_mjcf = −q_urdf; its free body's pos/quat; URDFs"
    return VerifyResult(
        model="m",
        source="s",
        seed=0,
        samples=1,
        joint_names=[],
        frames=[],
        backends=[],
        checks=[Check("limits.position", "j", ("urdf", "mjcf"), 0.0, 0.0, 1.0, True, (), note="the MJCF is wider")],
        versions={},
        notes=["MJCF: a note", "MJCFX"],
        sections={"s": Section("URDF vs MJCF", "the URDF", [Table("MJCF", ["URDF", "x"], [["MJCF", 1.0]])], notes=["q_urdf"])},
        findings=[Finding("base_transform", "error", message, values={"file": "MJCF", "files": ["URDF", 2]})],
    )


def test_relabel_names_each_side_by_its_format_in_every_text():
    result = _labelled_result()
    relabel(result, ("sdf", "mjcf"))
    (f,) = result.findings
    assert f.message == (
        "the MJCF's body b has a free joint; the MJCF's free joint says q_mjcf = −q_sdf; its free body's pos/quat; URDFs"
    )
    assert f.values == {"file": "MJCF", "files": ["SDF", 2]}
    (c,) = result.checks
    assert c.backends == ("sdf", "mjcf") and c.note == "the MJCF is wider"
    s = result.sections["s"]
    assert (s.title, s.summary, s.notes) == ("SDF vs MJCF", "the SDF", ["q_sdf"])
    assert (s.tables[0].title, s.tables[0].columns, s.tables[0].rows) == ("MJCF", ["SDF", "x"], [["MJCF", 1.0]])
    assert result.notes == ["MJCF: a note", "MJCFX"]


def test_relabel_says_how_a_usd_side_floats():
    result = _labelled_result()
    relabel(result, ("urdf", "usd"))
    assert result.findings[0].message == (
        "the USD's body b has no joint to the world; the USD's root body with no joint to the world says "
        "q_usd = −q_urdf; its root body's xform; URDFs"
    )
    assert result.checks[0].backends == ("urdf", "usd") and result.notes == ["USD: a note", "MJCFX"]
    table = result.sections["s"].tables[0]  # a table's title, columns and rows too
    assert (table.title, table.columns, table.rows) == ("USD", ["URDF", "x"], [["USD", 1.0]])


def test_the_map_section_or_a_note_saying_why_it_was_not_made(arm3_files):
    urdf, mjcf, _ = arm3_files
    result = _failed(urdf, mjcf, VerifyOptions(), [], "")
    add_map(result, [urdf, mjcf])
    assert "map" in result.sections and result.notes == [] and result.internal_errors == []
    add_map(result, [urdf, urdf])
    assert result.notes == [f"sim-to-sim map not made: {urdf} is given twice"] and result.internal_errors == []
    add_map(result, [None, 1])  # type: ignore[list-item]  # kinverify's own bug: not a note
    assert len(result.notes) == 1 and result.internal_errors[0].startswith("file mode, the sim-to-sim map: ")


def test_an_sdf_pair_is_relabelled_noted_and_its_files_named(arm3_files):
    urdf, _, sdf = arm3_files
    result = verify_files(urdf, sdf, dataclasses.replace(LIMITS, backends=None), command="cmd", kinds=("urdf", "sdf"))
    assert result.verdict == "pass" and not result.internal_errors and result.command == "cmd"
    assert (result.model, result.source) == ("arm3", f"{urdf} + {sdf}")
    assert result.model_info["files"] == {"urdf": urdf, "sdf": sdf}
    assert result.notes.count(SDF_NOTE) == 1 and "the SDF writes exact values" in result.notes[-2]
    assert set(result.sections) == {"filemode", "limits", "map"}  # limits asked for: no kinematics, no inertia
    assert "drake-sdf" in result.backends and result.duration_s > 0
    assert not any("MJCF" in f.message for f in result.findings)
    every = verify_files(urdf, sdf, dataclasses.replace(LIMITS, backends=None, suites=None), kinds=("urdf", "sdf"))
    assert sorted(every.timings) == ["inertia", "kinematics", "limits"] and every.passed  # no dynamics, no drawings
    asked = dataclasses.replace(LIMITS, backends=None, suites=["limits", "dynamics", "pictures"])
    assert sorted(verify_files(urdf, sdf, asked, kinds=("urdf", "sdf")).timings) == ["limits"]


def test_files_naming_their_robot_differently_name_the_run_after_both(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    result = verify_files(*write_pair(tmp_path, urdf, mjcf.replace('<mujoco model="arm3"', '<mujoco model="other"', 1)), LIMITS)
    assert result.model == "arm3-vs-other" and result.passed and "sdf" not in result.model_info.get("files", {})
    assert set(result.sections) == {"filemode", "limits", "map"} and not any(n.startswith("SDF:") for n in result.notes)


def test_three_files_are_two_pairs_in_one_result_the_mjcf_pair_first(arm3_files):
    urdf, mjcf, sdf = arm3_files
    result = verify_three(urdf, mjcf, sdf, dataclasses.replace(LIMITS, backends=None), command="cmd")
    assert result.source == f"{urdf} + {mjcf} + {sdf}" and result.command == "cmd"
    assert result.model_info["files"] == {"urdf": urdf, "mjcf": mjcf, "sdf": sdf}
    assert set(result.sections) == {"filemode", "limits", "map", "sdf:filemode", "sdf:limits", "sdf:map"}
    assert [result.sections[k].title for k in ("filemode", "sdf:filemode")] == [
        "File mode: URDF vs MJCF",
        "File mode: URDF vs SDF",
    ]
    assert result.notes.count(SDF_NOTE) == 1 and len(result.notes) == len(set(result.notes))
    assert any("the MJCF writes" in n for n in result.notes) and any("the SDF writes" in n for n in result.notes)
    assert {"mujoco", "drake-sdf"} <= set(result.backends) and len(result.backends) == len(set(result.backends))
    assert {c.backends for c in result.checks} == {("urdf", "mjcf"), ("urdf", "sdf")}  # each pair's checks, relabelled
    armature = [f.message.split(" gives")[0] for f in result.findings if f.kind == "inexpressible"]
    assert armature == ["the MJCF", "the SDF"]  # each pair's findings, the MJCF's first
    assert result.verdict == "pass" and not result.internal_errors


def test_three_files_without_a_urdf_anchor_on_the_sdf(arm3_files):
    _, mjcf, sdf = arm3_files
    result = verify_three(None, mjcf, sdf, dataclasses.replace(LIMITS, backends=None))
    assert result.source == f"{mjcf} + {sdf}" and result.model_info["files"] == {"mjcf": mjcf, "sdf": sdf}
    assert set(result.sections) == {"filemode", "limits", "map"} and result.notes.count(SDF_NOTE) == 1


def test_a_site_moved_is_an_error_and_a_frame_at_the_same_place_is_paired_with_its_unnamed_twin(tmp_path):
    """The MJCF's end_effector site 1 cm off the URDF's (a named frame: an error, not a convention);
    a URDF frame tcp where the MJCF has a site tool_center: paired, and aligned as one frame."""
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = mjcf.replace('<site name="end_effector" pos="0.0 0.0 0.05"', '<site name="end_effector" pos="0.0 0.01 0.05"')
    mjcf = P.sub_once(r'(<body name="link3"[^>]*>)', r'\1<site name="tool_center" pos="0 0 0.2"/>', mjcf)
    urdf = urdf.replace(
        "</robot>",
        '<link name="tcp"/><joint name="tcp_mount" type="fixed"><parent link="link3"/><child link="tcp"/>'
        '<origin xyz="0 0 0.2"/></joint></robot>',
    )
    diag = diagnose_files(*write_pair(tmp_path, urdf, mjcf))
    pair = ("tcp", "tool_center", "same place (no same-named twin)")
    assert diag["matching"].frames[-1] == pair and not diag["internal"]
    assert [(f.urdf, f.mjcf, f.why) for f in diag["alignment"].frames][-1] == pair
    moved = [f for f in diag["findings"] if f.kind in ("frame_offset", "frame_convention")]
    assert [(f.kind, f.severity, f.subject) for f in moved] == [("frame_offset", "error", "end_effector")]
    assert moved[0].magnitude == pytest.approx(0.01, abs=1e-12)
    assert [(f.kind, f.subject) for f in diag["findings"] if f.kind == "frame_twin"] == [("frame_twin", "tcp")]


def test_three_files_read_the_accepted_differences_given(tmp_path, arm3_files):
    """The MJCF's joint2 range ends at 1.4 rad: a failing difference, accepted in a file given
    (not beside the URDF): the two pairs pass."""
    urdf, _, sdf = arm3_files
    mjcf = tmp_path / "narrow.xml"
    mjcf.write_text(
        P.generated_pair("arm3")[1].replace(
            'range="-1.5707963267948966 1.5707963267948966"', 'range="-1.5707963267948966 1.4"', 1
        )
    )
    accepted = tmp_path / "accepted.toml"  # joint2's upper limits 1.4 rad and π/2 apart
    accepted.write_text(
        f'[[accepted]]\nkind = "limit_difference"\nsubject = "joint2"\nmagnitude = {math.pi / 2 - 1.4!r}\nunit = "rad"\n'
        'reason = "the MJCF keeps joint2 off its stop"\n'
    )
    options = dataclasses.replace(LIMITS, backends=None)
    result = verify_three(urdf, str(mjcf), sdf, options, accept=str(accepted))
    assert result.verdict == "pass" and [f.kind for f in result.findings if f.accepted] == ["limit_difference"]


def test_a_usd_side_is_read_by_the_usd_library_from_its_own_text(tmp_path):
    pytest.importorskip("pxr")
    urdf, _ = P.generated_pair("arm3")
    (tmp_path / "arm3.urdf").write_text(urdf)
    (tmp_path / "arm3.usda").write_text(generate_usd(load_spec(MODELS / "arm3.toml")))
    options = dataclasses.replace(FAST, backends=["pinocchio-urdf", "usd"], suites=["kinematics"])
    result = verify_files(str(tmp_path / "arm3.urdf"), str(tmp_path / "arm3.usda"), options, kinds=("urdf", "usd"))
    assert not result.internal_errors and all(c.passed for c in result.checks)
    assert {c.backends for c in result.checks if "finite-difference" not in c.backends} == {("pinocchio-urdf", "usd")}
    # the one thing the pair states apart: the USD's armature, which a URDF cannot state
    assert [(f.kind, f.severity) for f in result.findings if f.severity != "info"] == [("inexpressible", "warning")]


# --- decisions diagnose_files makes, each on the smallest pair that tells it apart ---------------

PINOCCHIO_MUJOCO = VerifyOptions(backends=["pinocchio-urdf", "mujoco"])
MID_TREE_FREE = (  # a free body below link3: Pinocchio reads it (held at neutral), MuJoCo's URDF import refuses it
    '<link name="slider"><inertial><mass value="0.1"/><inertia ixx="1e-5" iyy="1e-5" izz="1e-5" ixy="0" ixz="0" '
    'iyz="0"/></inertial></link><joint name="loose" type="floating"><parent link="link3"/><child link="slider"/></joint>'
)


def test_floating_files_whose_base_carries_everything_elsewhere_keep_their_base_frames(tmp_path):
    """Both bases float; the MJCF's base body carries its centre of mass and joint1 5 cm along −x.
    The base bodies fix the frame: no world shift moves the base along (the base frames would then
    differ), so the difference is joint1's origin, 5 cm, not a base frame offset."""
    urdf, mjcf = floating_arm3()
    mjcf = mjcf.replace('<inertial pos="0.0 0.0 0.0" mass="1.57', '<inertial pos="-0.05 0.0 0.0" mass="1.57', 1)
    mjcf = P.sub_once(r'<body name="link1" pos="0.0 0.0 0.1"', '<body name="link1" pos="-0.05 0.0 0.1"', mjcf)
    diag = diagnose_files(*write_pair(tmp_path, urdf, mjcf), PINOCCHIO_MUJOCO)
    al = diag["alignment"]
    assert al.candidate == "base frames" and np.array_equal(al.T, np.eye(4)) and not diag["internal"]
    assert [(f.kind, f.subject) for f in above_info_of(diag["findings"])] == [("joint_origin_moved", "joint1")]
    moved = only_of(diag["findings"], "joint_origin_moved")
    assert moved.magnitude == pytest.approx(0.05, abs=1e-12) and moved.values["xyz"] == pytest.approx([-0.05, 0, 0], abs=1e-12)


def test_a_zero_offset_the_limits_tolerance_set_by_the_user_tells_from_rounding(tmp_path):
    """joint2's range written ±1.57 in both files (rounded ±π/2: a limits floor of 2 × 7.96e-4 rad)
    and the MJCF's joint2 zero 1 mm rad further (``ref``), its range written alike: the range sits
    1e-3 rad apart physically. Below the floor it is rounding; with the limits tolerance set by the
    user (1e-4 rad), the floor no longer applies and the zero offset says the range too."""
    urdf, mjcf = P.generated_pair("arm3")
    half = "1.5707963267948966"
    urdf = urdf.replace(f'lower="-{half}" upper="{half}"', 'lower="-1.57" upper="1.57"', 1)
    mjcf = P.sub_once(
        r'(<joint name="joint2" )', r'\1ref="0.001" ', mjcf.replace(f'range="-{half} {half}"', 'range="-1.57 1.57"', 1)
    )
    files = write_pair(tmp_path, urdf, mjcf)
    user = dataclasses.replace(PINOCCHIO_MUJOCO, tolerances={"limits.position": 1e-4})
    diag = diagnose_files(*files, user)
    assert diag["info"].floors.limit == pytest.approx(2 * (math.pi / 2 - 1.57), rel=1e-9)
    f = only_of(diag["findings"], "zero_offset")
    assert f.subject == "joint2" and f.magnitude == pytest.approx(1e-3, abs=1e-12)
    assert f.values["range_written_alike"] is True and f.values["checks"] == [["limits.position", "joints"]]
    assert "its range [-1.57, 1.57] is written alike" in f.message
    # the user's tolerance 1e-2 rad: the range 1e-3 rad apart is within it, the offset alone is said
    wide = diagnose_files(*files, dataclasses.replace(PINOCCHIO_MUJOCO, tolerances={"limits.position": 1e-2}))
    f = only_of(wide["findings"], "zero_offset")
    assert (
        f.magnitude == pytest.approx(1e-3, abs=1e-12) and "range_written_alike" not in f.values and "its range" not in f.message
    )


def test_the_alignment_reads_the_urdf_with_the_library_that_read_it(tmp_path):
    """A free body below link3: Pinocchio reads the URDF (the body held at neutral), MuJoCo's URDF
    import refuses it (a warning); the alignment poses come from Pinocchio, and the pair agrees."""
    urdf, mjcf = P.generated_pair("arm3")
    files = write_pair(tmp_path, urdf.replace("</robot>", MID_TREE_FREE + "</robot>"), mjcf)
    diag = diagnose_files(*files, dataclasses.replace(PINOCCHIO_MUJOCO, backends=["pinocchio-urdf", "mujoco-urdf", "mujoco"]))
    assert diag["reference"] == "pinocchio-urdf" and sorted(diag["backends"]) == ["mujoco", "pinocchio-urdf"]
    refused = only_of(diag["findings"], "parser_refused")
    assert refused.values == {"file": "URDF", "backend": "mujoco-urdf"} and "free joint" in refused.message
    assert np.array_equal(diag["alignment"].T, np.eye(4)) and diag["alignment"].unexplained == 0 and not diag["internal"]
    assert "URDF: loose: JointModelFreeFlyer has 7 coordinates; only 1-DOF joints are compared (held at neutral)" in diag["notes"]


def test_no_library_asked_for_reading_the_urdf_is_a_one_line_input_error_saying_why(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    files = write_pair(tmp_path, urdf.replace("</robot>", MID_TREE_FREE + "</robot>"), mjcf)
    with pytest.raises(InputError) as err:
        diagnose_files(*files, dataclasses.replace(PINOCCHIO_MUJOCO, backends=["mujoco-urdf", "mujoco"]))
    message = str(err.value)
    assert message.startswith("no library could read the URDF: mujoco-urdf refuses the URDF: ")
    assert "free joint can only be used on top level" in message and "\n" not in message


def test_a_joint_origin_moved_along_its_axis_is_said_once_not_again_as_frame_conventions(tmp_path):
    """The MJCF's link3 body 1 cm along joint3's axis (y): link3 and the end effector sit at a
    constant offset, which is joint3's origin moved (an error), not a frame convention of each."""
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = P.sub_once(r'<body name="link3" pos="0.0 0.0 0.25">', '<body name="link3" pos="0.0 0.01 0.25">', mjcf)
    diag = diagnose_files(*write_pair(tmp_path, urdf, mjcf), PINOCCHIO_MUJOCO)
    assert [(f.kind, f.subject) for f in diag["findings"]] == [("joint_origin_moved", "joint3")]
    f = diag["findings"][0]
    assert f.severity == "error" and f.magnitude == pytest.approx(0.01, abs=1e-12)
    assert f.values["frames"] == ["link3", "end_effector"] and f.values["xyz"] == pytest.approx([0, 0.01, 0], abs=1e-12)


def test_lengths_in_millimetres_are_one_finding_that_explains_the_inertials_and_nothing_else_is_said(tmp_path):
    """Every position the MJCF writes 1000 times the URDF's: one length-units finding (ratio 1000),
    no frame or joint blamed for it, and the inertial comparison marked as explained by it."""
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = re.sub(r'( pos=")([^"]*)"', lambda g: g[1] + " ".join(repr(float(x) * 1000) for x in g[2].split()) + '"', mjcf)
    diag = diagnose_files(*write_pair(tmp_path, urdf, mjcf), PINOCCHIO_MUJOCO)
    (f,) = diag["findings"]
    assert (f.kind, f.severity) == ("length_units", "error") and f.magnitude == pytest.approx(1000, rel=1e-12)
    assert f.values["frames"] == ["base", "link1", "link2", "link3", "end_effector"]
    assert diag["info"].inertials_explained_by == "length_units" and not diag["internal"]


GUARDED = {  # each step diagnose_files guards, in the order it runs them: what its internal error names
    "unmoved_world": "attribution",
    "frame_twins": "frames with no same-named twin",
    "attribute": "attribution",
    "length_units": "length units",
    "alignment_findings": "alignment findings",
    "convention_findings": "frame conventions",
    "validate_inertials": "inertial validation",
    "cross_check": "parser cross-check",
    "coupling_findings": "couplings",
}


def test_each_guarded_step_that_fails_is_kinverifys_own_error_and_the_rest_still_runs(tmp_path, monkeypatch, arm3_files):
    """Every guarded step planted to fail (kinverify's own bug): each is one internal error naming
    the step, in order, and the files are still read, aligned and built by every library asked."""

    def broken(*args, **kwargs):
        raise ZeroDivisionError("planted")

    for name in GUARDED:
        monkeypatch.setattr(f"kinverify.filemode.pipeline.{name}", broken)
    diag = diagnose_files(*arm3_files[:2], PINOCCHIO_MUJOCO)
    assert diag["internal"] == [f"file mode, {what}: ZeroDivisionError: planted" for what in GUARDED.values()]
    assert sorted(diag["backends"]) == ["mujoco", "pinocchio-urdf"] and diag["reference"] == "pinocchio-urdf"
    assert diag["findings"] == [] and diag["parser_rows"] == [] and diag["alignment"].attribution == {}
    assert [a for a, _, _ in diag["matching"].frames] == ["base", "link1", "link2", "link3", "end_effector"]


def test_the_accepted_differences_written_name_both_files_and_a_failing_findings_step_is_named(tmp_path, monkeypatch, arm3_files):
    urdf, mjcf, _ = arm3_files
    accepted = tmp_path / "accepted.toml"
    result = verify_files(urdf, mjcf, LIMITS, write_accepted=str(accepted))
    assert accepted.read_text().splitlines()[0] == f"# kinverify accepted differences for {urdf} + {mjcf}"
    assert f"accepted differences written to {accepted}: review each entry and give its reason" in result.notes

    def broken(*args, **kwargs):
        raise ZeroDivisionError("planted")

    monkeypatch.setattr("kinverify.filemode.pipeline.finish", broken)
    result = verify_files(urdf, mjcf, LIMITS)
    assert result.internal_errors == ["file mode, findings: ZeroDivisionError: planted"]
    assert result.verdict == "error" and result.exit_code == 3 and "filemode" not in result.sections


def test_three_files_with_a_usd_take_it_as_a_usd_side(tmp_path, arm3_files):
    pytest.importorskip("pxr")
    urdf = arm3_files[0]
    (tmp_path / "arm3.usda").write_text(generate_usd(load_spec(MODELS / "arm3.toml")))
    options = dataclasses.replace(LIMITS, backends=["pinocchio-urdf", "usd"])
    result = verify_three(urdf, None, None, options, usd=str(tmp_path / "arm3.usda"))
    assert result.model_info["files"] == {"urdf": urdf, "usd": str(tmp_path / "arm3.usda")}
    assert {c.backends for c in result.checks} == {("urdf", "usd")} and not result.internal_errors
    assert any(n.startswith("USD: read by usd-core (pxr), its only reader here") for n in result.notes)


def above_info_of(findings: list) -> list:
    return [f for f in findings if f.severity != "info"]


def only_of(findings: list, kind: str):
    hits = [f for f in findings if f.kind == kind]
    assert len(hits) == 1, [(f.kind, f.subject) for f in findings]
    return hits[0]
