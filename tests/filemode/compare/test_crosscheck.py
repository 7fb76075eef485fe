"""Each file read by several libraries: the poses compared frame by frame (the worst sample),
the top-level pose Pinocchio's MJCF parser drops found, measured and put back, what a parser says
it ignores split by whether the comparison reads it, and the majority of readings decided with
each float32 reader's floor; a reading standing apart is one finding and is left out."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.backends.drake_ import DrakeBackend
from kinverify.backends.usd_ import UsdBackend
from kinverify.filemode.compare.context import FileModeInfo
from kinverify.filemode.compare.crosscheck import (
    QUIRK_ISSUE,
    cross_check,
    floored_tol,
    majority,
    pose_errors,
    refusal_findings,
    top_level_pose,
)
from kinverify.filemode.compare.libraries import build_backends, rebuild_mjcf

JOINTS = ["joint1", "joint2", "joint3"]
TIGHT = (1e-9, 1e-9)
FLOOR = UsdBackend.agreement_floor["fk.position"]  # a float32 reader's floor (2e-6)


def rz(angle: float, xyz=(0.0, 0.0, 0.0)) -> np.ndarray:
    t = np.eye(4)
    t[:2, :2] = [[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]]
    t[:3, 3] = xyz
    return t


def batch(*poses_per_sample) -> np.ndarray:
    """(N, F, 4, 4) from N lists of F poses."""
    return np.array([list(s) for s in poses_per_sample], dtype=float)


# --- pose differences -----------------------------------------------------------------------


def test_pose_errors_are_the_worst_sample_per_frame():
    a = batch([np.eye(4), np.eye(4)], [np.eye(4), np.eye(4)])
    b = batch([rz(0.0, (0.03, 0.04, 0.0)), rz(0.2)], [rz(0.0, (0.3, 0.4, 0.0)), rz(-0.1)])
    pos, rot = pose_errors(a, b)
    assert pos == pytest.approx([0.5, 0.0], abs=1e-15)
    assert rot == pytest.approx([0.0, 0.2], abs=1e-12)


# --- the top-level pose Pinocchio's MJCF parser drops ---------------------------------------


def test_the_top_level_pose_is_that_of_the_first_top_level_body_holding_others():
    mjcf = f"""<mujoco><worldbody>
      <body name="prop" pos="1 0 0"><geom size="0.1" mass="1"/></body>
      <body name="mount" pos="0 0 0.5" quat="{math.cos(0.25)!r} 0 0 {math.sin(0.25)!r}"><geom size="0.1" mass="1"/>
        <body name="arm"><joint name="j"/><geom size="0.1" mass="1"/></body></body>
      <body name="later" pos="0 2 0"><geom size="0.1" mass="1"/><body name="x"><geom size="0.1" mass="1"/></body></body>
    </worldbody></mujoco>"""
    assert top_level_pose(mjcf) == pytest.approx(rz(0.5, (0.0, 0.0, 0.5)), abs=1e-12)


@pytest.mark.parametrize("pos, moved", [("0 0 0", False), ("1e-16 0 0", False), ("1e-12 0 0", True)])
def test_a_top_level_pose_at_the_identity_is_none(pos, moved):
    mjcf = f"""<mujoco><worldbody><body name="mount" pos="{pos}"><geom size="0.1" mass="1"/>
      <body name="arm"><joint name="j"/><geom size="0.1" mass="1"/></body></body></worldbody></mujoco>"""
    found = top_level_pose(mjcf)
    assert (found is not None) == moved
    if moved:
        assert found[0, 3] == 1e-12


def test_a_model_without_a_body_holding_another_has_no_top_level_pose():
    mjcf = '<mujoco><worldbody><body name="alone" pos="1 0 0"><geom size="0.1" mass="1"/></body></worldbody></mujoco>'
    assert top_level_pose(mjcf) is None


# --- what a parser says it ignores ----------------------------------------------------------


@pytest.fixture(scope="module")
def drake_mjcf():
    urdf, mjcf = P.generated_pair("arm3")
    return DrakeBackend.from_mjcf(mjcf, JOINTS, ["link1"], name="drake-mjcf")


def test_what_drake_ignores_in_an_mjcf_is_a_warning_where_compared_and_an_info_elsewhere(drake_mjcf):
    refused, ignores = refusal_findings({"drake-mjcf": drake_mjcf}, ("urdf", "mjcf"))
    assert (refused.kind, refused.severity, refused.subject) == ("parser_refused", "warning", "MJCF")
    assert refused.values == {"file": "MJCF", "backend": "drake-mjcf", "elements": ["<site> in <worldbody>", "<site> in <body>"]}
    assert refused.message == (
        "drake-mjcf ignores part of the MJCF that is compared: <site> in <worldbody>, <site> in <body> "
        "(unsupported by its parser; the rest is read and compared)"
    )
    assert (ignores.kind, ignores.severity) == ("parser_ignores", "info")
    assert ignores.values["elements"] == [
        "option@timestep",
        "option@integrator",
        "<light> in <worldbody>",
        "joint@frictionloss",
        "<sensor> in <mujoco>",
        "<visual> in <mujoco>",
    ]
    assert ignores.message.startswith("drake-mjcf ignores option@timestep, option@integrator, <light> in <worldbody>")
    assert ignores.message.endswith(" in the MJCF (unsupported by its parser; nothing compared through it depends on them)")


def test_a_backend_seen_through_the_alignment_is_asked_through_its_inner_library(drake_mjcf):
    wrapped = SimpleNamespace(inner=drake_mjcf)  # an aligned backend keeps the library as ``inner``
    assert [f.kind for f in refusal_findings({"drake-mjcf": wrapped}, ("urdf", "mjcf"))] == ["parser_refused", "parser_ignores"]


def test_a_reader_of_a_format_not_compared_names_the_file(drake_mjcf):
    assert [f.values["file"] for f in refusal_findings({"drake-mjcf": drake_mjcf}, ("urdf", "sdf"))] == ["file", "file"]
    assert [f.values["file"] for f in refusal_findings({"drake-sdf": drake_mjcf}, ("urdf", "sdf"))] == ["SDF", "SDF"]
    assert "ignores part of the SDF that is compared" in refusal_findings({"drake-sdf": drake_mjcf}, ("sdf", "mjcf"))[0].message


TAG = "<literal-string>.xml:1: warning: The tag '{}' found as a child of '{}' is currently unsupported and will be ignored."
ATTR = "<literal-string>.xml:1: warning: The attribute '{}' found in a '{}' tag is currently unsupported and will be ignored."


@pytest.mark.parametrize(
    "warning",
    [
        TAG.format("site", "body"),
        TAG.format("frame", "body"),
        TAG.format("inertial", "body"),
        TAG.format("equality", "mujoco"),
        TAG.format("tendon", "mujoco"),
        TAG.format("weld", "equality"),
        ATTR.format("gravcomp", "body"),
        ATTR.format("fullinertia", "inertial"),
        ATTR.format("range", "joint"),
        ATTR.format("ref", "joint"),
        ATTR.format("axis", "joint"),
        ATTR.format("pos", "joint"),
        ATTR.format("limited", "joint"),
        ATTR.format("mass", "geom"),
        ATTR.format("density", "geom"),
    ],
)
def test_each_element_the_comparison_reads_is_refused_not_ignored(drake_mjcf, warning):
    drake = DrakeBackend(drake_mjcf.plant, "drake-mjcf", JOINTS, ["link1"], [warning, ATTR.format("damping", "joint")])
    refused, ignores = refusal_findings({"drake-mjcf": drake}, ("urdf", "mjcf"))
    assert (refused.kind, ignores.kind, ignores.values["elements"]) == ("parser_refused", "parser_ignores", ["joint@damping"])
    assert len(refused.values["elements"]) == 1


def test_a_library_that_ignores_nothing_or_has_no_parser_warnings_gives_no_finding(drake_mjcf):
    quiet = DrakeBackend(drake_mjcf.plant, "drake-mjcf", JOINTS, ["link1"], [])
    assert refusal_findings({"drake-mjcf": quiet, "mujoco": SimpleNamespace()}, ("urdf", "mjcf")) == []


# --- the majority of readings ---------------------------------------------------------------


def readings(**shifts) -> dict:
    """Name -> (2, 1, 4, 4) poses of one frame moved ``shift`` metres along x (in reading order)."""
    return {n: batch([rz(0.0, (s, 0.0, 0.0))], [rz(0.0, (s, 0.0, 0.0))]) for n, s in shifts.items()}


def test_two_readings_that_agree_outvote_the_reference():
    agree, apart = majority(readings(ref=0.01, b=0.0, c=0.0), TIGHT)
    assert (agree, apart) == (["b", "c"], {"ref": (pytest.approx(0.01), 0.0)})


def test_on_a_tie_the_references_group_is_the_majority():
    agree, apart = majority(readings(ref=0.0, b=0.25), TIGHT)
    assert (agree, apart) == (["ref"], {"b": (0.25, 0.0)})


def test_a_difference_at_the_tolerance_agrees():
    assert majority(readings(ref=0.0, b=0.5), (0.5, 0.0)) == (["ref", "b"], {})
    assert majority(readings(ref=0.0, b=0.5), (0.25, 0.0))[1] == {"b": (0.5, 0.0)}


def test_a_rotation_beyond_its_tolerance_stands_apart_even_when_positions_agree():
    turned = {"ref": batch([np.eye(4)]), "b": batch([np.eye(4)]), "c": batch([rz(0.125)])}
    assert majority(turned, (1.0, 0.1)) == (["ref", "b"], {"c": (0.0, pytest.approx(0.125))})
    assert majority(turned, (1.0, 0.125 + 1e-12)) == (["ref", "b", "c"], {})


def test_a_float32_reading_within_its_floor_does_not_vote_and_is_named_with_the_majority():
    found = readings(ref=0.0, b=0.01, usd=FLOOR / 2)
    agree, apart = majority(found, TIGHT, {"usd": UsdBackend})
    assert (agree, apart) == (["ref", "usd"], {"b": (0.01, 0.0)})
    # without its floor, it votes: three readings, each its own group: the reference's first
    assert majority(found, TIGHT)[1] == {"b": (0.01, 0.0), "usd": (FLOOR / 2, 0.0)}


def test_a_float32_reading_beyond_its_floor_stands_apart():
    agree, apart = majority(readings(ref=0.0, b=0.0, usd=3 * FLOOR), TIGHT, {"usd": UsdBackend})
    assert (agree, apart) == (["ref", "b"], {"usd": (pytest.approx(3 * FLOOR), 0.0)})


def test_a_float32_reading_that_cannot_tell_the_apart_reading_from_the_majority_is_named_with_neither():
    agree, apart = majority(readings(ref=0.0, b=1.5 * FLOOR, usd=FLOOR), TIGHT, {"usd": UsdBackend})
    assert (agree, apart) == (["ref"], {"b": (pytest.approx(1.5 * FLOOR), 0.0)})


def test_float32_readings_alone_all_vote():
    agree, apart = majority(readings(usd=0.0, newton=0.01), TIGHT, {"usd": UsdBackend, "newton": UsdBackend})
    assert (agree, apart) == (["usd"], {"newton": (0.01, 0.0)})


def test_a_float32_floor_raises_the_tolerance_of_the_pairs_it_is_in():
    assert floored_tol(TIGHT, UsdBackend, None) == (FLOOR, FLOOR)
    assert floored_tol((1e-3, 1e-9), None, UsdBackend) == (1e-3, FLOOR)
    assert floored_tol((1e-3, 1e-2)) == (1e-3, 1e-2)


# --- the readings of each file compared -----------------------------------------------------


def backends_of(urdf: str, mjcf: str, names) -> dict:
    info = FileModeInfo.from_sources(SimpleNamespace(urdf=urdf, mjcf=mjcf, joint_names=JOINTS))
    return build_backends(info, urdf, mjcf, names, lambda frame: TIGHT, [])


Q = np.random.default_rng(3).uniform(-1, 1, (3, 3))


@pytest.fixture(scope="module")
def arm3():
    return P.generated_pair("arm3")


def moved_joint3(urdf: str) -> str:
    return P.sub_once(r'(<joint name="joint3".*?<origin xyz=")0.0 0.0 0.25(")', r"\g<1>0.01 0.0 0.25\2", urdf)


def test_libraries_that_read_a_file_alike_give_rows_and_no_finding(arm3):
    backends = backends_of(*arm3, ["pinocchio-urdf", "yourdfpy", "mujoco", "pinocchio-mjcf"])
    keep, findings, rows = cross_check(backends, Q, TIGHT, np.eye(4), None, rebuild_mjcf)
    assert (list(keep), findings) == (["pinocchio-urdf", "yourdfpy", "mujoco", "pinocchio-mjcf"], [])
    assert [r[:2] for r in rows] == [["URDF", "pinocchio-urdf vs yourdfpy"], ["MJCF", "mujoco vs pinocchio-mjcf"]]
    assert max(max(r[2], r[3]) for r in rows) < 1e-12


def test_a_reading_apart_from_two_that_agree_is_one_finding_and_left_out(arm3):
    urdf, mjcf = arm3
    backends = backends_of(urdf, mjcf, ["pinocchio-urdf", "yourdfpy", "mujoco"])
    backends["mujoco-urdf"] = backends_of(moved_joint3(urdf), mjcf, ["mujoco-urdf"])["mujoco-urdf"]
    keep, findings, rows = cross_check(backends, Q, TIGHT, np.eye(4), None, rebuild_mjcf)
    assert list(keep) == ["pinocchio-urdf", "yourdfpy", "mujoco"]
    assert rows[1][:3] == ["URDF", "pinocchio-urdf vs mujoco-urdf", pytest.approx(0.01, rel=1e-9)]
    (f,) = findings
    assert (f.kind, f.severity, f.magnitude, f.unit) == ("parser_disagreement", "warning", pytest.approx(0.01), "m|rad")
    assert f.values["agree"] == ["pinocchio-urdf", "yourdfpy"] and f.values["apart"] == "mujoco-urdf"
    assert f.values["backends"] == ["pinocchio-urdf", "mujoco-urdf"] and f.values["file"] == "URDF"
    assert f.values["position_m"] == pytest.approx(0.01) and f.values["rotation_rad"] < 1e-12
    assert f.message.startswith(
        "the URDF is read alike by pinocchio-urdf and yourdfpy, and differently by mujoco-urdf: up to 0.01 m"
    )
    assert f.message.endswith("mujoco-urdf stands apart and is left out of the comparison between the files")


def test_two_readings_that_differ_are_one_finding_with_no_majority(arm3):
    urdf, mjcf = arm3
    backends = backends_of(urdf, mjcf, ["pinocchio-urdf"])
    backends["yourdfpy"] = backends_of(moved_joint3(urdf), mjcf, ["yourdfpy"])["yourdfpy"]
    keep, (f,), _ = cross_check(backends, Q, TIGHT, np.eye(4), None, rebuild_mjcf)
    assert list(keep) == ["pinocchio-urdf"]
    assert f.values["agree"] == ["pinocchio-urdf"] and f.magnitude == pytest.approx(0.01)
    assert f.message.startswith("the URDF is read differently by pinocchio-urdf and yourdfpy: up to 0.01 m")
    assert "(no third reading agrees with either); yourdfpy is left out" in f.message


def test_readings_are_compared_on_the_frames_every_one_has_in_the_references_order(arm3):
    urdf, mjcf = arm3
    backends = backends_of(urdf, mjcf, ["pinocchio-urdf", "yourdfpy"])
    info = FileModeInfo.from_sources(SimpleNamespace(urdf=urdf, mjcf=mjcf, joint_names=JOINTS))
    few = ["link3", "link1"]
    info.matching.frames[:] = [(f, f, "name") for f in few]
    backends["yourdfpy"] = build_backends(info, moved_joint3(urdf), mjcf, ["yourdfpy"], lambda frame: TIGHT, [])["yourdfpy"]
    _, (f,), rows = cross_check(backends, Q, TIGHT, np.eye(4), None, rebuild_mjcf)
    assert rows[0][2] == pytest.approx(0.01, rel=1e-9)  # link3 compared with link3, link1 with link1


def test_a_library_failing_on_a_file_is_a_finding_and_left_out(arm3):
    urdf, mjcf = arm3
    backends = backends_of(urdf, mjcf, ["pinocchio-urdf", "yourdfpy", "mujoco-urdf"])
    backends["yourdfpy"].alignment = SimpleNamespace()  # a fault planted in the input: no joint map to evaluate with
    with pytest.raises(AttributeError):
        backends["yourdfpy"].poses(Q)
    keep, findings, rows = cross_check(backends, Q, TIGHT, np.eye(4), None, rebuild_mjcf)
    assert list(keep) == ["pinocchio-urdf", "mujoco-urdf"] and [r[1] for r in rows] == ["pinocchio-urdf vs mujoco-urdf"]
    (f,) = findings
    assert (f.kind, f.values) == ("parser_refused", {"file": "URDF", "backend": "yourdfpy"})
    assert f.message.startswith("yourdfpy cannot evaluate the URDF: 'types.SimpleNamespace' object has no attribute")


def test_a_side_read_by_one_library_is_not_cross_checked(arm3):
    assert cross_check(backends_of(*arm3, ["pinocchio-urdf", "mujoco"]), Q, TIGHT, np.eye(4), None, rebuild_mjcf)[1:] == ([], [])


@pytest.fixture(scope="module")
def mounted(arm3):
    """arm3's MJCF with its mount 0.3 rad about z and (0.1, 0.2, 0) m from the world."""
    return P.turned_world(*arm3, 0.3, [0.1, 0.2, 0.0])


