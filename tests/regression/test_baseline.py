"""Baselines: save, check, what moved and why; bad input; the `baseline` and `diff` commands."""

from __future__ import annotations

import json
import re
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings

from kinverify.regression import baseline as bl
from kinverify.regression import check as bl_check
from kinverify.regression import quantities as bl_q
from kinverify import load_spec, spec_from_dict
from kinverify.testing import strategies as kst
from kinverify.regression.check import check_baseline
from kinverify.cli import main
from kinverify.errors import InputError
from kinverify.pipeline.sampling import spec_samples
from kinverify.model.spec import Origin
from tests.paths import MODELS

ARM3 = MODELS / "arm3.toml"


def shift_joint(spec, index: int, dz: float):
    """``spec`` with joint ``index``'s origin moved by ``dz`` along z (a link length change)."""
    joints = list(spec.joints)
    o = joints[index].origin
    joints[index] = replace(joints[index], origin=Origin((o.xyz[0], o.xyz[1], o.xyz[2] + dz), o.rpy))
    return replace(spec, joints=tuple(joints))


def write_arm3_with_link2_longer(tmp_path: Path, dz: float = 0.001) -> Path:
    """A spec file: arm3 with link2 (joint3's origin) ``dz`` longer."""
    text = ARM3.read_text()
    old = "xyz = [0.0, 0.0, 0.25]   # link2_length"
    assert old in text
    path = tmp_path / "arm3.toml"
    path.write_text(text.replace(old, f"xyz = [0.0, 0.0, {0.25 + dz!r}]"))
    return path


@pytest.fixture(scope="module")
def arm3_baseline(tmp_path_factory) -> Path:
    return bl.save_baseline(load_spec(ARM3), tmp_path_factory.mktemp("bl") / "arm3.json", samples=10)


@pytest.mark.parametrize("name", sorted(p.stem for p in MODELS.glob("*.toml")))
def test_unchanged_shipped_models_pass(tmp_path, name):
    spec = load_spec(MODELS / f"{name}.toml")
    result = bl_check.check(spec, bl.save_baseline(spec, tmp_path / f"{name}.json", samples=5))
    assert result.passed and not result.moved and not result.spec_changed
    kinematics = 4 * len(spec.frame_names) * result.samples
    dynamics = 2 * spec.nq * result.samples  # mass-matrix row and gravity per coordinate
    ik = 0 if spec.floating else 2 * min(bl_q.IK_TARGETS, result.samples)
    assert result.compared == kinematics + dynamics + ik
    assert result.explanations == []


def test_a_1mm_longer_link_is_reported_at_the_right_frame_and_size(arm3_baseline):
    spec = shift_joint(load_spec(ARM3), 2, 0.001)  # joint3 sits at the end of link2
    result = bl_check.check(spec, arm3_baseline)
    assert not result.passed
    positions = [m for m in result.moved if m.property == "fk.position"]
    assert [m.frame for m in positions] == ["link3", "end_effector"]  # link2's own frame does not move
    for m in positions:
        assert m.delta == pytest.approx(1e-3, abs=1e-12)
        assert np.linalg.norm(np.subtract(m.new, m.old)) == pytest.approx(1e-3, abs=1e-12)
        assert m.count == m.of == result.samples
    (change,) = result.spec_changes
    assert (change.where, change.field) == ("joint joint3", "origin.xyz")
    assert change.delta == pytest.approx(1e-3, abs=1e-12)
    assert "joint joint3: origin.xyz" in result.explanations[0]


@settings(max_examples=25, deadline=None)
@given(kst.data())
def test_a_perturbation_moves_the_perturbed_frame_first(data):
    spec = data.draw(kst.arm_specs(max_joints=5))
    new = data.draw(kst.perturbed_specs(spec, 1e-3))
    result = check_baseline(new, bl.build_baseline(spec, samples=3))
    assert not result.passed and result.spec_changed
    (change,) = result.spec_changes
    kind, _, name = change.where.partition(" ")
    frame = {"base": spec.base_link.name, "tool": name}.get(kind) or next(j.link.name for j in spec.joints if j.name == name)
    kinematic = [m for m in result.moved if m.property.startswith(("fk.", "jacobian."))]
    first = min(kinematic, key=lambda m: list(spec.frame_names).index(m.frame))
    assert first.frame == frame
    if change.field.endswith("xyz"):  # the frame's origin moves by exactly the perturbation
        moved = next(m for m in result.moved if m.property == "fk.position" and m.frame == frame)
        assert moved.delta == pytest.approx(change.delta, rel=1e-6, abs=1e-12)


