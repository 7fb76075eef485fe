"""One-file audit (``verify --urdf X`` or ``--mjcf Y`` alone): every library that reads the file,
compared with each other on the real libraries. A library that reads the file differently is one
error finding naming it and the first element it places elsewhere; a refusal is a warning naming
the library; Pinocchio's dropped top-level pose (pinocchio#2782) is information, corrected."""

from __future__ import annotations

import dataclasses
import json
import math
import os
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from kinverify.backends import available_backends, names_reading
from kinverify.backends.pinocchio_ import PinocchioBackend
from kinverify.cli import main
from kinverify.errors import InputError
from kinverify.filemode.audit import ONLY_READER, _describe, _disagreement, _first_element, _section, audit_file
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.filemode.read.loading import load_urdf
from kinverify.filemode.read.prepare import prepare_urdf
from kinverify.filemode.usd_audit import ONLY_READER as USD_ONLY
from kinverify.filemode.compare.crosscheck import QUIRK_ISSUE
from kinverify.run import VerifyOptions
from tests.filemode.pairs import generated_pair, ignored_by_drake, small_usda, turned_world
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
    assert {"pinocchio-urdf", "mujoco-urdf"} <= set(wrong.values["agree"]) and "yourdfpy" not in wrong.values["agree"]
    assert wrong.message.endswith(" agree with each other, yourdfpy stands apart")  # the majority, named
    failed = {c.backends for c in result.failed}
    assert failed == {("pinocchio-urdf", "yourdfpy")}  # MuJoCo's URDF import agrees with Pinocchio
    assert statuses(result)["yourdfpy"] == "reads it differently"


def test_an_inertial_read_otherwise_joins_a_frame_read_otherwise(tmp_path):
    """Two causes in one file: yourdfpy moves a prismatic carriage along an axis of length 2, and
    MuJoCo's URDF import gives a link without <inertial> its geometry's mass: one finding each."""
    urdf, _ = generated_pair("scara")
    joint = re.search(r'<joint name="(\w+)" type="prismatic">.*?<child link="(\w+)"', urdf, re.S)
    urdf = re.sub(
        rf'(<joint name="{joint[1]}" type="prismatic">.*?<axis xyz=")0.0 0.0 -1.0(")', r"\g<1>0 0 -2\2", urdf, count=1, flags=re.S
    )
    bare, n = re.subn(rf'(<link name="{joint[2]}">)\s*<inertial>.*?</inertial>', r"\1", urdf, count=1, flags=re.S)
    assert n == 1
    result = audit(tmp_path, bare, "urdf")
    assert sorted((f.kind, f.subject, f.property, f.values["backend"]) for f in result.findings if f.fails) == [
        ("parser_disagreement", joint[2], "fk.position", "yourdfpy"),
        ("parser_disagreement", joint[2], "inertia.mass", "mujoco-urdf"),
    ]


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


# --- the audit's own decisions, on tiny files and the real libraries -----------------------------

LIMIT = '<limit lower="-1" upper="1" effort="1" velocity="1"/>'
CHAIN = (
    '<robot name="c"><link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/>'
    '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/>'
    f'<axis xyz="0 0 1"/>{LIMIT}</joint>'
    '<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.2 0 0"/>'
    f'<axis xyz="0 1 0"/>{LIMIT}</joint>'
    '<joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.3 0 0"/>'
    f'<axis xyz="0 1 0"/>{LIMIT}</joint></robot>'
)
Q = np.array([[0.1, 0.2, 0.3], [0.0, -0.1, -0.4]])


def pin(text: str, frames=("base", "l1", "l2", "l3")):
    return PinocchioBackend.from_urdf(text, ["j1", "j2", "j3"], list(frames))


@pytest.fixture(scope="module")
def chain_desc():
    return describe_urdf(CHAIN)