def test_the_top_level_pose_pinocchio_drops_is_put_back_and_said_once(mounted):
    urdf, mjcf = mounted
    backends = backends_of(urdf, mjcf, ["mujoco", "pinocchio-mjcf", "drake-mjcf"])
    keep, findings, rows = cross_check(backends, Q, TIGHT, np.eye(4), top_level_pose(mjcf), rebuild_mjcf)
    assert list(keep) == ["mujoco", "pinocchio-mjcf", "drake-mjcf"] and keep["pinocchio-mjcf"] is not backends["pinocchio-mjcf"]
    assert rows[0][:2] == ["MJCF", "mujoco vs pinocchio-mjcf"] and rows[0][3] == pytest.approx(0.3)
    assert rows[0][4].startswith("corrected: ") and len(rows[1]) == 4
    (f,) = findings
    shift = math.hypot(0.1, 0.2)
    assert (f.kind, f.severity, f.magnitude, f.unit) == ("parser_quirk", "info", pytest.approx(0.3), "m|rad")
    assert f.values["top_level_xyz"] == pytest.approx([0.1, 0.2, 0.0]) and f.values["issue"] == QUIRK_ISSUE
    assert f.values["backends"] == ["mujoco", "pinocchio-mjcf"] and f.values["rotation_rad"] == pytest.approx(0.3)
    assert f.values["position_m"] == rows[0][2] > 0.2 and f.values["file"] == "MJCF"
    assert f"({shift:.4g} m, 0.3 rad = {math.degrees(0.3):.4g}°)" in f.message and "pinocchio#2782" in f.message
    # corrected: the same poses as MuJoCo's
    cols = [backends["mujoco"].frames.index(x) for x in keep["pinocchio-mjcf"].frames]
    assert keep["pinocchio-mjcf"].poses(Q) == pytest.approx(backends["mujoco"].poses(Q)[:, cols], abs=1e-12)