def test_only_library_versions_changed(arm3_baseline, tmp_path):
    data = json.loads(arm3_baseline.read_text())
    data["versions"]["mujoco"] = "0.0.1"
    result = check_baseline(load_spec(ARM3), data)
    assert result.passed
    assert result.version_changes["mujoco"][0] == "0.0.1"
    assert any(e.startswith("only library versions changed (mujoco 0.0.1 ->") for e in result.explanations)


def test_the_file_is_sorted_one_record_per_line_and_exact(arm3_baseline):
    text = arm3_baseline.read_text()
    data = json.loads(text)
    assert list(data) == sorted(data)
    spec = load_spec(ARM3)
    assert np.array_equal(np.array(data["q"]), spec_samples(spec, 10, 0))  # repr floats round-trip exactly
    record_lines = [line for line in text.splitlines() if line.lstrip().startswith('{"frame"')]
    kinematics = [r for r in data["records"] if r["property"].startswith(("fk.", "jacobian."))]
    assert len(record_lines) == len(data["records"]) and len(kinematics) == 4 * len(spec.frame_names) * len(data["q"])
    assert sorted(data["fixed"]) == ["ik"] and text.count('\n  "ik": {') == 1  # fixed inputs: one line each
    (ik_line,) = [line for line in text.splitlines() if line.startswith('  "ik": ')]
    assert ik_line.endswith("}") and json.loads(ik_line.removeprefix('  "ik": ')) == data["fixed"]["ik"]
    assert data["format_version"] == bl.FORMAT_VERSION and data["model"] == "arm3"
    assert set(data["fingerprints"]) == {"spec", "urdf", "mjcf"}


def test_a_new_quantity_plugs_in(monkeypatch, tmp_path):
    def reach(spec, q):
        from kinverify.model.kinematics import frame_poses

        d = np.linalg.norm(frame_poses(spec, q)[:, -1, :3, 3], axis=-1)
        return [
            {"property": "test.reach", "frame": spec.frame_names[-1], "sample": s, "value": float(v)} for s, v in enumerate(d)
        ]

    monkeypatch.setattr(bl, "QUANTITIES", bl.QUANTITIES + [bl.Quantity("reach", reach)])
    spec = load_spec(ARM3)
    path = bl.save_baseline(spec, tmp_path / "b.json", samples=4)
    assert "reach" in json.loads(path.read_text())["quantities"]
    result = bl_check.check(shift_joint(spec, 0, 0.002), path)
    moved = next(m for m in result.moved if m.property == "test.reach")
    assert moved.frame == "end_effector" and 0 < moved.delta <= 0.002 + 1e-12


def test_a_joint_count_change_fails_and_says_why(arm3_baseline):
    d = tomllib.loads(ARM3.read_text())
    d["joints"].append(
        {
            "name": "wrist",
            "xyz": [0, 0, 0.05],
            "axis": [0, 0, 1],
            "limits": {"lower": -1, "upper": 1, "unit": "rad"},
            "link": {"name": "link4"},
        }
    )
    result = bl_check.check(spec_from_dict(d), arm3_baseline)
    assert not result.passed and not result.comparable
    assert result.frames_added == ["link4"]
    assert any("joint count changed" in e for e in result.explanations)