def test_the_first_element_read_differently_is_the_highest_in_the_chain_placed_elsewhere_at_zero(chain_desc):
    moved = CHAIN.replace('<origin xyz="0.2 0 0"/>', '<origin xyz="0.25 0 0"/>')
    where = _first_element("urdf", chain_desc, pin(CHAIN), pin(moved, ("l3", "l2", "l1", "base")), Q, (1e-9, 1e-9))
    assert where == {
        "frame": "l2",  # the highest, though l3 comes first in the other reading's frames
        "joint": "j2",
        "position_m": pytest.approx(0.05, rel=1e-9),
        "rotation_rad": pytest.approx(0.0, abs=1e-12),
        "at_zero": True,
        "frames": ["l3", "l2"],
        "element": "link",
    }
    assert _first_element("urdf", chain_desc, pin(CHAIN), pin(moved), Q, (0.06, 1e-9)) is None  # within tolerance
    turned = CHAIN.replace('<origin xyz="0.2 0 0"/>', '<origin xyz="0.2 0 0" rpy="0 0 0.1"/>')  # only turned at zero
    where = _first_element("urdf", chain_desc, pin(CHAIN), pin(turned), Q, (0.5, 1e-9))
    assert (where["frame"], where["at_zero"], where["frames"]) == ("l2", True, ["l2", "l3"])
    assert where["rotation_rad"] == pytest.approx(0.1, rel=1e-9)


def test_an_element_apart_only_once_its_joint_moves_is_named_with_the_joint(chain_desc):
    flipped = CHAIN.replace('<origin xyz="0.3 0 0"/><axis xyz="0 1 0"/>', '<origin xyz="0.3 0 0"/><axis xyz="0 -1 0"/>')
    assert flipped != CHAIN
    where = _first_element("urdf", chain_desc, pin(CHAIN), pin(flipped), Q, (1e-9, 1e-9))
    assert (where["frame"], where["joint"], where["at_zero"], where["frames"]) == ("l3", "j3", False, ["l3"])
    assert where["rotation_rad"] == pytest.approx(0.8, rel=1e-9)  # 2 × 0.4 rad, the largest |q3|
    assert where["position_m"] == pytest.approx(0.0, abs=1e-12)  # its origin is on the axis
    assert _first_element("urdf", chain_desc, pin(CHAIN), pin(flipped), Q, (1e-9, 0.9)) is None


def test_readings_alike_or_without_a_frame_in_common_have_no_first_element(chain_desc):
    assert _first_element("urdf", chain_desc, pin(CHAIN), pin(CHAIN), Q, (1e-12, 1e-12)) is None
    assert _first_element("urdf", chain_desc, pin(CHAIN, ("base", "l1")), pin(CHAIN, ("l2", "l3")), Q, (1e-9, 1e-9)) is None


WHERE = dict(
    frame="l2", joint="j2", position_m=0.0123456, rotation_rad=0.5, at_zero=False, frames=["l2", "l3", "l4"], element="link"
)


def test_a_disagreement_names_the_library_the_element_and_how_far_apart():
    f = _disagreement("urdf", "pinocchio-urdf", "yourdfpy", WHERE)
    assert f.message == (
        "yourdfpy reads the URDF's link l2 differently from pinocchio-urdf: placed alike at q = 0, apart once j2 moves, "
        "up to 0.0123 m, 0.5 rad (2 frames below it differ with it)"
    )
    assert (f.kind, f.severity, f.subject, f.subject_type, f.property, f.unit) == (
        "parser_disagreement",
        "error",
        "l2",
        "link",
        "fk.position",
        "m|rad",
    )
    assert f.magnitude == 0.5 and f.values == {
        "file": "URDF",
        "backends": ["pinocchio-urdf", "yourdfpy"],
        "backend": "yourdfpy",
        "agree": [],
        "joint": "j2",
        "position_m": 0.0123456,
        "rotation_rad": 0.5,
        "at_zero": False,
        "frames": ["l2", "l3", "l4"],
    }
    near = _disagreement("urdf", "a", "b", {**WHERE, "position_m": 2.0, "rotation_rad": 0.1})
    assert near.magnitude == 2.0


