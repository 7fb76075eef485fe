"""One-file audit (``verify --urdf X`` or ``--mjcf Y`` alone): every library that reads the file,
compared with each other on the real libraries. A library that reads the file differently is one
error finding naming it and the first element it places elsewhere; a refusal is a warning naming
the library; Pinocchio's dropped top-level pose (pinocchio#2782) is information, corrected."""

from __future__ import annotations

import json
import math
import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from kinverify.backends import available_backends, names_reading
from kinverify.cli import main
from kinverify.filemode.audit import audit_file
from kinverify.filemode.compare.crosscheck import QUIRK_ISSUE
from kinverify.run import VerifyOptions
from tests.filemode.pairs import generated_pair, ignored_by_drake, turned_world
from tests.paths import REAL_ROBOTS

OPTIONS = VerifyOptions(samples=20, fd_samples=4, extra={"dynamics_samples": 20})
REAL = Path(os.environ.get("KINVERIFY_REAL_ROBOTS", REAL_ROBOTS))
REAL_FILES = [
    f"{robot}/{name}"
    for robot, names in {
        "panda": ("panda_erd.urdf", "panda_menagerie.xml"),
        "iiwa14": ("iiwa14_no_collision_drake.urdf", "iiwa14_menagerie.xml"),
        "z1": ("z1_erd.urdf", "z1_menagerie.xml"),
        "go2": ("go2_erd.urdf", "go2_menagerie.xml"),
    }.items()
    for name in names
]


def readers(kind: str) -> list[str]:
    return [n for n in names_reading(kind) if available_backends()[n].available]


def audit(tmp_path, text: str, kind: str, name: str = "robot"):
    path = tmp_path / f"{name}.{'urdf' if kind == 'urdf' else 'xml'}"
    path.write_text(text)
    return audit_file(str(path), kind, OPTIONS)


def statuses(result) -> dict[str, str]:
    return {row[0]: row[1] for row in result.sections["audit"].tables[0].rows}


@pytest.mark.parametrize("kind", ["urdf", "mjcf"])
def test_a_generated_file_is_read_alike_by_every_library(tmp_path, kind):
    urdf, mjcf = generated_pair("panda")
    result = audit(tmp_path, urdf if kind == "urdf" else mjcf, kind)
    assert result.verdict == "pass" and result.exit_code == 0
    assert result.backends == readers(kind) and len(result.backends) >= 2
    pairs = {c.backends for c in result.checks if c.property == "fk.position"}
    assert pairs == {(readers(kind)[0], other) for other in readers(kind)[1:]}  # every reader against the primary one
    ignored = [f for f in result.findings if ignored_by_drake(f) and f.values.get("backend") == "drake-mjcf"]
    assert all(c.passed for c in result.checks) and not [f for f in result.findings if f.severity != "info" and f not in ignored]
    if kind == "mjcf" and "drake-mjcf" in result.backends:  # Drake's MJCF parser says, element by element, what it ignores
        kinds = {e: (f.kind, f.severity) for f in ignored for e in f.values["elements"]}
        assert kinds["<site> in <body>"] == ("parser_refused", "warning"), kinds  # a site is a compared frame
        assert kinds["joint@frictionloss"] == kinds["option@timestep"] == ("parser_ignores", "info"), kinds  # not compared
    assert {n: s.split(" (its parser ignores")[0] for n, s in statuses(result).items() if n in readers(kind)} == {
        readers(kind)[0]: "reference",
        **{n: "agrees" for n in readers(kind)[1:]},
    }
    assert result.model_info["files"] == {kind: str(tmp_path / f"robot.{'urdf' if kind == 'urdf' else 'xml'}")}


def test_a_top_level_body_pose_is_pinocchios_known_quirk_reported_as_information(tmp_path):
    urdf, mjcf = turned_world(*generated_pair("panda"), xyz=[0.1, 0.2, 0.3])
    result = audit(tmp_path, mjcf, "mjcf")
    (quirk,) = [f for f in result.findings if f.kind == "parser_quirk"]
    assert quirk.severity == "info" and QUIRK_ISSUE in quirk.message and quirk.values["issue"] == QUIRK_ISSUE
    assert quirk.values["top_level_xyz"] == pytest.approx([0.1, 0.2, 0.3])
    assert result.verdict == "pass" and "pinocchio-mjcf" in result.backends  # compared with the pose put back
    assert all(c.passed for c in result.checks if "pinocchio-mjcf" in c.backends)
    assert "pinocchio#2782" in statuses(result)["pinocchio-mjcf"]


