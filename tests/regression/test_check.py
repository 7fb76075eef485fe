"""The baseline comparison: what moved (beyond the property's tolerance, NaN included), the worst
sample per property and frame, how many samples moved, the order of the report, whether the check
passes (removed or added frames fail it) and the explanations. Pinned on hand-made records."""

from __future__ import annotations

import copy

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from kinverify import load_spec
from kinverify.errors import InputError
from kinverify.model.canonical import spec_to_canonical
from kinverify.regression.baseline import (
    FORMAT,
    FORMAT_VERSION,
    Tolerance,
    compute_records,
    dumps_baseline,
    fingerprints,
    prepare_fixed,
)
from kinverify.regression.check import BaselineCheck, Moved, check_baseline, compare_records
from kinverify.regression.check import check as check_path
from kinverify.regression.specdiff import ParamChange, diff_specs
from kinverify.versions import library_versions

TOL = {"fk.position": Tolerance(1e-6, "m"), "jacobian.linear": Tolerance(1e-5, "m/rad")}
Q = np.array([[0.0, 0.1], [1.0, 1.1], [2.0, 2.1]])


def rec(prop: str, frame: str, sample: int, value) -> dict:
    return {"property": prop, "frame": frame, "sample": sample, "value": value}


def test_moved_beyond_the_tolerance_the_worst_sample_and_the_count():
    old = [rec("fk.position", "l1", s, [0.0, 0.0, 0.0]) for s in range(3)]
    new = [
        rec("fk.position", "l1", 0, [1e-6, 0.0, 0.0]),  # exactly the tolerance: not moved
        rec("fk.position", "l1", 1, [0.0, 3e-6, 0.0]),
        rec("fk.position", "l1", 2, [0.0, 0.0, 2e-6]),
    ]
    moved, compared = compare_records(old, new, Q, ["l1"], TOL)
    assert compared == 3
    assert moved == [Moved("fk.position", "l1", 1, (1.0, 1.1), [0.0, 0.0, 0.0], [0.0, 3e-6, 0.0], 3e-6, 1e-6, "m", 2, 3)]


def test_a_value_that_became_nan_moved_and_a_record_missing_now_is_not_compared():
    old = [rec("fk.position", "l2", 0, [0.0]), rec("fk.position", "l1", 0, [0.0]), rec("fk.position", "l1", 1, [0.0])]
    new = [rec("fk.position", "l1", 0, [math.nan]), rec("fk.position", "l1", 1, [5.0]), rec("fk.position", "l2", 1, [0.0])]
    moved, compared = compare_records(old, new, Q, ["l1", "l2"], TOL)
    assert compared == 2
    (m,) = moved
    assert (m.frame, m.sample, m.count, m.of) == ("l1", 0, 2, 2) and math.isnan(m.delta)  # NaN moved, counted
    moved, _ = compare_records(old[1:2], new[:1], Q, ["l1"], TOL)
    assert len(moved) == 1 and math.isnan(moved[0].delta) and (moved[0].count, moved[0].of) == (1, 1)


def test_a_property_without_a_tolerance_has_the_fallback_and_the_report_order():
    old = [rec(p, f, 0, [0.0]) for p in ("other", "jacobian.linear", "fk.position") for f in ("l2", "j1", "l1")]
    new = [
        rec(p, f, 0, [2e-9]) if p == "other" else rec(p, f, 0, [1.0])
        for p in ("other", "jacobian.linear", "fk.position")
        for f in ("l2", "j1", "l1")
    ]
    moved, compared = compare_records(old, new, Q, ["l1", "l2"], TOL)
    assert compared == 9
    assert [(m.property, m.frame) for m in moved] == [  # tolerances' order, then the frames' (others last)
        ("fk.position", "l1"),
        ("fk.position", "l2"),
        ("fk.position", "j1"),
        ("jacobian.linear", "l1"),
        ("jacobian.linear", "l2"),
        ("jacobian.linear", "j1"),
        ("other", "l1"),
        ("other", "l2"),
        ("other", "j1"),
    ]
    assert (moved[-1].tolerance, moved[-1].unit, moved[-1].delta) == (1e-9, "", 2e-9)
    assert [(m.property, m.frame) for m in compare_records(old[:2], new[:2], Q, ["l2", "j1"], TOL)[0]] == [
        ("other", "l2"),
        ("other", "j1"),
    ]
    ties = compare_records(
        [rec("z", "l1", 0, [0.0]), rec("a", "l1", 0, [0.0])], [rec("z", "l1", 0, [1.0]), rec("a", "l1", 0, [1.0])], Q, ["l1"], TOL
    )[0]
    assert [m.property for m in ties] == ["a", "z"]  # neither has a tolerance: by name