def test_a_disagreement_says_where_it_starts_and_who_agrees():
    at_zero = _disagreement("mjcf", "mujoco", "drake-mjcf", {**WHERE, "at_zero": True, "frames": ["l2", "l3"]})
    assert "MJCF's link l2 differently from mujoco: placed elsewhere at q = 0, up to" in at_zero.message
    assert at_zero.message.endswith(" (1 frame below it differ with it)")
    unowned = _disagreement("sdf", "a", "b", {**WHERE, "joint": None, "frames": ["l2"]})
    assert unowned.message.endswith("apart once the joints moves, up to 0.0123 m, 0.5 rad")
    site = _disagreement("mjcf", "mujoco", "b", {**WHERE, "element": "site", "frame": "tip"})
    assert (site.subject, site.subject_type) == ("tip", "frame") and "MJCF's site tip differently" in site.message
    two = _disagreement("urdf", "pinocchio-urdf", "yourdfpy", WHERE, ("pinocchio-urdf", "mujoco-urdf"))
    assert two.message.endswith("differ with it); pinocchio-urdf and mujoco-urdf agree with each other, yourdfpy stands apart")
    assert two.values["agree"] == ["pinocchio-urdf", "mujoco-urdf"]
    three = _disagreement("urdf", "a", "d", WHERE, ("a", "b", "c"))
    assert three.message.endswith("; a, b and c agree with each other, d stands apart")
    one = _disagreement("urdf", "a", "d", WHERE, ("a",))
    assert one.message.endswith("differ with it)")


def left_out(name: str) -> str:
    """What the audit's table says of a library that reads the file's format but was not compared."""
    info = available_backends()[name]
    return "not selected (--backends)" if info.available else f"not installed ({info.reason})"


def test_the_audit_table_says_how_each_library_read_the_file():
    wanted = readers("urdf")[:4]  # the installed ones: the newton extra may be absent
    ref, refused, ignoring, differ = wanted
    backends = {n: n for n in wanted if n != refused}
    findings = [
        finding("parser_refused", "r", {"backend": refused}),
        finding("parser_refused", "i", {"backend": ignoring, "elements": ["<a>", "b@c"]}),
        finding("parser_refused", "i", {"backend": refused, "elements": ["<z>"]}),
        finding("parser_disagreement", "d", {"backend": differ}, severity="error"),
    ]
    rows = [(0, f"{ref} vs {ignoring}", 1.5e-10, 2.25e-9), (0, f"{ref} vs {differ}", 0.01234, 0.5)]
    section = _section("urdf", "r.urdf", wanted, backends, dict(backends), ref, rows, findings, ["note"])
    assert section.title == "One-file audit: every library reading the URDF"
    assert section.summary == f"r.urdf read by 3 libraries ({', '.join(backends)}); reference {ref}; 1 disagreement(s)."
    (table,) = section.tables
    assert (table.title, table.columns) == (
        "Libraries",
        ["library", "reading", f"max position vs {ref} [m]", "max rotation [rad]"],
    )
    assert table.rows == [
        [ref, "reference", "", ""],
        [refused, "refuses the file", "", ""],
        [ignoring, "agrees (its parser ignores <a>, b@c)", "1.5e-10", "2.25e-09"],
        [differ, "reads it differently", "0.0123", "0.5"],
        *([n, left_out(n), "", ""] for n in names_reading("urdf") if n not in wanted),
    ]
    assert section.notes == ["note"]
    quirk = finding("parser_quirk", "q", {"backends": [ref, differ]})
    quirky = _section("urdf", "r.urdf", wanted, {n: n for n in wanted}, {ref: ref}, ref, [], [quirk], [])
    assert [row[1] for row in quirky.tables[0].rows][:4] == [
        "reference",
        "agrees",
        "agrees",
        "agrees once the known quirk is corrected (pinocchio#2782)",
    ]
    assert quirky.summary == f"r.urdf read by 1 library ({ref}); reference {ref}; 0 disagreement(s)."


def test_a_file_no_reference_reader_can_load_is_one_line_naming_the_reader(tmp_path):
    mjcf = '<mujoco><worldbody><body name="b"><joint name="j"/><geom size="0.1" material="nowhere"/></body></worldbody></mujoco>'
    path = tmp_path / "m.xml"
    path.write_text(mjcf)
    with pytest.raises(InputError) as err:
        audit_file(str(path), "mjcf", OPTIONS)
    assert str(err.value).startswith(f"--mjcf: MuJoCo, the reference reader of MJCF, cannot load {path}: material 'nowhere'")
    sdf = '<sdf version="1.9"><model name="m"><link name="a"/><joint name="j" type="revolute"><parent>a</parent><child>nowhere</child></joint></model></sdf>'
    path = tmp_path / "s.sdf"
    path.write_text(sdf)
    with pytest.raises(InputError) as err:
        audit_file(str(path), "sdf", OPTIONS)
    assert str(err.value).startswith(f"--sdf: Drake, the only reader of SDFormat, cannot load {path}: ") and "nowhere" in str(
        err.value
    )


