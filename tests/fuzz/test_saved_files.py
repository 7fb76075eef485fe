"""Files kinverify wrote, read back after someone edited them: a results JSON (``kinverify
report``) or a baseline (``baseline check``) that does not validate is bad input (exit 2, one line
naming the field), never a report or a check that passes what it should not: a FAIL never
renders as PASS, a baseline with nothing left to compare never passes."""

from __future__ import annotations

import copy
import json

import pytest
from hypothesis import given, note
from hypothesis import strategies as st

from kinverify.cli import main
from tests.fuzz.harness import fuzz_settings, refused

OTHER_TYPES = [None, "x", 1.5, True, [], {}]


def _kind(value) -> str:
    return {bool: "boolean", int: "number", float: "number", str: "string", list: "array", dict: "object"}.get(
        type(value), "null"
    )


def _nodes(data, path=()):
    yield path
    children = data.items() if isinstance(data, dict) else enumerate(data) if isinstance(data, list) else ()
    for key, child in children:
        if not (isinstance(data, list) and key > 2):  # the first items of a list stand for the rest
            yield from _nodes(child, (*path, key))


def _strict(path: tuple, value) -> bool:
    """Is ``path`` a field the schema types exactly? The top level and every field of a check or a
    finding (a finding's ``values`` and a null ``magnitude`` are free; so are the sections, whose
    data the report mostly keeps as it is, and the model information)."""
    if path[0] in ("sections", "model_info", "versions"):
        return False
    if path[0] == "findings" and len(path) > 2 and path[2] == "values":
        return False
    return not (value is None and path[-1] == "magnitude")


@fuzz_settings(8)  # a report with pictures takes half a second to render
@given(st.sampled_from(["res.json", "fail.json"]), st.data())
def test_a_results_file_with_a_field_retyped_is_refused_and_a_fail_never_passes(capfd, work, name, data):
    saved = json.loads((work / name).read_text())
    expected = {"pass": 0, "fail": 1}[saved["verdict"]]
    path = data.draw(st.sampled_from([p for p in _nodes(saved) if p]))
    value = data.draw(st.sampled_from([v for v in OTHER_TYPES if _kind(v) != _kind(_get(saved, path))]))
    note(f"{'.'.join(map(str, path))} = {value!r}")
    edited = copy.deepcopy(saved)
    _set(edited, path, value)
    (work / "edited.json").write_text(json.dumps(edited))
    capfd.readouterr()
    code = main(["report", "edited.json", "--out", "out/r.html"])
    err = capfd.readouterr().err
    assert code in (2, expected), err  # never a crash, never another verdict (a FAIL never passes)
    if code == 2:
        assert err.count("\n") == 1 and err.startswith("kinverify: error: edited.json: "), err
    if _strict(path, value):
        assert code == 2 and "edited.json: not a valid kinverify results JSON" in err, err


def _get(data, path):
    for key in path:
        data = data[key]
    return data


def _set(data, path, value):
    _get(data, path[:-1])[path[-1]] = value


@pytest.mark.parametrize(
    "edit, words",
    [
        (lambda d: d.update(findings=[json.dumps(f) for f in d["findings"]]), "must be an object, got a string"),
        (
            lambda d: d["checks"][0].update(error=None),
            "checks[0]: Additional properties are not allowed ('error' was unexpected)",
        ),
        (lambda d: d["checks"][0].update(max_error=None), "checks[0].max_error must be a number, got null"),
        (lambda d: d.update(model=None), "model must be a string, got null"),
        (lambda d: d.update(schema_version="2"), "schema_version must be a whole number, got a string"),
        (lambda d: d.update(sections=list(d["sections"].values())), "sections must be an object, got an array"),
        (lambda d: d["checks"][0].update(tolerance="abc"), "checks[0].tolerance must be a number, got a string"),
        (lambda d: d.update(findings=[f for f in d["findings"] if f["severity"] != "error"]), "saved verdict is 'fail' but"),
        (lambda d: d.update(verdict="pass"), "saved verdict is 'pass' but its checks and findings give 'fail'"),
        (lambda d: d["findings"][0].update(severity="fine"), "findings[0].severity must be one of"),
    ],
)
def test_the_edits_that_turned_a_fail_into_a_pass_are_refused(capfd, work, edit, words):
    saved = json.loads((work / "fail.json").read_text())
    edit(saved)
    (work / "edited.json").write_text(json.dumps(saved))
    refused(capfd, ["report", "edited.json", "--out", "out/r.html"], work, "edited.json", words)


def _baseline(work, edit) -> None:
    data = json.loads((work / "b.json").read_text())
    edit(data)
    (work / "edited.json").write_text(json.dumps(data))


@pytest.mark.parametrize(
    "edit, words",
    [
        (lambda d: d.update(records=[]), "records of fk.position at base are missing (0 of"),
        (lambda d: d.update(records=[r for r in d["records"] if r["frame"] != "link2"]), "at link2 are missing"),
        (lambda d: d.update(frames=[], records=[]), "frames must be a non-empty list of names"),
        (lambda d: d.update(q=[[str(x) for x in row] for row in d["q"]]), "q must be a non-empty table of finite numbers"),
        (lambda d: d.update(q=[]), "q must be a non-empty table"),
        (lambda d: d["q"][1].__setitem__(0, float("nan")), "holds NaN, which is not a number this file may hold"),
        (lambda d: d["records"][3].update(value="0.5"), "records[3].value is not a finite number"),
        (lambda d: d["records"][3].update(value=[1e400]), "holds Infinity"),
        (lambda d: d["fixed"]["ik"]["targets"][0].update(start=["0"] * 3), "fixed.ik targets must hold finite numbers"),
        (lambda d: d.update(format_version=True), "format_version must be an integer"),
        (
            lambda d: d.update(
                frames=[f.replace("link2", "linkX") for f in d["frames"]],  # renamed, records and all
                records=[{**r, "frame": r["frame"].replace("link2", "linkX")} for r in d["records"]],
            ),
            "its frames differ from the model's (only in the baseline: linkX; only in the model: link2)",
        ),
    ],
)
def test_an_edited_baseline_is_refused_not_compared(capfd, work, edit, words):
    _baseline(work, edit)
    refused(capfd, ["baseline", "check", "m.toml", "--baseline", "edited.json"], work, "edited.json", words)


def test_check_refuses_an_emptied_baseline_beside_the_spec(capfd, work):
    (work / "baselines").mkdir()
    _baseline(work, lambda d: d.update(records=[]))
    (work / "edited.json").rename(work / "baselines" / "m.json")
    refused(capfd, ["check", "m.toml", "--samples", "0", "--suites", "kinematics"], work, "baselines/m.json", "missing")
