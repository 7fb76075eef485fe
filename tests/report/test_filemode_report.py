"""The file-mode report: findings grouped by joint and link with both files' values side by
side, accepted findings greyed, and a pair whose MJCF turns the base shown overlaid and named on
the first screen."""

from __future__ import annotations

import html as htmllib
import json
import math
import re

import numpy as np
import pytest

from kinverify.cli import main
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import load_spec
from kinverify.report.html import render_html
from kinverify.report.skeleton import panels
from kinverify.results import VerifyResult
from kinverify.run import VerifyOptions, verify
from kinverify.backends import ModelSources
from tests.paths import MODELS
from tests.report import browser


def _text(fragment: str) -> str:
    return " ".join(htmllib.unescape(re.sub(r"<[^>]+>", "", fragment)).split())


@pytest.fixture(scope="module")
def small_result():
    return verify(ModelSources.from_spec(load_spec(MODELS / "arm3.toml")), VerifyOptions(samples=5, suites=["kinematics"]))


def test_findings_are_grouped_by_subject_with_values_side_by_side(small_result):
    data = small_result.to_dict()
    findings = [
        {
            "kind": "damping_difference",
            "severity": "error",
            "subject": f"j{i}",
            "subject_type": "joint",
            "message": f"joint j{i}: damping 0.003 in the URDF, 1 in the MJCF",
            "values": {"urdf": 0.003, "mjcf": 1.0},
        }
        for i in range(3)
    ]
    findings += [
        {"kind": "rounding", "severity": "info", "subject": "j0", "subject_type": "joint", "message": "quat rounded"},
        {
            "kind": "mass_difference",
            "severity": "error",
            "subject": "l2",
            "subject_type": "link",
            "accepted": True,
            "message": "link l2: mass 1 kg in the URDF, 1.5 kg in the MJCF",
            "values": {"urdf": 1.0, "mjcf": 1.5},
        },
        {
            "kind": "velocity_difference",
            "severity": "warning",
            "subject": "j3",
            "subject_type": "joint",
            "message": "velocity only in the URDF",
        },
    ]
    data["findings"] = findings
    data["notes"] = [f"{f['kind']}: {f['message']}" for f in findings] + ["URDF: meshes skipped", "a run note"]
    data["sections"]["filemode"] = {
        "title": "File mode: URDF vs MJCF",
        "summary": "",
        "figures": [],
        "notes": ["URDF: meshes skipped"],
        "tables": [
            {
                "title": "Findings",
                "columns": ["kind", "subject", "finding"],
                "rows": [[f["kind"], f["subject"], f["message"]] for f in findings],
            }
        ],
    }
    result = VerifyResult.from_dict(data)
    assert result.verdict == "fail" and len(result.failing_findings) == 3
    page = render_html(result)
    text = _text(page)
    assert "Findings: 3 error, 1 warning, 1 info, 1 accepted." in text
    for f in findings:
        assert text.count(f["message"]) == 1  # once, in its group; never repeated as a note
    assert text.count("URDF: meshes skipped") == 1 and "a run note" in text
    # the errors on the first screen, one group per joint; the others (here j0's info) in the file-mode section
    top = page[page.index('<section id="failures"') : page.index('<section id="matrix"')]
    groups = re.findall(r'<tbody class="group (\w+)">\s*<tr class="subject"><th colspan="5">([^<]*)</th>', top)
    assert groups == [("error", "joint j0"), ("error", "joint j1"), ("error", "joint j2")]
    assert "quat rounded" not in top and '<span class="sev info">' not in top
    row = next(r for r in top.split("<tr ") if "joint j1: damping" in r)
    assert re.findall(r'<td class="val"><div><code>([^<]*)</code></div></td>', row) == ["0.003", "1"]  # URDF, MJCF
    # the accepted finding is greyed, in the file-mode section, after the warning and j0's info
    rest = page[page.index('<section id="section-filemode">') :]
    others = re.findall(r'<tbody class="group (\w+)">\s*<tr class="subject"><th colspan="5">([^<]*)</th>', rest)
    assert others == [("warning", "joint j3"), ("info", "joint j0"), ("accepted", "link l2")]
    assert re.search(r'<tr class="accepted"><td><span class="sev accepted">accepted</span></td><td>mass_difference', rest)
    assert rest.index("velocity only in the URDF") < rest.index("link l2: mass 1 kg")