def test_a_urdf_pinocchio_refuses_is_described_through_mujoco_and_one_neither_reads_is_refused(tmp_path):
    inertial = '<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>'
    text = (
        f'<robot name="r"><link name="base"/><link name="l1">{inertial}</link><joint name="j1" type="revolute">'
        '<parent link="base"/><child link="l1"/><origin xyz="0.1 0 0"/><axis xyz="0 0 1"/></joint></robot>'
    )  # no <limit>: urdfdom refuses a revolute joint without one, MuJoCo reads it unlimited
    path = tmp_path / "r.urdf"
    path.write_text(text)
    out, desc, free = _describe("urdf", load_urdf(str(path), keep_meshes=False))
    assert (desc.library, desc.kind, free, [j.name for j in desc.joints]) == ("mujoco (URDF import)", "urdf", [], ["j1"])
    assert desc.joints[0].anchor == pytest.approx([0.1, 0, 0], abs=1e-12) and out == prepare_urdf(load_urdf(str(path)).text)
    path.write_text(text.replace(inertial, ""))  # MuJoCo refuses a moving body without mass
    with pytest.raises(InputError) as err:
        audit_file(str(path), "urdf", OPTIONS)
    assert str(err.value).startswith(f"--urdf: neither Pinocchio nor MuJoCo can load {path}: mass and inertia")


