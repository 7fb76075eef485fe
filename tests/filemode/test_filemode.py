"""File mode: a URDF against an MJCF. Generated pairs must agree with no findings; each deliberate
mutation must be detected and named; bad input is a one-line error; the real pairs in
../shared/real-robots (when present) run to a verdict."""

from __future__ import annotations

import math
import re
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from tests.filemode.pairs import MUTATIONS, generated_pair
from kinverify.cli import main
from kinverify.errors import InputError
from kinverify.filemode import diagnose_files, verify_files
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.results import VerifyResult
from kinverify.testing.strategies import arm_specs
from kinverify.model.transforms import matrix_to_quat, rpy_to_matrix
from kinverify.run import VerifyOptions
from tests.paths import REAL_ROBOTS

REAL = REAL_ROBOTS
FAST = VerifyOptions(samples=10, fd_samples=5)


def write_pair(folder: Path, urdf: str, mjcf: str) -> tuple[str, str]:
    (folder / "robot.urdf").write_text(urdf)
    (folder / "robot.xml").write_text(mjcf)
    return str(folder / "robot.urdf"), str(folder / "robot.xml")


def kinds(findings) -> list[str]:
    return [f.kind for f in findings]


@pytest.mark.parametrize("model", ["panda", "scara"])
def test_identical_generated_pair_has_no_findings_and_passes(tmp_path, model):
    result = verify_files(*write_pair(tmp_path, *generated_pair(model)), FAST)
    assert result.findings == []
    assert result.passed, [c for c in result.failed]
    assert {"pinocchio-urdf", "yourdfpy", "mujoco-urdf", "mujoco", "pinocchio-mjcf"} <= set(result.backends)
    data = result.to_dict()
    assert data["findings"] == [] and VerifyResult.from_dict(data).findings == []


@pytest.mark.parametrize("mutate,kind,name", MUTATIONS, ids=[m[0].__name__ for m in MUTATIONS])
def test_each_mutation_is_detected_and_named(tmp_path, mutate, kind, name):
    diag = diagnose_files(*write_pair(tmp_path, *mutate(*generated_pair("panda"))))
    hits = [f for f in diag["findings"] if f.kind == kind]
    assert hits, kinds(diag["findings"])
    if name is not None:
        assert any(name == f.subject for f in hits), hits
    values = hits[0].values
    if kind == "base_transform":
        assert np.allclose(values["rpy"], [0, 0, math.pi / 4], atol=1e-12)
        assert values["residual_position_m"] < 1e-9 and values["residual_rotation_rad"] < 1e-9
    elif kind == "axis_position":
        assert values["distance_m"] == pytest.approx(1e-3, abs=1e-12)
    elif kind == "zero_offset":
        assert abs(values["offset_rad"]) == pytest.approx(0.1, abs=1e-12)
    elif kind == "rounding":
        assert values["constant"] == "π/2" and values["written"] == "1.5708"
    elif kind == "limits_degrees_as_radians":
        assert {f.values["bound"] for f in hits} == {"lower", "upper"}


@pytest.mark.parametrize("mutate,kind,name", [m for m in MUTATIONS if m[1] not in ("rounding",)], ids=[m[0].__name__ for m in MUTATIONS if m[1] != "rounding"])
def test_a_real_difference_fails_the_verdict_with_an_error_finding_naming_it(tmp_path, mutate, kind, name):
    result = verify_files(*write_pair(tmp_path, *mutate(*generated_pair("panda"))), FAST)
    assert result.verdict == "fail" and result.exit_code == 1
    hits = [f for f in result.findings if f.kind == kind and f.severity == "error"]
    assert hits, [(f.kind, f.severity) for f in result.findings]
    assert name is None or any(f.subject == name for f in hits), hits