def _turned_pair(folder):
    """A generated UR5e pair whose MJCF mount body turns the arm by π about z."""
    spec = load_spec(MODELS / "ur5e.toml")
    urdf, mjcf = generate_urdf(spec), generate_mjcf(spec)
    turned = mjcf.replace('<body name="world_mount">', '<body name="world_mount" quat="0 0 0 1">', 1)
    assert turned != mjcf
    (folder / "ur5e.urdf").write_text(urdf)
    (folder / "ur5e.xml").write_text(turned)
    return folder / "ur5e.urdf", folder / "ur5e.xml"


@pytest.fixture(scope="module")
def turned(tmp_path_factory):
    folder = tmp_path_factory.mktemp("turned")
    urdf, mjcf = _turned_pair(folder)
    html, js = folder / "r.html", folder / "r.json"
    code = main(
        [
            "verify",
            "--urdf",
            str(urdf),
            "--mjcf",
            str(mjcf),
            "--samples",
            "10",
            "--quiet",
            "--report",
            str(html),
            "--json",
            str(js),
        ]
    )
    assert code == 1
    return html.read_text(encoding="utf-8"), VerifyResult.from_dict(json.loads(js.read_text()))


def test_turned_base_is_drawn_overlaid_and_named(turned):
    page, result = turned
    pictures = result.sections["pictures"].data
    assert pictures["other"] == "mujoco" and set(pictures["poses"]["worst"]) == {result.backends[0], "mujoco"}
    # the MJCF side arrives aligned (on the URDF side); the "as written" panel turns it back by π about z
    turn = np.diag([-1.0, -1.0, 1.0, 1.0])
    for key in ("home", "worst"):
        urdf_side = np.array(pictures["poses"][key][result.backends[0]])
        mjcf_side = np.array(pictures["poses"][key]["mujoco"])
        np.testing.assert_allclose(mjcf_side, urdf_side, atol=1e-9)
    alignment = np.array(result.sections["filemode"].data["alignment"]["T_mjcf_from_urdf"])
    np.testing.assert_allclose(alignment, turn, atol=1e-9)
    written = dict(panels(pictures, alignment.tolist()))["home pose, as written"]

    def origins(poses):
        return np.array([p for p in poses if p is not None])[:, :3, 3]

    np.testing.assert_allclose(origins(written["mujoco"]), origins(written[result.backends[0]]) * [-1, -1, 1], atol=1e-9)
    first_screen = _text(page[: page.index('<section id="matrix">')])
    assert "The MJCF's base is the URDF's turned by 180° about [0, 0, 1] (panels" in first_screen
    assert "pinocchio-urdf solid, mujoco ghosted over it" in first_screen
    assert '<figure class="plot answer-picture"><svg' in page


def test_alignment_draws_the_mjcf_side_back_onto_the_urdf_side(turned):
    """With the file-mode alignment in the section, a panel draws the MJCF as written (turned)
    and the others mapped back through the alignment (on top of the URDF)."""
    _, result = turned
    data = result.sections["pictures"].data
    t = np.diag([-1.0, -1.0, 1.0, 1.0])
    drawn = panels(data, t.tolist())
    assert [title for title, _ in drawn] == [
        "home pose, as written",
        "home pose, bases aligned",
        "worst configuration, bases aligned",
    ]
    ref = data["reference"]
    for title, poses in drawn:
        same = all(
            np.allclose(a, b, atol=1e-9)
            for a, b in zip(poses[ref], poses["mujoco"], strict=True)
            if a is not None and b is not None
        )
        assert same == ("aligned" in title)
    result.sections["filemode"].data["alignment"] = {"T_mjcf_from_urdf": t.tolist()}
    assert "panels &#34;as written&#34;" in render_html(result) or 'panels "as written"' in render_html(result)