def test_what_a_one_file_audit_refuses_before_reading(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text(CHAIN.replace('type="revolute"', 'type="fixed"'))
    with pytest.raises(InputError) as err:
        audit_file(str(path), "urdf", OPTIONS)
    assert str(err.value) == f"--urdf: {path} has no movable 1-DOF joints (hinge or slide) to compare"
    with pytest.raises(InputError) as err:
        audit_file(str(path), "urdf", VerifyOptions(backends=["mujoco", "drake-mjcf"]))
    assert str(err.value) == (
        f"--backends: a one-file audit of a URDF compares {', '.join(names_reading('urdf'))}; got mujoco, drake-mjcf"
    )


def test_a_urdf_pinocchio_refuses_is_one_refusal_and_its_dynamics_are_not_compared(tmp_path):
    inertial = '<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>'
    path = tmp_path / "r.urdf"
    path.write_text(
        f'<robot name="r"><link name="base"/><link name="l1">{inertial}</link><joint name="j1" type="revolute">'
        '<parent link="base"/><child link="l1"/><origin xyz="0.1 0 0"/><axis xyz="0 0 1"/></joint></robot>'
    )
    result = audit_file(str(path), "urdf", dataclasses.replace(OPTIONS, backends=["pinocchio-urdf", "mujoco-urdf"]))
    (refused,) = result.findings  # one cause, one finding
    assert (refused.kind, refused.values["backend"]) == ("parser_refused", "pinocchio-urdf") and "limits" in refused.message
    assert "dynamics not compared: pinocchio-urdf did not read the file" in result.notes
    assert statuses(result) == {
        "pinocchio-urdf": "refuses the file",
        "mujoco-urdf": "reference",
        **{n: left_out(n) for n in names_reading("urdf") if n not in ("pinocchio-urdf", "mujoco-urdf")},
    }
    assert result.model_info["audit"] == {"file": "URDF", "libraries": ["mujoco-urdf"], "reference": "mujoco-urdf"}


def test_a_file_no_selected_library_reads_is_one_line_naming_their_refusals(tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text(
        '<robot name="r"><link name="base"/><link name="l1"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" '
        'izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link><joint name="j1" type="revolute"><parent link="base"/>'
        '<child link="l1"/><axis xyz="0 0 1"/></joint></robot>'
    )  # no <limit>: urdfdom refuses it
    with pytest.raises(InputError) as err:
        audit_file(str(path), "urdf", dataclasses.replace(OPTIONS, backends=["pinocchio-urdf"]))
    assert str(err.value).startswith(f"--urdf: no library can read {path}: pinocchio-urdf refuses the URDF: ")
    assert "limits" in str(err.value) and "\n" not in str(err.value)


def test_a_free_base_is_held_fixed_and_said_so(tmp_path):
    path = tmp_path / "f.xml"
    path.write_text(
        '<mujoco model="f"><asset><mesh name="gone" file="gone.stl"/></asset><worldbody><body name="base" pos="0 0 0.5">'
        '<freejoint/><geom size="0.1"/><body name="arm" pos="0.2 0 0"><joint name="j" axis="0 0 1" range="-1 1"/>'
        '<geom size="0.05"/><geom type="mesh" mesh="gone" mass="0"/></body></body></worldbody></mujoco>'
    )
    options = dataclasses.replace(OPTIONS, backends=["mujoco", "pinocchio-mjcf"], suites=["kinematics"])
    result = audit_file(str(path), "mjcf", options)
    (free,) = result.findings
    assert (free.kind, free.subject, free.values) == ("floating_base", "MJCF", {"file": "MJCF", "bodies": ["base"]})
    assert free.message == (
        "the MJCF's free base (base) is held at the identity pose: the libraries' readings of everything below it are compared"
    )
    assert result.verdict == "pass" and result.backends == ["mujoco", "pinocchio-mjcf"]
    assert ("mujoco", "pinocchio-mjcf") in {c.backends for c in result.checks} and "dynamics" not in result.sections
    assert result.notes == ["MJCF: 1 mesh geoms and their assets skipped, their files are absent"]  # the reading's own
    assert result.duration_s > 0
    assert result.model_info["audit"] == {"file": "MJCF", "libraries": ["mujoco", "pinocchio-mjcf"], "reference": "mujoco"}
    assert result.model_info["files"] == {"mjcf": str(path)} and list(result.sections)[0] == "audit"
    assert result.source == str(path) and result.model == "f"


def test_an_sdformat_audit_is_drakes_reading_alone_and_says_so(tmp_path):
    path = tmp_path / "s.sdf"
    path.write_text(
        '<sdf version="1.9"><model name="m"><link name="a"/><link name="b"><inertial><mass>1</mass></inertial></link>'
        '<joint name="j" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz>'
        "<limit><lower>-1</lower><upper>1</upper></limit></axis></joint></model></sdf>"
    )
    result = audit_file(str(path), "sdf", OPTIONS)
    assert result.notes[0] == ONLY_READER and "Drake is the only library here that reads SDFormat" in ONLY_READER
    assert "dynamics not compared: Drake is the only reader of SDFormat" in result.notes
    assert [f.kind for f in result.findings] == ["floating_base"] and "SDF's free base (a)" in result.findings[0].message
    assert statuses(result) == {"drake-sdf": "reference"} and result.verdict == "pass"
    assert result.sections["audit"].summary == f"{path} read by 1 library (drake-sdf); reference drake-sdf; 0 disagreement(s)."
    assert result.model_info["audit"] == {"file": "SDF", "libraries": ["drake-sdf"], "reference": "drake-sdf"}


MIMIC = (
    '<robot name="m"><link name="base"/>'
    + "".join(
        f'<link name="l{i}"><inertial><mass value="1"/><origin xyz="0.1 0 0"/>'
        '<inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        for i in (1, 2)
    )
    + '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 1 0"/>'
    '<limit lower="-1" upper="1" effort="10" velocity="1"/></joint>'
    '<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.2 0 0"/><axis xyz="0 1 0"/>'
    '<limit lower="-1" upper="1" effort="10" velocity="1"/><mimic joint="j1" multiplier="0.5"/></joint></robot>'
)


def test_dynamics_of_one_file_cover_every_joint_a_follower_too(tmp_path):
    path = tmp_path / "m.urdf"
    path.write_text(MIMIC)
    result = audit_file(str(path), "urdf", dataclasses.replace(OPTIONS, backends=["pinocchio-urdf", "mujoco-urdf"]))
    dynamics = [c for c in result.checks if c.property.startswith("dynamics.")]
    assert {c.property for c in dynamics} >= {"dynamics.mass_matrix", "dynamics.gravity", "dynamics.forward"}
    assert all(c.passed for c in dynamics) and not result.internal_errors and result.notes == []
    assert result.command == "" and "dynamics" in result.timings and "dynamics" in result.sections
    alone = audit_file(str(path), "urdf", dataclasses.replace(OPTIONS, backends=["yourdfpy"]), command="kinverify verify")
    assert alone.notes == ["dynamics not compared: pinocchio-urdf, mujoco-urdf did not read the file"]
    assert alone.command == "kinverify verify" and "dynamics" not in alone.sections


def test_every_free_base_is_named(tmp_path):
    path = tmp_path / "two.sdf"
    path.write_text(
        '<sdf version="1.9"><model name="m"><link name="a"/><link name="b"><inertial><mass>1</mass></inertial></link>'
        '<link name="c"><inertial><mass>1</mass></inertial></link><joint name="j" type="revolute"><parent>a</parent>'
        "<child>b</child><axis><xyz>0 0 1</xyz><limit><lower>-1</lower><upper>1</upper></limit></axis></joint></model></sdf>"
    )
    (free,) = audit_file(str(path), "sdf", OPTIONS).findings
    assert free.message.startswith("the SDF's free base (a, c) is held at the identity pose") and free.values["bodies"] == [
        "a",
        "c",
    ]


def test_a_usd_audit_is_usd_cores_reading_with_what_the_file_states(tmp_path):
    pytest.importorskip("pxr")
    path = small_usda(tmp_path, "r")  # two bodies and a revolute joint between them
    result = audit_file(path, "usd", OPTIONS)
    assert result.notes[0] == USD_ONLY and list(result.sections)[:2] == ["audit", "usd"]
    assert (
        "dynamics not compared: usd-core reads the USD's kinematics and inertials, no USD dynamics library is here"
        in result.notes
    )
    assert [r[0] for r in result.sections["usd"].tables[0].rows] == ["j1"]
    assert result.model_info["audit"]["file"] == "USD" and result.model_info["files"] == {"usd": path}
    assert result.sections["audit"].title == "One-file audit: every library reading the USD"


def test_what_the_reference_reading_leaves_out_is_a_note_naming_the_file(tmp_path):
    path = tmp_path / "b.xml"
    path.write_text(
        '<mujoco model="b"><worldbody><body name="base"><geom size="0.1"/><body name="arm" pos="0.2 0 0">'
        '<joint name="j" axis="0 0 1" range="-1 1"/><geom size="0.05"/><body name="tip" pos="0.2 0 0">'
        '<joint name="ball" type="ball"/><geom size="0.05"/></body></body></body></worldbody></mujoco>'
    )
    options = dataclasses.replace(OPTIONS, backends=["mujoco", "pinocchio-mjcf"], suites=["kinematics"])
    result = audit_file(str(path), "mjcf", options)
    assert result.notes == ["MJCF: ball: mjJNT_BALL joints are not compared (held at 0)"] and result.verdict == "pass"


def test_dynamics_alone_on_at_most_the_dynamics_samples(tmp_path):
    path = tmp_path / "m.urdf"
    path.write_text(MIMIC)
    only = VerifyOptions(samples=150, backends=["pinocchio-urdf", "mujoco-urdf"], suites=["dynamics"])
    result = audit_file(str(path), "urdf", only)
    assert {c.property.split(".")[0] for c in result.checks} == {"dynamics"}  # no kinematics asked for
    assert {c.samples for c in result.checks if c.property == "dynamics.mass_matrix"} == {100}  # the default cap
    fewer = audit_file(str(path), "urdf", dataclasses.replace(only, extra={"dynamics_samples": 7}))
    assert {c.samples for c in fewer.checks if c.property == "dynamics.mass_matrix"} == {7}


def test_dynamics_the_suite_skips_is_a_note_naming_the_library_that_read_the_file(tmp_path):
    """A ball joint (not compared) gives the MJCF more degrees of freedom than the compared joints:
    Pinocchio's MJCF parser declines its dynamics, and the note says so in full (the terminal shows
    only the section summary's first clause)."""
    mjcf = """<mujoco model="ball"><worldbody>
      <body name="a"><joint name="j1" axis="0 0 1"/><geom type="sphere" size="0.05" mass="1"/>
        <body name="b" pos="0.2 0 0"><joint name="j2" type="ball"/><geom type="sphere" size="0.05" mass="1"/></body>
      </body></worldbody></mujoco>"""
    path = tmp_path / "ball.xml"
    path.write_text(mjcf)
    result = audit_file(str(path), "mjcf", dataclasses.replace(OPTIONS, backends=["mujoco", "pinocchio-mjcf"]))
    reason = "pinocchio-mjcf: dynamics needs the model to move by the compared joints only (1 degree of freedom), the MJCF has 4"
    assert result.sections["dynamics"].summary == f"skipped: {reason}"
    assert f"dynamics not compared: {reason}" in result.notes
    assert f"dynamics not compared: {reason}" in result.sections["audit"].notes