def test_dynamics_of_one_file_in_pinocchio_and_mujoco(tmp_path):
    urdf, mjcf = generated_pair("panda")
    for kind, text, pair in (("urdf", urdf, ("pinocchio-urdf", "mujoco-urdf")), ("mjcf", mjcf, ("mujoco", "pinocchio-mjcf"))):
        result = audit(tmp_path, text, kind, kind)
        dynamics = [c for c in result.checks if c.property.startswith("dynamics.")]
        assert {c.property for c in dynamics} >= {"dynamics.mass_matrix", "dynamics.gravity", "dynamics.forward"}
        assert all(c.passed and c.backends == pair for c in dynamics) and result.verdict == "pass"
        assert pair[0] in result.sections["dynamics"].title


def test_a_tilted_top_level_body_tilts_gravity_in_pinocchios_reading_and_is_put_back(tmp_path):
    """Pinocchio's MJCF parser drops the top-level body's rotation, so its world is that body's:
    gravity there is the MJCF's gravity turned back, or gravity torques differ by newtons."""
    _, mjcf = generated_pair("panda")
    tilted = mjcf.replace(
        '<body name="world_mount">', f'<body name="world_mount" quat="{math.cos(0.15)!r} {math.sin(0.15)!r} 0 0">', 1
    )
    result = audit(tmp_path, tilted, "mjcf")
    assert [f.kind for f in result.findings if f.values.get("backend") != "drake-mjcf"] == ["parser_quirk"]
    (gravity,) = [c for c in result.checks if c.property == "dynamics.gravity"]
    assert gravity.passed and gravity.max_error < 1e-9 and result.verdict == "pass"


def test_a_link_without_inertial_is_read_with_mass_by_mujocos_urdf_import(tmp_path):
    """MuJoCo's URDF import gives a link without ``<inertial>`` the mass of its geometry (density
    1000); Pinocchio reads it massless: one finding naming the library and the link."""
    urdf, _ = generated_pair("panda")
    bare = re.sub(r'(<link name="panda_link3">)\s*<inertial>.*?</inertial>', r"\1", urdf, count=1, flags=re.S)
    result = audit(tmp_path, bare, "urdf")
    (wrong,) = [f for f in result.findings if f.fails]
    assert (wrong.kind, wrong.subject, wrong.property, wrong.values["backend"]) == (
        "parser_disagreement",
        "panda_link3",
        "inertia.mass",
        "mujoco-urdf",
    )
    assert wrong.values["pinocchio-urdf"] == 0.0 and wrong.values["mujoco-urdf"] > 0.1
    assert not [c for c in result.failed if not c.property.startswith("dynamics.")]  # kinematics agree


def test_a_library_reading_the_file_differently_fails_naming_the_library_and_the_link(tmp_path):
    """yourdfpy moves a prismatic joint along its axis as written; Pinocchio and MuJoCo make the
    axis a unit vector first (the URDF format asks for one): with ``axis="0 0 -2"`` yourdfpy's
    reading moves the carriage twice as far."""
    urdf, _ = generated_pair("scara")
    joint = re.search(r'<joint name="(\w+)" type="prismatic">.*?<child link="(\w+)"', urdf, re.S)
    doubled = re.sub(
        rf'(<joint name="{joint[1]}" type="prismatic">.*?<axis xyz=")([^"]*)(")',
        lambda m: m[1] + " ".join(repr(2 * float(x)) for x in m[2].split()) + m[3],
        urdf,
        count=1,
        flags=re.S,
    )
    result = audit(tmp_path, doubled, "urdf")
    assert result.verdict == "fail" and result.exit_code == 1
    (wrong,) = [f for f in result.findings if f.fails]
    assert wrong.kind == "parser_disagreement" and wrong.values["backend"] == "yourdfpy"
    assert (wrong.subject_type, wrong.subject, wrong.values["joint"]) == ("link", joint[2], joint[1])
    assert not wrong.values["at_zero"] and "yourdfpy" in wrong.message and joint[2] in wrong.message
    failed = {c.backends for c in result.failed}
    assert failed == {("pinocchio-urdf", "yourdfpy")}  # MuJoCo's URDF import agrees with Pinocchio
    assert statuses(result)["yourdfpy"] == "reads it differently"