@pytest.mark.parametrize("mutate", [m[0] for m in MUTATIONS if m[1] in ("axis_sign_flip", "axis_position", "rounding", "zero_offset")])
def test_kinematic_mutations_fail_the_verdict_where_the_chain_starts_to_differ(tmp_path, mutate):
    result = verify_files(*write_pair(tmp_path, *mutate(*generated_pair("panda"))), FAST)
    assert not result.passed
    starts = [f for f in result.findings if f.kind == "disagreement_starts"]
    joint = next(f.subject for f in result.findings if f.kind in ("axis_sign_flip", "axis_position", "zero_offset", "axis_direction"))
    assert starts and starts[0].subject == joint.replace("joint", "link")


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(spec=arm_specs(max_joints=4), xyz=st.lists(st.floats(-1, 1), min_size=3, max_size=3),
       rpy=st.lists(st.floats(-3, 3), min_size=3, max_size=3))
def test_random_arm_with_a_moved_base_gives_only_the_base_transform(spec, xyz, rpy):
    """The MJCF's top-level mount moved by a random transform: recovered exactly, residual zero,
    and Pinocchio's MJCF parser (which ignores a top-level body's pose) is named as a quirk."""
    urdf, mjcf = generate_urdf(spec), generate_mjcf(spec)
    quat = matrix_to_quat(rpy_to_matrix(rpy))
    moved = mjcf.replace('<body name="world_mount">', f'<body name="world_mount" pos="{" ".join(repr(float(v)) for v in xyz)}" '
                         f'quat="{" ".join(repr(float(v)) for v in quat)}">', 1)
    with tempfile.TemporaryDirectory() as folder:
        diag = diagnose_files(*write_pair(Path(folder), urdf, moved))
    found = {f.kind: f.values for f in diag["findings"]}
    assert found["base_transform"]["residual_position_m"] < 1e-9
    assert np.allclose(found["base_transform"]["xyz"], xyz, atol=1e-9)
    assert np.allclose(rpy_to_matrix(found["base_transform"]["rpy"]), rpy_to_matrix(rpy), atol=1e-9)
    if np.linalg.norm(xyz) > 1e-6 or np.linalg.norm(rpy) > 1e-6:
        assert "parser_quirk" in found
    assert set(found) <= {"base_transform", "parser_quirk"}