@pytest.mark.parametrize(
    "content, message",
    [
        (lambda text: text[: len(text) // 2], "corrupt or truncated"),
        (lambda text: "{not json", "corrupt or truncated"),
        (lambda text: json.dumps({"hello": 1}), "not a kinverify baseline"),
        (lambda text: text.replace('"format_version": 2', '"format_version": 7'), "format version 7 is newer"),
        (lambda text: text.replace('"model": "arm3"', '"model": "ur5e"'), "for model 'ur5e', not 'arm3'"),
        (lambda text: text.replace('"sample": 3,', '"sample": 999,'), "records"),
        (lambda text: text.replace('"targets": [{"pose"', '"targets": [{"pos"'), "fixed.ik"),
        (lambda text: text.replace('"value": [0.0, 0.0, 0.42]', '"value": "oops"', 1), r"records\[0\].value"),
    ],
)
def test_bad_baselines_are_one_line_errors_and_nothing_is_overwritten(arm3_baseline, tmp_path, capsys, content, message):
    bad = tmp_path / "bad.json"
    bad.write_text(content(arm3_baseline.read_text()))
    before = bad.read_bytes()
    with pytest.raises(InputError, match=message):
        bl_check.check(load_spec(ARM3), bad)
    report = tmp_path / "report.html"
    report.write_text("previous report")
    assert main(["baseline", "check", str(ARM3), "--baseline", str(bad), "--report", str(report)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message.split()[0].replace("\\", "") in err and "Traceback" not in err
    assert main(["baseline", "save", str(ARM3), "--out", str(bad)]) == 2  # refuses to overwrite
    assert "refusing to overwrite" in capsys.readouterr().err
    assert bad.read_bytes() == before and report.read_text() == "previous report"


def test_cli_save_check_and_report(tmp_path, capsys):
    out = tmp_path / "arm3.json"
    assert main(["baseline", "save", str(ARM3), "--out", str(out), "--samples", "5"]) == 0
    assert main(["baseline", "check", str(ARM3), "--baseline", str(out)]) == 0
    assert "nothing moved beyond tolerance" in capsys.readouterr().out
    changed = write_arm3_with_link2_longer(tmp_path)
    report = tmp_path / "check.html"
    assert main(["baseline", "check", str(changed), "--baseline", str(out), "--report", str(report)]) == 1
    text = capsys.readouterr().out
    assert "link3" in text and "1.000e-03 m" in text and "joint joint3: origin.xyz" in text
    html = report.read_text()
    assert "FAIL" in html and "link3" in html and "joint joint3" in html
    # near the stretched-arm singularity a 1 mm longer link moves an IK solution by ~0.1 rad
    assert main(["baseline", "check", str(changed), "--baseline", str(out), "--tolerance", "0.01"]) == 1
    assert "ik.q" in capsys.readouterr().out
    assert main(["baseline", "check", str(changed), "--baseline", str(out), "--tolerance", "0.5"]) == 0


def test_cli_diff_two_specs(tmp_path, capsys):
    changed = write_arm3_with_link2_longer(tmp_path)
    report = tmp_path / "diff.html"
    assert main(["diff", str(ARM3), str(changed), "--samples", "20", "--report", str(report)]) == 1
    out = capsys.readouterr().out
    assert "joint joint3" in out and "origin.xyz" in out and "CHANGED" in out
    assert "+0.001000" in out  # the end effector reaches 1 mm further
    html = report.read_text()
    assert "workspace reach" in html and "<script" not in html
    assert main(["diff", str(ARM3), str(ARM3), "--samples", "5", "--report", str(tmp_path / "same.html")]) == 0
    assert "IDENTICAL" in capsys.readouterr().out
    assert main(["diff", str(ARM3), str(tmp_path / "arm.urdf")]) == 2
    assert "is a spec and" in capsys.readouterr().err


def test_diff_of_the_same_change_in_python():
    from kinverify.regression.modeldiff import diff_models

    spec = load_spec(ARM3)
    d = diff_models(spec, shift_joint(spec, 2, 0.001), samples=10)
    moved = {f.frame: f for f in d.frames if f.position > 0}
    assert set(moved) == {"link3", "end_effector"}
    assert moved["link3"].position == pytest.approx(1e-3, abs=1e-12)
    (reach,) = d.reach
    assert reach.change == pytest.approx(1e-3, abs=1e-9)


def test_html_is_escaped(tmp_path):
    from kinverify.report.regression import render_document_html

    doc = {
        "title": "<script>x</script>",
        "passed": False,
        "verdict": "FAIL",
        "summary": ["a<b"],
        "notes": [],
        "tables": [{"title": "t", "columns": ["c"], "rows": [["<img>"]]}],
    }
    html = render_document_html(doc)
    assert "<script>x" not in html and "&lt;script&gt;" in html and "&lt;img&gt;" in html


def scale_link_mass(spec, index: int, factor: float):
    """``spec`` with joint ``index``'s child link ``factor`` times heavier (same CoM and inertia)."""
    joints = list(spec.joints)
    link = joints[index].link
    joints[index] = replace(joints[index], link=replace(link, inertial=replace(link.inertial, mass=link.inertial.mass * factor)))
    return replace(spec, joints=tuple(joints))


def test_a_20_percent_heavier_link_moves_dynamics_only(arm3_baseline):
    from kinverify.tracking.models import PinocchioDynamics
    from kinverify.generate import generate_urdf

    spec = load_spec(ARM3)
    heavy = scale_link_mass(spec, 1, 1.2)  # link2, carried by joint2
    result = bl_check.check(heavy, arm3_baseline)
    assert not result.passed
    assert {m.property.split(".")[0] for m in result.moved} == {"dynamics"}  # kinematics and IK unchanged
    (change,) = result.spec_changes
    assert (change.where, change.field) == ("link link2", "inertial.mass")
    assert change.delta == pytest.approx(0.2 * spec.joints[1].link.inertial.mass, rel=1e-12)
    gravity = {m.frame: m for m in result.moved if m.property == "dynamics.gravity"}
    assert "joint2" in gravity and "joint1" not in gravity  # joint1's axis is vertical: no gravity torque
    # the reported delta is the gravity torque change recomputed independently at that configuration
    m = gravity["joint2"]
    torques = [PinocchioDynamics(generate_urdf(s), s.joint_names, [0.0] * s.dof).gravity(np.array(m.q)) for s in (spec, heavy)]
    assert m.old == pytest.approx(torques[0][1], abs=1e-12) and m.new == pytest.approx(torques[1][1], abs=1e-12)
    assert m.delta == pytest.approx(abs(torques[1][1] - torques[0][1]), abs=1e-12) and m.unit == "N·m"
    assert any(m.property == "dynamics.mass_matrix" and m.frame == "joint2" for m in result.moved)


@settings(max_examples=10, deadline=None)
@given(kst.arm_specs(max_joints=6))
def test_ik_targets_are_stable_for_an_unchanged_model(spec):
    data = bl.build_baseline(spec, samples=3)
    again = json.loads(bl.dumps_baseline(bl.build_baseline(spec, samples=3)))
    assert again["fixed"] == json.loads(bl.dumps_baseline(data))["fixed"]
    ik = [r for r in data["records"] if r["property"] == "ik.q"]
    assert len(ik) == min(bl_q.IK_TARGETS, len(data["q"]))
    result = check_baseline(spec, json.loads(bl.dumps_baseline(data)))
    assert result.passed and not result.missing_quantities


def test_ik_solutions_move_when_a_link_grows(arm3_baseline):
    spec = shift_joint(load_spec(ARM3), 2, 0.001)
    result = bl_check.check(spec, arm3_baseline)
    data = json.loads(arm3_baseline.read_text())
    targets = data["fixed"]["ik"]["targets"]
    moved = next(m for m in result.moved if m.property == "ik.q")
    assert moved.frame == "end_effector" and 0 < moved.delta < 0.1  # a nearby solution, not another branch
    # the new solution reaches the stored target with the changed arm
    from kinverify.model.kinematics import frame_poses

    target = next(t for t in targets if t["sample"] == moved.sample)
    reached = frame_poses(spec, np.array([moved.new]))[0, spec.frame_names.index("end_effector"), :3, 3]
    assert np.linalg.norm(reached - np.array(target["pose"])[:3, 3]) < 1e-9


def test_a_format_1_baseline_is_still_checked(arm3_baseline):
    data = json.loads(arm3_baseline.read_text())
    data["format_version"], data["quantities"] = 1, ["kinematics"]
    del data["fixed"]
    data["records"] = [r for r in data["records"] if r["property"].startswith(("fk.", "jacobian."))]
    old = tmp = arm3_baseline.with_name("v1.json")
    tmp.write_text(bl.dumps_baseline(data))
    result = bl_check.check(load_spec(ARM3), old)
    assert result.passed and result.compared == len(data["records"])
    assert result.missing_quantities == ["ik", "dynamics"]
    assert any("no ik, dynamics records" in e for e in result.explanations)
    moved = bl_check.check(shift_joint(load_spec(ARM3), 2, 0.001), old)
    assert {m.frame for m in moved.moved if m.property == "fk.position"} == {"link3", "end_effector"}


@pytest.mark.parametrize("section", sorted(bl.SCHEMA[2]))
def test_a_baseline_missing_a_section_is_refused(arm3_baseline, tmp_path, capsys, section):
    data = json.loads(arm3_baseline.read_text())
    del data[section]
    bad = tmp_path / "bad.json"
    bad.write_text(bl.dumps_baseline(data))
    assert main(["baseline", "check", str(ARM3), "--baseline", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err == f"kinverify: error: {bad}: malformed baseline: missing {section}\n"


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda d: d.update(fixed={}), "fixed.ik is missing (the ik inputs the baseline was saved with)"),
        (lambda d: d.update(seed=True), "seed must be a whole number, got bool"),
        (lambda d: d.update(records={}), "records must be a list, got dict"),
        (lambda d: d.update(quantities=[1]), "quantities must be a list of names"),
    ],
)
def test_a_retyped_or_emptied_section_is_refused(arm3_baseline, tmp_path, edit, message):
    data = json.loads(arm3_baseline.read_text())
    edit(data)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(data))
    with pytest.raises(InputError, match=re.escape(message)):
        bl.read_baseline(bad)


def test_a_quantity_that_became_nan_has_moved():
    """NaN compares false with everything: ``delta > tol`` would call it unmoved."""
    old = [
        {"property": "fk.position", "frame": "link3", "sample": 0, "value": [0.0, 0.0, 1.0]},
        {"property": "fk.position", "frame": "link3", "sample": 1, "value": [0.0, 0.0, 1.0]},
    ]
    new = [dict(old[0], value=[float("nan"), 0.0, 1.0]), dict(old[1])]
    moved, compared = bl_check.compare_records(old, new, np.zeros((2, 3)), ["link3"], {"fk.position": bl.Tolerance(1e-9, "m")})
    (m,) = moved
    assert compared == 2 and (m.property, m.frame, m.sample, m.count, m.of) == ("fk.position", "link3", 0, 1, 2)
    assert np.isnan(m.delta)


def test_a_frame_the_model_no_longer_has_fails_the_check(arm3_baseline):
    spec = load_spec(ARM3)
    result = bl_check.check(replace(spec, tools=()), arm3_baseline)
    assert result.frames_removed == ["end_effector"] and result.frames_added == []
    assert not result.passed and not result.moved  # what is left agrees; the frame's absence fails alone
    assert bl_check.check(spec, arm3_baseline).passed


@pytest.mark.parametrize("model, position_only", [("ur5e", False), ("arm3", True)])
def test_ik_targets_keep_their_orientation_when_the_arm_has_six_joints(model, position_only):
    spec = load_spec(MODELS / f"{model}.toml")
    q = spec_samples(spec, 4, seed=0)
    fixed = bl_q.ik_fixed(spec, q)
    assert fixed["position_only"] is position_only and len(fixed["targets"]) == min(len(q), bl_q.IK_TARGETS)
    assert np.array(fixed["targets"][0]["pose"]).shape == (4, 4)


def test_save_time_inputs_default_to_the_ones_made_now():
    spec = load_spec(ARM3)
    q = spec_samples(spec, 1, seed=0)[-3:]
    assert bl.compute_records(spec, q) == bl.compute_records(spec, q, bl.prepare_fixed(spec, q))


def test_a_negative_sample_count_is_refused():
    with pytest.raises(InputError, match=r"^--samples must be >= 0, got -1$"):
        bl.build_baseline(load_spec(ARM3), samples=-1)


def test_read_errors_name_the_file(arm3_baseline, tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text(arm3_baseline.read_text().replace('"format_version": 2', '"format_version": "2"'))
    with pytest.raises(
        InputError, match=f"^{re.escape(str(bad))}: malformed baseline: format_version must be an integer, got '2'$"
    ):
        bl.read_baseline(bad)
    bad.write_text(arm3_baseline.read_text().replace('"value": [0.0, 0.0, 0.42]', '"value": [NaN, 0.0, 0.42]', 1))
    with pytest.raises(InputError, match=f"^--baseline: {re.escape(str(bad))} holds NaN, which is not a number"):
        bl.read_baseline(bad)


def test_a_one_sample_baseline_missing_a_frames_records_is_refused(arm3_baseline, tmp_path):
    data = json.loads(arm3_baseline.read_text())
    data["q"], data["fixed"]["ik"]["targets"] = data["q"][:1], []
    data["records"] = [r for r in data["records"] if r["sample"] == 0 and r["frame"] != "link2"]
    bad = tmp_path / "bad.json"
    text = bl.dumps_baseline(data)
    assert '\n "fixed": {\n  "ik": {"frame": "end_effector", "position_only": true, "targets": []}\n }' in text
    bad.write_text(text)
    with pytest.raises(InputError, match=re.escape("records of fk.position at link2 are missing (0 of 1 samples)")):
        bl.read_baseline(bad)
