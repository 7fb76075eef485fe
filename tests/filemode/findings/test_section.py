"""The file-mode report section: its summary, tables and the data the report draws from, built
from a hand-made comparison (two joints, one in one file only, a frame, a coupling, findings)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import tests.filemode.findings.descs as D
from kinverify.filemode.align.match import Matching
from kinverify.filemode.align.result import FrameFit, JointMap
from kinverify.filemode.compare.context import FileModeInfo
from kinverify.filemode.findings.section import build_section
from kinverify.filemode.read.model import BodyInertial
from kinverify.filemode.read.precision import Precision
from kinverify.suites.base import Finding

FILES = SimpleNamespace(path="arm.urdf"), SimpleNamespace(path="arm.xml")  # what the section reads of a loaded file


def body(mass: float) -> BodyInertial:
    return BodyInertial(None, mass, np.zeros(3), np.eye(3))


def comparison() -> FileModeInfo:
    """URDF joints a, b (b coupled to a), c in the URDF only; MJCF A, B, and X in it only; the world
    moved 0.5 m along x; b reversed with a zero offset of 0.25."""
    u = D.desc("urdf", [D.joint("a"), D.joint("b", "a"), D.joint("c", "b")])
    m = D.desc("mjcf", [D.joint("A"), D.joint("B", "A"), D.joint("X", "B")])
    u.bodies, m.bodies = [body(1.0), body(2.0)], [body(3.5)]
    matching = Matching([("a", "A", "name"), ("b", "B", "position")], ["c"], ["X"], [("a_link", "A_link", "moves with a")])
    t = np.eye(4)
    t[0, 3] = 0.5
    frame = FrameFit("a_link", "A_link", "moves with a", 1e-3, 2e-3, np.eye(4), 3e-4, 4e-4, True)
    al = D.alignment(
        [JointMap("a", "A", "revolute"), JointMap("b", "B", "prismatic", -1, 0.25)],
        T=t,
        frames=[frame],
        residual=(1e-7, 2e-7),
        candidate="as fitted",
        unexplained=2,
    )
    al.couplings = {"b": D.couple("b", "a", 2.0, 0.125)}
    precision = Precision("URDF"), Precision("MJCF", length=1e-4, examples={"length": "0.1234"})
    return FileModeInfo(u, m, matching, al, precision=precision, floating=True)


FINDINGS = [
    Finding("zero_offset", "error", "b zero", "b", "joint", "B", magnitude=0.25, unit="m", values={"urdf": 0.0, "mjcf": 0.25}),
    Finding("mass_difference", "error", "heavier", "link1", "link", accepted=True, magnitude=1.5, unit="kg"),
    Finding("joint_names", "info", "renamed", "b", "joint", "B"),
    Finding("coupling_difference", "error", "apart", "c", "joint", magnitude=math.inf, unit="rad"),
]


@pytest.fixture
def section():  # built in each test (a few ms): mutation testing credits a function to the tests that call it
    return build_section(*FILES, comparison(), FINDINGS, ["a note"], [["arm.urdf", "pinocchio, mujoco", 1e-12]])


def table(section, title: str):
    return next(t for t in section.tables if t.title.startswith(title))


def test_the_summary_counts_matched_joints_those_in_one_file_and_failing_findings(section):
    assert section.title == "File mode: URDF vs MJCF" and section.notes == ["a note"]
    assert section.summary == "arm.urdf vs arm.xml: 2 joints matched, 2 in one file only; 4 findings, 2 failing"
    empty = build_section(*FILES, comparison(), [], [], [])
    assert empty.summary == "arm.urdf vs arm.xml: 2 joints matched, 2 in one file only; no differences found"


def test_the_findings_table_shows_acceptance_magnitudes_with_units_and_labels(section):
    findings = table(section, "Findings")
    assert findings.columns == ["severity", "kind", "subject", "magnitude", "finding"]
    assert findings.rows == [
        ["error", "zero_offset", "joint b / B", "0.25 m", "b zero"],
        ["accepted error", "mass_difference", "link link1", "1.5 kg", "heavier"],
        ["info", "joint_names", "joint b / B", "", "renamed"],
        ["error", "coupling_difference", "joint c", "inf rad", "apart"],
    ]


def test_the_joint_map_frames_and_parser_tables(section):
    joints = table(section, "Joint map")
    assert joints.title == "Joint map (q_mjcf = sign · q_urdf + offset)"
    assert joints.columns == ["URDF joint", "MJCF joint", "matched by", "sign", "offset"]
    assert joints.rows == [["a", "A", "name", 1, 0.0], ["b", "B", "position", -1, 0.25]]
    frames = table(section, "Frames after alignment")
    assert frames.title == "Frames after alignment (max over the fit's configurations)"
    assert frames.rows == [["a_link / A_link", "moves with a", 1e-3, 2e-3, [3e-4, 4e-4], True]]
    assert frames.columns == [
        "frame (URDF / MJCF)",
        "why compared",
        "position [m]",
        "rotation [rad]",
        "after removing a constant [m, rad]",
        "in the fit",
    ]
    parsers = table(section, "Each file read by two libraries")
    assert parsers.columns == ["file", "backends", "max position [m]", "max rotation [rad]", "note"]
    assert parsers.rows == [["arm.urdf", "pinocchio, mujoco", 1e-12, "", ""]]  # padded to the five columns


def test_the_data_keeps_the_alignment_for_the_report_to_redraw(section):
    al = section.data["alignment"]
    assert al["T_mjcf_from_urdf"][0] == [1.0, 0.0, 0.0, 0.5] and len(al["T_mjcf_from_urdf"]) == 4
    assert (al["residual_m"], al["residual_rad"], al["candidate"], al["unexplained_features"]) == (1e-7, 2e-7, "as fitted", 2)
    assert al["joints"] == [
        {"urdf": "a", "mjcf": "A", "type": "revolute", "sign": 1, "offset": 0.0},
        {"urdf": "b", "mjcf": "B", "type": "prismatic", "sign": -1, "offset": 0.25},
    ]
    assert al["couplings"] == [{"follower": "b", "leader": "a", "multiplier": 2.0, "offset": 0.125, "source": "<mimic>"}]
    assert al["frames"] == [
        {
            "urdf": "a_link",
            "mjcf": "A_link",
            "why": "moves with a",
            "position_m": 1e-3,
            "rotation_rad": 2e-3,
            "residual_m": 3e-4,
            "residual_rad": 4e-4,
            "in_fit": True,
        }
    ]


def test_the_data_keeps_each_finding_grouped_by_subject_with_an_infinite_size_as_text(section):
    data = section.data
    assert data["findings"][0] == {
        "kind": "zero_offset",
        "severity": "error",
        "subject": "joint b / B",
        "accepted": False,
        "magnitude": 0.25,
        "unit": "m",
        "urdf": 0.0,
        "mjcf": 0.25,
    }
    assert data["findings"][1]["accepted"] is True and data["findings"][1]["urdf"] is None
    assert data["findings"][2]["magnitude"] is None and data["findings"][3]["magnitude"] == "inf"
    assert data["findings_by_subject"] == {"joint b / B": [0, 2], "link link1": [1], "joint c": [3]}


def test_the_data_keeps_precision_masses_base_and_what_one_file_has_alone(section):
    data = section.data
    assert data["precision"] == {
        "urdf": "the URDF writes exact values",
        "mjcf": Precision("MJCF", length=1e-4, examples={"length": "0.1234"}).describe(),
    }
    assert data["precision"]["mjcf"] != data["precision"]["urdf"]
    assert data["total_mass"] == {"urdf": 3.0, "mjcf": 3.5} and data["floating_base"] is True
    assert data["unmatched"] == {"urdf": ["c"], "mjcf": ["X"]}