def test_a_rotation_moved_by_its_geodesic_angle():
    c, s = math.cos(0.1), math.sin(0.1)
    old = [rec("fk.rotation", "l1", 0, np.eye(3).tolist())]
    new = [rec("fk.rotation", "l1", 0, [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])]
    (m,) = compare_records(old, new, Q, ["l1"], {"fk.rotation": Tolerance(1e-5, "rad")})[0]
    assert m.delta == pytest.approx(0.1, abs=1e-12) and m.unit == "rad"


def test_the_first_worst_sample_kept_on_a_tie():
    old = [rec("fk.position", "l1", s, [0.0]) for s in (2, 0)]
    new = [rec("fk.position", "l1", s, [1.0]) for s in (2, 0)]
    (m,) = compare_records(old, new, Q, ["l1"], TOL)[0]
    assert (m.sample, m.q) == (2, (2.0, 2.1))


def check(moved=(), **kwargs) -> BaselineCheck:
    return BaselineCheck("arm3", "b.json", 3, list(moved), **kwargs)


MOVED = Moved("fk.position", "l1", 1, (1.0, 1.1), [0.0], [1.0], 1.0, 1e-6, "m", 1, 3)


def test_passed_only_when_comparable_nothing_moved_and_no_frame_added_or_removed():
    assert check().passed is True
    assert check(moved=[MOVED]).passed is False
    assert check(frames_removed=["tool"]).passed is False
    assert check(frames_added=["tool"]).passed is False
    assert check(comparable=False).passed is False
    b = BaselineCheck("arm3", "b.json", 3, [MOVED])
    assert b.passed is False


CHANGE = ParamChange("joint joint2", "origin.xyz", "changed", [0, 0, 0.1], [0, 0, 0.101], 0.001)


def test_explanations():
    versions = {"mujoco": ("3.1", "3.2"), "pin": ("2", "3")}
    assert check().explanations == []
    assert check(moved=[MOVED]).explanations == ["neither the spec nor the library versions changed"]
    assert check(spec_changed=True, spec_changes=[CHANGE], version_changes=versions).explanations == [
        f"the spec changed: {CHANGE.describe()}",
        "library versions also changed: mujoco 3.1 -> 3.2, pin 2 -> 3",
    ]
    assert check(spec_changed=True).explanations == ["the spec changed: no parameter differs by more than 1e-12"]
    assert check(files_changed=["urdf", "mjcf"], moved=[MOVED]).explanations == [
        "the spec is unchanged but the generated URDF AND MJCF changed (a different kinverify generator)",
        "neither the spec nor the library versions changed",
    ]
    assert check(version_changes={"pin": ("2", "3")}).explanations == [
        "only library versions changed (pin 2 -> 3); nothing moved"
    ]
    assert check(version_changes={"pin": ("2", "3")}, frames_removed=["t"]).explanations == [
        "the spec is unchanged; library versions changed (pin 2 -> 3): they explain the movement"
    ]
    assert check(missing_quantities=["ik", "dynamics"], comparable=False).explanations == [
        "neither the spec nor the library versions changed",
        "the baseline has no ik, dynamics records (an older format or kinverify); they were not compared: save a new "
        "baseline to include them",
        "the joint count changed, so the baseline's configurations cannot be re-evaluated; save a new baseline",
    ]