def test_a_dropped_turn_alone_is_the_quirk_too(arm3):
    """A mount turned about z alone: at q = 0 every frame is on the z axis, and only the rotations differ."""
    urdf, mjcf = P.turned_world(*arm3, 0.3)
    backends = backends_of(urdf, mjcf, ["mujoco", "pinocchio-mjcf"])
    keep, (f,), _ = cross_check(backends, np.zeros((2, 3)), TIGHT, np.eye(4), top_level_pose(mjcf), rebuild_mjcf)
    assert f.kind == "parser_quirk" and f.magnitude == pytest.approx(0.3)


def test_a_top_level_pose_that_does_not_explain_the_difference_is_no_quirk(mounted):
    urdf, mjcf = mounted
    backends = backends_of(urdf, mjcf, ["mujoco", "pinocchio-mjcf", "drake-mjcf"])
    keep, (f,), rows = cross_check(backends, Q, TIGHT, np.eye(4), rz(0.3), rebuild_mjcf)
    assert f.kind == "parser_disagreement" and f.values["apart"] == "pinocchio-mjcf" and len(rows[0]) == 4
    assert list(keep) == ["mujoco", "drake-mjcf"]
    # the base transform is taken out of the pose put back
    keep, findings, _ = cross_check(backends, Q, TIGHT, rz(0.3), top_level_pose(mjcf), rebuild_mjcf)
    assert [f.kind for f in findings] == ["parser_disagreement"]


def test_readings_that_agree_are_not_corrected(arm3):
    backends = backends_of(*arm3, ["mujoco", "pinocchio-mjcf"])
    keep, findings, rows = cross_check(backends, Q, TIGHT, np.eye(4), np.eye(4), rebuild_mjcf)
    assert findings == [] and len(rows[0]) == 4 and keep["pinocchio-mjcf"] is backends["pinocchio-mjcf"]


def test_three_readings_that_agree_are_listed_with_the_one_apart(arm3):
    urdf, mjcf = arm3
    backends = backends_of(urdf, mjcf, ["pinocchio-urdf", "yourdfpy", "mujoco-urdf"])
    backends["drake-urdf"] = backends_of(moved_joint3(urdf), mjcf, ["drake-urdf"])["drake-urdf"]
    keep, (f,), rows = cross_check(backends, Q, TIGHT, np.eye(4), None, rebuild_mjcf)
    assert list(keep) == ["pinocchio-urdf", "yourdfpy", "mujoco-urdf"] and len(rows) == 3
    assert f.message.startswith(
        "the URDF is read alike by pinocchio-urdf, yourdfpy and mujoco-urdf, and differently by drake-urdf: up to 0.01 m"
    )