@settings(max_examples=5, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(spec=arm_specs(max_joints=4, prismatic=False), data=st.data())
def test_random_arm_identical_then_one_axis_flipped(spec, data):
    urdf, mjcf = generate_urdf(spec), generate_mjcf(spec)
    k = data.draw(st.integers(0, len(spec.joints) - 1))
    name = spec.joints[k].name
    flipped = re.sub(rf'(<joint name="{name}"[^>]*? axis=")([^"]*)(")',
                     lambda m: m[1] + " ".join(repr(-float(v)) for v in m[2].split()) + m[3], mjcf, count=1)
    with tempfile.TemporaryDirectory() as folder:
        assert diagnose_files(*write_pair(Path(folder), urdf, mjcf))["findings"] == []
        found = diagnose_files(*write_pair(Path(folder), urdf, flipped))["findings"]
    assert [f.subject for f in found if f.kind == "axis_sign_flip"] == [name]


def test_a_library_refusing_a_file_is_a_finding_not_a_crash(tmp_path):
    urdf, mjcf = generated_pair("arm3")
    massless = re.sub(r'(<link name="link3">).*?(</link>)', r"\1\2", urdf, count=1, flags=re.S)
    result = verify_files(*write_pair(tmp_path, massless, mjcf), FAST)
    refused = [f for f in result.findings if f.kind == "parser_refused"]
    assert [f.values["backend"] for f in refused] == ["mujoco-urdf"]
    assert "mujoco-urdf" not in result.backends and result.checks
    assert any(f.kind == "mass_difference" and f.subject == "link3" for f in result.findings)


def test_joints_matched_by_chain_order_when_names_differ(tmp_path):
    urdf, mjcf = generated_pair("panda")
    renamed = re.sub(r'"panda_joint(\d)"', r'"J\1"', mjcf)  # joints and the actuators naming them
    diag = diagnose_files(*write_pair(tmp_path, urdf, renamed))
    assert [(a, b) for a, b, _ in diag["matching"].joints] == [(f"panda_joint{i}", f"J{i}") for i in range(1, 8)]
    assert diag["findings"] == []


# --- bad input -------------------------------------------------------------------------------

def _bad(tmp_path, urdf_text=None, mjcf_text=None):
    urdf, mjcf = generated_pair("arm3")
    return write_pair(tmp_path, urdf if urdf_text is None else urdf_text, mjcf if mjcf_text is None else mjcf_text)


XXE = '<?xml version="1.0"?><!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]><robot name="r">&x;</robot>'
BOMB = ('<?xml version="1.0"?><!DOCTYPE r [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">'
        '<!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;"><!ENTITY d "&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;">]><robot name="r">&d;</robot>')
FIXED_ONLY = '<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint></robot>'
SLIDER = ('<mujoco model="s"><worldbody><body name="b"><joint name="slider" type="slide" axis="1 0 0"/>'
          '<inertial pos="0 0 0" mass="1" diaginertia="0.1 0.1 0.1"/></body></worldbody></mujoco>')


@pytest.mark.parametrize("case,message", [
    ("missing", "is not a file"), ("not_xml", "is not XML"), ("urdf_as_mjcf", "is a URDF, not an MJCF"),
    ("xxe", "entities"), ("bomb", "entities"), ("no_movable", "no movable"), ("no_common", "no common joints"),
])
def test_bad_input_is_a_one_line_input_error(tmp_path, case, message, capsys):
    urdf, mjcf = _bad(tmp_path)
    if case == "missing":
        urdf = str(tmp_path / "absent.urdf")
    elif case == "not_xml":
        Path(mjcf).write_text("this is not xml <")
    elif case == "urdf_as_mjcf":
        mjcf = urdf
    elif case in ("xxe", "bomb"):
        Path(urdf).write_text(XXE if case == "xxe" else BOMB)
    elif case == "no_movable":
        Path(urdf).write_text(FIXED_ONLY)
    elif case == "no_common":
        Path(mjcf).write_text(SLIDER)
    with pytest.raises(InputError, match=message):
        verify_files(urdf, mjcf, FAST)
    code = main(["verify", "--urdf", urdf, "--mjcf", mjcf, "--samples", "5", "--json", str(tmp_path / "r.json"),
                 "--report", str(tmp_path / "r.html")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1 and message in err


# --- real pairs ------------------------------------------------------------------------------

REAL_PAIRS = {"panda": ("panda_erd.urdf", "panda_menagerie.xml"),
              "iiwa14": ("iiwa14_no_collision_drake.urdf", "iiwa14_menagerie.xml"),
              "z1": ("z1_erd.urdf", "z1_menagerie.xml")}


@pytest.mark.parametrize("robot", list(REAL_PAIRS))
def test_real_pair_runs_to_a_verdict(robot):
    folder = REAL / robot
    if not folder.is_dir():
        pytest.skip(f"{folder} absent")
    urdf, mjcf = (str(folder / f) for f in REAL_PAIRS[robot])
    result = verify_files(urdf, mjcf, FAST)
    assert result.verdict in ("pass", "fail") and result.checks
    found = {(f.kind, f.subject or None) for f in result.findings}
    if robot == "panda":  # finger_joint2 is a <mimic> joint: yourdfpy hides it; hand quat written to 7 digits
        assert ("parser_refused", "URDF") in found and ("rounding", "hand") in found
    elif robot == "iiwa14":  # Menagerie's link1 diaginertia has ixx and iyy exchanged w.r.t. Drake's URDF
        assert ("inertia_rotated", "iiwa_link_1") in found
    elif robot == "z1":  # the URDF has a gripper the MJCF lacks
        assert ("unmatched_joint", "jointGripper") in found and ("mass_difference", "link06") in found