def test_to_dict():
    assert MOVED.to_dict() == {
        "property": "fk.position",
        "frame": "l1",
        "sample": 1,
        "q": [1.0, 1.1],
        "old": [0.0],
        "new": [1.0],
        "delta": 1.0,
        "tolerance": 1e-6,
        "unit": "m",
        "count": 1,
        "of": 3,
    }
    b = check(
        moved=[MOVED],
        frames_added=["a"],
        frames_removed=["r"],
        spec_changed=True,
        spec_changes=[CHANGE],
        files_changed=["urdf"],
        version_changes={"pin": ("2", "3")},
        comparable=True,
        compared=7,
        missing_quantities=["ik"],
    )
    assert b.to_dict() == {
        "model": "arm3",
        "source": "b.json",
        "passed": False,
        "samples": 3,
        "compared": 7,
        "moved": [MOVED.to_dict()],
        "frames_added": ["a"],
        "frames_removed": ["r"],
        "spec_changed": True,
        "spec_changes": [CHANGE.to_dict()],
        "files_changed": ["urdf"],
        "comparable": True,
        "missing_quantities": ["ik"],
        "version_changes": {"pin": ["2", "3"]},
        "explanations": b.explanations,
    }
    assert check().to_dict()["passed"] is True and check().to_dict()["comparable"] is True


ARM3 = Path(__file__).resolve().parents[2] / "models" / "arm3.toml"


@pytest.fixture(scope="module")
def arm3():
    """arm3, one configuration, and a baseline of it made by hand (kinematics and dynamics records)."""
    spec = load_spec(ARM3)
    q = np.array([[0.1, -0.2, 0.3]])
    fixed = prepare_fixed(spec, q)
    data = {
        "format": FORMAT,
        "format_version": FORMAT_VERSION,
        "model": spec.name,
        "seed": 0,
        "samples": 1,
        "joint_names": list(spec.coordinate_names),
        "q": q.tolist(),
        "frames": list(spec.frame_names),
        "spec": spec_to_canonical(spec),
        "fingerprints": fingerprints(spec),
        "versions": library_versions(),
        "quantities": ["kinematics", "ik", "dynamics"],
        "records": compute_records(spec, q, fixed),
        "fixed": fixed,
    }
    return spec, data


def test_check_baseline_of_the_unchanged_model_passes(arm3):
    spec, data = arm3
    result = check_baseline(spec, data, source="b.json")
    assert (result.passed, result.moved, result.compared, result.samples) == (True, [], len(data["records"]), 1)
    assert (result.model, result.source, result.spec_changed, result.files_changed, result.version_changes) == (
        spec.name,
        "b.json",
        False,
        [],
        {},
    )
    assert (result.frames_added, result.frames_removed, result.missing_quantities) == ([], [], [])
    assert {r["property"] for r in data["records"]} >= {"ik.q", "ik.error", "dynamics.gravity"}  # all compared
    assert check_baseline(spec, data).source == ""


def test_check_reads_the_file(arm3, tmp_path):
    spec, data = arm3
    path = tmp_path / "b.json"
    path.write_text(dumps_baseline(data))
    result = check_path(spec, path)
    assert (result.passed, result.compared, result.source) == (True, len(data["records"]), str(path))
    moved = check_path(spec, path, {"fk.position": Tolerance(-1.0, "m")})
    assert {m.property for m in moved.moved} == {"fk.position"}  # the tolerances given, the fallback for the rest
    assert check_path(spec, path, {}).passed is True  # no tolerances: the defaults


def test_check_baseline_of_configurations_stored_as_integers(arm3):
    spec, data = arm3
    q = np.zeros((1, 3))
    records = [dict(r) for r in compute_records(spec, q, {})]
    records[0]["value"] = np.add(records[0]["value"], 1.0).tolist()
    result = check_baseline(spec, {**data, "q": [[0, 0, 0]], "fixed": {}, "records": records})
    assert all(type(v) is float for m in result.moved for v in m.q) and result.moved[0].q == (0.0, 0.0, 0.0)


def test_moved_joints_in_the_order_of_the_model(arm3):
    spec, data = arm3
    gravity = [dict(r) for r in data["records"] if r["property"] == "dynamics.gravity"][::-1]
    for r in gravity:
        r["value"] += 1.0
    result = check_baseline(spec, {**data, "records": gravity})
    assert [m.frame for m in result.moved] == ["joint1", "joint2", "joint3"]


def test_the_stored_fingerprint_decides_first_and_a_malformed_stored_spec_is_named(arm3):
    spec, data = arm3
    other = {**data["spec"], "name": "renamed"}
    assert check_baseline(spec, {**data, "spec": other}).spec_changed is False  # same fingerprint: unchanged
    with pytest.raises(InputError) as err:
        check_baseline(spec, {**data, "spec": {}, "fingerprints": {}}, source="b.json")
    assert str(err.value) == "b.json: spec: malformed stored spec (KeyError: 'joints')"


