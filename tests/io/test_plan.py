"""The outputs a run may write: a target that is a directory or not a regular file is refused, an
output that is an input (also when the input is read later) or another output is refused naming
both, a path is written once, the outputs are renamed together (a failure says how many were
already replaced), and a default output name is reduced to a plain file name."""

from __future__ import annotations

import re

import pytest

from kinverify.errors import InputError
from kinverify.io.plan import OutputPlan, check_target, claim_outputs, default_output, output_plan


def refused(call, *args) -> str:
    with pytest.raises(InputError) as err:
        call(*args)
    return str(err.value)


def test_a_target_must_be_a_regular_file_or_absent(tmp_path):
    assert check_target(tmp_path / "new.json") == (tmp_path / "new.json").resolve()
    (tmp_path / "old.json").write_text("{}")
    assert check_target(tmp_path / "old.json", "--json") == (tmp_path / "old.json").resolve()
    message = refused(check_target, tmp_path, "--json")
    assert message == f"--json {tmp_path} is a directory, not a regular file: refusing to write there (give a file path)"


def test_two_outputs_naming_one_file_are_refused_with_both_labels(tmp_path):
    out = tmp_path / "r.json"
    message = refused(claim_outputs, ("--json", out), ("--report", out))
    assert message == f"--report {out} and --json {out} name the same file: give each output its own path"
    assert claim_outputs(("--json", out), ("--json", out)) == [out.resolve(), out.resolve()]


def test_an_output_that_is_an_input_is_refused_whichever_comes_first(tmp_path):
    model = tmp_path / "m.urdf"
    model.write_text("<robot/>")
    plan = OutputPlan()
    plan.add_input(model, "--urdf")
    expected = f"--json {model} is --urdf {model}, an input of this run: refusing to overwrite it (choose another output path)"
    assert refused(plan.claim, model, "--json") == expected
    later = OutputPlan()
    later.claim(model, "--json")
    assert refused(later.add_input, model, "--urdf") == expected


def test_a_path_is_written_once_per_run(tmp_path):
    plan = OutputPlan()
    out = tmp_path / "r.json"
    assert plan.before_write(out) == out.resolve()
    assert refused(plan.before_write, out) == (
        f"{out}: written twice in one run (two outputs name the same file): give each output its own path"
    )


def test_the_outputs_are_renamed_together_and_a_failure_says_how_many_were(tmp_path):
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    with output_plan(outputs=[("--json", a), ("--report", b)]) as plan:
        for target in (a, b):
            tmp = tmp_path / f".{target.name}.tmp"
            tmp.write_text(target.name)
            plan.stage(str(tmp), target)
    assert (a.read_text(), b.read_text()) == ("a.json", "b.json")
    plan = OutputPlan()
    (tmp_path / "ta").write_text("new a")
    plan.stage(str(tmp_path / "ta"), a)
    plan.stage(str(tmp_path / "missing"), b)
    message = refused(plan.commit)
    assert message == f"{b}: cannot write: No such file or directory; 1 other output(s) were already replaced"
    plan.stage(str(tmp_path / "missing"), a)
    assert refused(plan.commit).endswith("; nothing was replaced")


def test_a_default_output_name_is_a_plain_file_name():
    assert default_output("arm3", ".json") == "reports/arm3.json"
    assert default_output("../../etc/x y", ".html", "out") == "out/_.._etc_x_y.html"
    assert default_output("...", ".json") == "reports/model.json"
    assert re.fullmatch(r"reports/a{120}\.json", default_output("a" * 300, ".json"))
