"""SDFormat in file mode, read by Drake: an SDFormat file against a URDF, against an MJCF, all
three at once, the one-file audit, and Drake's own example pair (the Acrobot's SDFormat and URDF
files shipped in its wheel) with a planted difference named by its finding. Skipped without the
``drake`` extra."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

pytest.importorskip("pydrake")

from pydrake.common import FindResourceOrThrow  # noqa: E402

from kinverify.cli import main  # noqa: E402
from kinverify.filemode.audit import audit_file  # noqa: E402
from kinverify.filemode.pipeline import verify_files, verify_three  # noqa: E402
from kinverify.run import VerifyOptions  # noqa: E402

FAST = VerifyOptions(samples=12, fd_samples=4, extra={"dynamics_samples": 10})
ACROBOT = Path(FindResourceOrThrow("drake/examples/acrobot/Acrobot.sdf")).parent


@pytest.fixture(scope="module")
def arm3(tmp_path_factory) -> Path:
    """``kinverify generate models/arm3.toml``, with two planted SDFormat variants: joint3's axis
    turned (y to x) and link2 20 % heavier."""
    folder = tmp_path_factory.mktemp("arm3")
    assert main(["generate", "models/arm3.toml", "--out", str(folder)]) == 0
    sdf = (folder / "arm3.sdf").read_text()
    parts = sdf.split("<xyz>")  # the joints' axes, in chain order: joint1, joint2, joint3
    parts[3] = parts[3].replace("0.0 1.0 0.0", "1.0 0.0 0.0", 1)
    (folder / "turned.sdf").write_text("<xyz>".join(parts))
    masses = sdf.split("<mass>")  # base, link1, link2, link3
    masses[3] = re.sub(r"^[0-9.e-]+", lambda m: repr(float(m[0]) * 1.2), masses[3])
    (folder / "heavier.sdf").write_text("<mass>".join(masses))
    return folder


def errors(result) -> list[tuple[str, str]]:
    return sorted((f.kind, f.subject) for f in result.findings if f.fails)


@pytest.mark.parametrize("other, kinds", [("arm3.urdf", ("urdf", "sdf")), ("arm3.xml", ("sdf", "mjcf"))])
def test_a_generated_sdf_agrees_with_the_urdf_and_the_mjcf(arm3, other, kinds):
    first, second = (arm3 / other, arm3 / "arm3.sdf") if kinds[0] != "sdf" else (arm3 / "arm3.sdf", arm3 / other)
    result = verify_files(str(first), str(second), FAST, kinds=kinds)
    assert result.verdict == "pass" and not result.internal_errors, (errors(result), result.internal_errors)
    assert "drake-sdf" in result.backends and result.model_info["files"] == {kinds[0]: str(first), kinds[1]: str(second)}
    assert result.sections["filemode"].title == f"File mode: {kinds[0].upper()} vs {kinds[1].upper()}"
    assert any("read by Drake, its only reader" in n for n in result.notes)


def test_a_turned_axis_in_the_sdf_fails_naming_the_joint(arm3, capsys):
    code = main(
        [
            "verify",
            "--sdf",
            str(arm3 / "turned.sdf"),
            "--urdf",
            str(arm3 / "arm3.urdf"),
            "--samples",
            "12",
            "--json",
            str(arm3 / "turned.json"),
            "--report",
            str(arm3 / "turned.html"),
        ]
    )
    assert code == 1
    data = json.loads((arm3 / "turned.json").read_text())
    failing = [f for f in data["findings"] if f["severity"] == "error"]
    assert [(f["kind"], f["subject"]) for f in failing] == [("axis_direction", "joint3")]
    assert "MJCF" not in failing[0]["message"] and "joint joint3" in capsys.readouterr().out


def test_a_heavier_link_in_the_sdf_is_one_mass_finding(arm3):
    result = verify_files(str(arm3 / "arm3.urdf"), str(arm3 / "heavier.sdf"), FAST, kinds=("urdf", "sdf"))
    assert result.verdict == "fail" and errors(result) == [("mass_difference", "link2")]
    (mass,) = [f for f in result.findings if f.kind == "mass_difference"]
    assert "(SDF)" in mass.message and mass.magnitude == pytest.approx(0.2 * 0.7634070148223197, rel=1e-9)


def test_three_files_at_once_are_two_pairs_in_one_result(arm3):
    result = verify_three(str(arm3 / "arm3.urdf"), str(arm3 / "arm3.xml"), str(arm3 / "turned.sdf"), FAST)
    assert result.verdict == "fail" and errors(result) == [("axis_direction", "joint3")]  # the SDF's, not the MJCF's
    assert {"mujoco", "drake-sdf", "pinocchio-urdf"} <= set(result.backends)
    assert {"filemode", "sdf:filemode"} <= set(result.sections)
    assert set(result.model_info["files"]) == {"urdf", "mjcf", "sdf"}


def test_the_one_file_audit_of_an_sdf_says_drake_is_its_only_reader(arm3):
    result = audit_file(str(arm3 / "arm3.sdf"), "sdf", FAST)
    assert result.verdict == "pass" and result.backends == ["drake-sdf"]
    assert result.model_info["audit"] == {"file": "SDF", "libraries": ["drake-sdf"], "reference": "drake-sdf"}
    assert any("Drake is the only library here that reads SDFormat" in n for n in result.notes)


def test_drakes_acrobot_sdf_and_urdf_are_one_robot_read_by_drake_alone_for_the_urdf():
    """Drake's Acrobot.urdf names a ``world`` parent link it never declares (Drake's dialect):
    Pinocchio, MuJoCo and yourdfpy refuse it, each named; Drake reads both files, and they agree."""
    result = verify_files(str(ACROBOT / "Acrobot.urdf"), str(ACROBOT / "Acrobot.sdf"), FAST, kinds=("urdf", "sdf"))
    assert result.verdict == "pass" and not result.internal_errors, errors(result)
    assert set(result.backends) == {"drake-urdf", "drake-sdf"}
    refused = {f.values.get("backend") for f in result.findings if f.kind == "parser_refused"}
    assert {"pinocchio-urdf", "yourdfpy", "mujoco-urdf"} <= refused
    assert {"shoulder", "elbow"} <= set(result.joint_names)
    assert {c.frame for c in result.checks if c.property == "fk.position"} >= {"upper_link", "lower_link"}


@pytest.mark.parametrize(
    "change, wanted",
    [
        (
            ("elbow", '<xyz expressed_in="__model__">0 1 0</xyz>', '<xyz expressed_in="__model__">1 0 0</xyz>'),
            ("axis_direction", "elbow"),
        ),
        (("lower_link", "<mass>1</mass>", "<mass>1.2</mass>"), ("mass_difference", "lower_link")),
    ],
)
def test_a_planted_difference_in_drakes_acrobot_sdf_is_named(tmp_path, change, wanted):
    element, old, new = change
    sdf = (ACROBOT / "Acrobot.sdf").read_text()
    at = sdf.index(f'name="{element}"')
    (tmp_path / "Acrobot.sdf").write_text(sdf[:at] + sdf[at:].replace(old, new, 1))
    result = verify_files(str(ACROBOT / "Acrobot.urdf"), str(tmp_path / "Acrobot.sdf"), FAST, kinds=("urdf", "sdf"))
    assert result.verdict == "fail" and wanted in errors(result), errors(result)