def test_check_baseline_moved_frames_and_versions(arm3):
    spec, data = arm3
    records = [dict(r) for r in data["records"]]
    first = next(r for r in records if r["property"] == "fk.position" and r["frame"] == spec.frame_names[-1])
    first["value"] = [v + 1e-3 for v in first["value"]]
    versions = {**data["versions"], "numpy": "0.0", "gone": "1"}
    # the stored spec differs too (joint1's damping): other frames with the very same spec are bad input
    stored = copy.deepcopy(data["spec"])
    stored["joints"][0]["damping"] += 0.1
    changed = {
        **data,
        "records": records,
        "frames": [*data["frames"][:-1], "removed_frame"],
        "versions": versions,
        "quantities": None,
        "spec": stored,
        "fingerprints": {**data["fingerprints"], "urdf": "x", "spec": "x"},
    }
    result = check_baseline(spec, changed, {"fk.position": Tolerance(1e-6, "m")})
    (m,) = [m for m in result.moved if m.property == "fk.position"]
    assert (m.frame, m.sample, m.count, m.of, m.tolerance) == (spec.frame_names[-1], 0, 1, 1, 1e-6)
    assert m.delta == pytest.approx(math.sqrt(3) * 1e-3)
    assert (result.frames_removed, result.frames_added) == (["removed_frame"], [spec.frame_names[-1]])
    assert result.version_changes == {"gone": ("1", "None"), "numpy": ("0.0", data["versions"]["numpy"])}
    assert (result.files_changed, result.missing_quantities, result.passed) == (["urdf"], ["ik", "dynamics"], False)
    assert all(m.tolerance == 1e-9 for m in result.moved if m.property != "fk.position")  # the fallback


def test_check_baseline_of_a_changed_spec_names_the_change(arm3):
    spec, data = arm3
    j = spec.joints[2]
    origin = replace(j.origin, xyz=tuple(np.add(j.origin.xyz, (0.0, 0.0, 1e-3))))
    longer = replace(spec, joints=[*spec.joints[:2], replace(j, origin=origin)])
    result = check_baseline(longer, data, source="b.json")
    assert result.spec_changed and not result.passed and result.files_changed == ["urdf", "mjcf"]
    assert [c.describe() for c in result.spec_changes] == [c.describe() for c in diff_specs(spec, longer)]
    assert result.spec_changes and result.moved
    same = check_baseline(spec, {**data, "fingerprints": None})  # no stored fingerprints: the spec itself compared
    assert (same.spec_changed, same.files_changed, same.passed) == (False, ["urdf", "mjcf"], True)


def test_check_baseline_joint_count_changed_or_nothing_compared(arm3):
    spec, data = arm3
    result = check_baseline(spec, {**data, "q": [[0.1, 0.2]], "records": []}, source="b.json")
    assert (result.comparable, result.passed, result.compared, result.moved) == (False, False, 0, [])
    with pytest.raises(InputError) as err:
        check_baseline(spec, {**data, "records": [rec("fk.position", "nowhere", 0, [0.0])]}, source="b.json")
    assert str(err.value) == (
        "b.json: no record of the baseline matches what the model computes: nothing was compared (save the baseline again)"
    )
    with pytest.raises(InputError, match="only in the baseline: gone; only in the model: none"):  # the same spec, other frames
        check_baseline(spec, {**data, "records": [], "frames": [*data["frames"], "gone"]})


def test_ik_solved_for_the_stored_targets_not_new_ones(arm3):
    spec, data = arm3
    ik = [r for r in data["records"] if r["property"].startswith("ik.")]
    result = check_baseline(spec, {**data, "q": [[0.0, 0.0, 0.0]], "records": ik})  # targets stay where they were saved
    assert (result.passed, result.compared) == (True, len(ik)) and ik


def test_check_refuses_a_baseline_of_another_model(arm3, tmp_path):
    spec, data = arm3
    path = tmp_path / "b.json"
    path.write_text(dumps_baseline({**data, "model": "other"}))
    with pytest.raises(InputError, match="other"):
        check_path(spec, path)