def test_a_library_refusing_the_file_is_a_warning_naming_it(tmp_path):
    urdf, mjcf = generated_pair("panda")
    twice = urdf.replace(
        '<joint name="panda_joint3" type="revolute">',
        '<joint name="panda_joint3" type="revolute">\n    <origin xyz="0.3 0 0"/>',
        1,
    )
    result = audit(tmp_path, twice, "urdf")  # a repeated <origin>: MuJoCo refuses, urdfdom and yourdfpy take the first
    (refused,) = [f for f in result.findings if f.kind == "parser_refused" and not ignored_by_drake(f)]
    assert refused.severity == "warning" and refused.values["backend"] == "mujoco-urdf" and "origin" in refused.message
    assert result.verdict == "pass" and "mujoco-urdf" not in result.backends
    assert statuses(result)["mujoco-urdf"] == "refuses the file"
    two = mjcf.replace(
        '<joint name="panda_joint4" ',
        '<joint name="extra" type="hinge" axis="1 0 0" range="-1 1"/><joint name="panda_joint4" ',
        1,
    )  # Pinocchio makes one composite joint of two in a body
    result = audit(tmp_path, two, "mjcf", "two")
    refused = [f.values["backend"] for f in result.findings if f.kind == "parser_refused" and not ignored_by_drake(f)]
    assert [b for b in refused if b != "newton-mjcf"] == ["pinocchio-mjcf"]  # Newton merges them too (quirks.py)
    assert result.verdict == "pass" and [b for b in result.backends if b not in ("drake-mjcf", "newton-mjcf")] == ["mujoco"]


def test_the_command_audits_one_file_and_writes_every_output(tmp_path, capsys):
    urdf, _ = generated_pair("arm3")
    path = tmp_path / "arm3.urdf"
    path.write_text(urdf)
    out = {k: tmp_path / f"out.{k}" for k in ("json", "html", "xml")}
    code = main(
        [
            "verify",
            "--urdf",
            str(path),
            "--samples",
            "20",
            "--quiet",
            "--json",
            str(out["json"]),
            "--report",
            str(out["html"]),
            "--junit",
            str(out["xml"]),
        ]
    )
    assert code == 0 and "arm3: pass" in capsys.readouterr().out
    data = json.loads(out["json"].read_text())
    assert data["verdict"] == "pass" and data["sections"]["audit"]["tables"][0]["rows"][0][:2] == ["pinocchio-urdf", "reference"]
    assert "One-file audit" in out["html"].read_text()
    cases = list(ET.parse(out["xml"]).getroot().iter("testcase"))  # one per property and backend pair, frames counted
    assert len(cases) == len({(c["property"], tuple(c["backends"])) for c in data["checks"]}) + len(data["findings"])
    assert sum(int(c.get("assertions", 0)) for c in cases) >= len(data["checks"])


@pytest.mark.parametrize(
    "argv, words",
    [
        (["--frames", "a=b"], "--frames pairs two files"),
        (["--accept", "x.toml"], "--accept pairs two files"),
        (["--backends", "mujoco"], "a one-file audit of a URDF compares pinocchio-urdf"),
    ],
)
def test_what_a_one_file_audit_cannot_take_is_one_line(tmp_path, capsys, argv, words):
    path = tmp_path / "arm3.urdf"
    path.write_text(generated_pair("arm3")[0])
    assert main(["verify", "--urdf", str(path), "--samples", "20", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert words in err and "\n" not in err and not list(tmp_path.glob("*.json"))


@pytest.mark.parametrize("name", REAL_FILES)
def test_every_real_file_is_audited_to_a_verdict(name):
    path = REAL / name
    if not path.is_file():
        pytest.skip(f"{path} absent")
    kind = "urdf" if name.endswith(".urdf") else "mjcf"
    result = audit_file(str(path), kind, OPTIONS)
    assert result.verdict in ("pass", "fail") and not result.internal_errors
    assert result.checks and set(result.backends) <= set(readers(kind))
    for f in result.findings:  # every finding about a reading names its library
        if f.kind.startswith("parser_"):
            assert f.values.get("backend") or f.values.get("backends")
    if name.startswith("go2/") and kind == "mjcf":
        assert [f.kind for f in result.findings if f.kind == "floating_base"] == ["floating_base"]