@browser.needs_chromium
def test_turned_base_on_the_first_screen(turned, tmp_path):
    page, _ = turned
    layout, requests = browser.probe(page, tmp_path, [".answer-picture", ".answer-picture figcaption", "table.findings"])
    boxes = layout["boxes"]
    assert boxes[".answer-picture"]["bottom"] <= browser.HEIGHT and boxes[".answer-picture figcaption"]["top"] < browser.HEIGHT
    assert boxes["table.findings"]["top"] < browser.HEIGHT
    assert requests == []


def test_turn_is_described_in_plain_words():
    from kinverify.report.failures import describe_offset
    from kinverify.model.transforms import make_transform, rpy_to_matrix

    assert describe_offset(make_transform(rpy_to_matrix([0, 0, math.pi]), [0, 0, 0])) == "turned by 180° about [0, 0, 1]"
    assert describe_offset(make_transform(np.eye(3), [0.1, 0, 0])) == "moved by [0.1, 0, 0] m"
    both = describe_offset(make_transform(rpy_to_matrix([math.pi / 2, 0, 0]), [0, 0, 0.5]))
    assert both == "turned by 90° about [1, 0, 0] and moved by [0, 0, 0.5] m"


def test_checks_a_finding_explains_are_not_called_missed_goals(tmp_path):
    """A swapped inertia fails inertia.tensor; the inertia finding explains it: the page, the
    terminal verdict and JUnit call it explained, never a performance goal missed."""
    from junitparser import JUnitXml

    from tests.filemode.pairs import generated_pair, swapped_inertia

    urdf, mjcf = swapped_inertia(*generated_pair("panda"))
    (tmp_path / "p.urdf").write_text(urdf)
    (tmp_path / "p.xml").write_text(mjcf)
    out = {k: tmp_path / f"r.{k}" for k in ("html", "json", "xml")}
    code = main(
        [
            "verify",
            "--urdf",
            str(tmp_path / "p.urdf"),
            "--mjcf",
            str(tmp_path / "p.xml"),
            "--samples",
            "10",
            "--quiet",
            "--report",
            str(out["html"]),
            "--json",
            str(out["json"]),
            "--junit",
            str(out["xml"]),
        ]
    )
    assert code == 1
    result = VerifyResult.from_dict(json.loads(out["json"].read_text()))
    assert result.explained and not result.missed_goals and not result.failed
    assert {c.property for c in result.explained} >= {"inertia.tensor"}
    banner = _text(out["html"].read_text()[: out["html"].read_text().index('<section id="matrix">')])
    n = len(result.explained)
    assert f"{n} check{'s' if n != 1 else ''} differ" in banner and "performance goal" not in banner
    skipped = [
        case for suite in JUnitXml.fromfile(str(out["xml"])) for case in suite if case.result and case.result[0]._tag == "skipped"
    ]
    assert skipped and all("explained by a finding" in case.result[0].message for case in skipped)


def test_the_findings_table_heads_each_side_with_its_format():
    from types import SimpleNamespace

    from kinverify.report.html import side_labels

    assert side_labels(SimpleNamespace(model_info={"files": {"urdf": "a.urdf", "usd": "a.usda"}})) == ("URDF", "USD")
    assert side_labels(SimpleNamespace(model_info={"files": {"sdf": "a.sdf", "mjcf": "a.xml"}})) == ("SDF", "MJCF")
    assert side_labels(SimpleNamespace(model_info={})) == ("URDF", "MJCF")  # a spec: its generated URDF and MJCF
