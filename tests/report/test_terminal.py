"""Terminal output at 80 and 200 columns, printed from results and by the real CLI in a
pseudo-terminal and to a log: every line fits, no row wraps, no number or name is cut, the labels
say what the numbers are; findings wrap under their text; ``kinverify track``'s table; the
progress every long suite reports; ``--quiet``."""

from __future__ import annotations

import dataclasses
import itertools
import re

import pytest
from rich.console import Console

from kinverify.backends import ModelSources, backend_info
from kinverify.cli import main
from kinverify.model.specfile import load_spec
from kinverify.report.json_ import load_result_json
from kinverify.report.progress import UNITS, VerifyProgress
from kinverify.report.terminal import compact, display_unit, fit_table, print_result, track_table
from kinverify.results import VerifyResult
from kinverify.run import VerifyOptions, verify
from kinverify.suites.base import Finding, value_check
from kinverify.suites.registry import get_property
from tests.paths import MODELS
from tests.report.flipped import FLIPPED, flipped_backend
from tests.report.terminal_checks import assert_fits, render, run_in_terminal, run_to_file

WIDTHS = (80, 200)


@pytest.fixture(scope="module")
def failing():
    """Kinematics, IK and dynamics with one backend whose joint2 axis is flipped, and tracking
    checks as the tracking suite makes them (one below its goal)."""
    sources = ModelSources.from_spec(load_spec(MODELS / "arm3.toml"))
    opts = VerifyOptions(samples=10, suites=["kinematics", "ik", "dynamics"], extra={"ik_targets": 5})
    result = verify(sources, opts, extra_backends=[flipped_backend(sources, "joint2")])
    result.checks.append(
        value_check(
            get_property("tracking.computed-torque"), None, "end_effector", ("plan", "mujoco"), 3.5e-5, samples=4001, unit="rad"
        )
    )
    result.checks.append(
        value_check(
            get_property("tracking.pd+gravity"),
            None,
            "end_effector",
            ("plan", "mujoco"),
            0.42,
            samples=4001,
            unit="fraction of the move",
        )
    )
    return result


def _render(result, width: int) -> str:
    return "\n".join(render(result, width))


def rows_of(text: str, name: str) -> list[str]:
    """Every table row of property ``name``, its wrapped lines (if any) joined: a row starts with
    its property's name, a continuation line with a space."""
    lines, out = text.splitlines(), []
    for i, line in enumerate(lines):
        if line.startswith(f"{name} "):
            block = [line] + list(itertools.takewhile(lambda more: more.startswith(" ") and more.strip(), lines[i + 1 :]))
            out.append(" ".join(" ".join(block).split()))
    return out


@pytest.mark.parametrize("width", WIDTHS)
def test_results_fit_the_terminal_and_cut_no_number(failing, width):
    """Every number whole and equal to its check's; at 80 columns only a row naming this test's
    long backend name twice ('flipped-urdf vs closed-form') wraps, between words."""
    for terminal in (False, True):
        lines = render(failing, width, terminal)
        assert_fits(lines, failing, width, wrapped_rows_allowed=width == 80)
        wrapped = [lines[i - 1] for i, line in enumerate(lines) if line.startswith(" ") and lines[i - 1].startswith("ik.")]
        assert all(FLIPPED in row and "closed" in row for row in wrapped), wrapped
    text = _render(failing, width)
    for prop in {c.property for c in failing.failed}:  # its own row, blamed on the flipped backend
        assert any(FLIPPED in row and "FAIL" in row for row in rows_of(text, prop)), rows_of(text, prop)
    assert "verdict: FAIL" in text


@pytest.mark.parametrize("width", WIDTHS)
def test_labels_say_what_each_number_is(failing, width):
    text = _render(failing, width)
    lines = text.splitlines()
    agreement = next(i for i, ln in enumerate(lines) if ln.startswith("property ") and "max error" in ln)
    assert "tolerance" in lines[agreement] and ("p99 error" in lines[agreement]) == (width == 200)
    assert any(ln.startswith("performance ") and "measured" in ln and "goal" in ln for ln in lines[agreement + 1 :])
    rms = rows_of(text, "tracking.computed-torque")[0]
    assert " 3.5e-5 0.0001 rad " in rms  # 'measured' is the check's value (an RMS here), then the goal and its unit
    pd = rows_of(text, "tracking.pd+gravity")[0]
    assert " 0.42 0.15 × move " in pd and pd.endswith("missed") and "FAIL" not in pd
    assert ("RMS joint error over the motion" in rms) == (width == 200)  # what is measured: dropped before any number
    assert "rad|m" not in text  # every joint of arm3 is revolute: joint-space errors are in rad
    verdict = next(ln for ln in lines if ln.startswith("verdict: "))
    assert len(verdict) <= width  # the backends by name where the line has room, else how many
    assert f"{len(failing.backends)} backends" in verdict or all(b in verdict for b in failing.backends)
    pairs = "pin-urdf vs 2" if backend_info("drake-sdf").available else "pin-urdf vs mujoco"  # Drake's dynamics: a second pair
    assert pairs in rows_of(text, "dynamics.gravity")[0]  # short labels in the tables


def test_compact_numbers_keep_three_digits_and_drop_exponent_padding():
    assert [compact(x) for x in (7.69e-16, 1e-9, 0.0422, 0.0, 1.0, 2.46e6, float("inf"), 1e-4)] == [
        "7.69e-16",
        "1e-9",
        "0.0422",
        "0",
        "1",
        "2.46e6",
        "inf",
        "0.0001",
    ]


def test_suites_get_one_line_each(failing):
    text = _render(failing, 80)
    head = text.split(f"\n{failing.model}: ")[0]  # before the tables (a failure below starts with ✗ too)
    lines = [ln for ln in head.splitlines() if re.match(r"^[✓✗·] ", ln)]
    assert [ln.split()[1] for ln in lines] == ["kinematics", "ik", "dynamics"]
    assert "✗ kinematics" in text and "checks fail" in lines[0] and lines[0].rstrip().endswith("s")


def test_fit_table_drops_optional_columns_before_cutting_a_word():
    console = Console(width=40, record=True, file=open("/dev/null", "w"))
    cols = [("name", {}), ("value", {"justify": "right"}), ("comment", {})]
    rows = [["fk.position", "1.234567e-16", "a long explanation of the number"]]
    console.print(fit_table(console, cols, rows, optional=("comment",)))
    text = console.export_text()
    assert "fk.position" in text and "1.234567e-16" in text and "explanation" not in text
    assert max(len(ln.rstrip()) for ln in text.splitlines()) <= 40


@pytest.mark.parametrize("width", WIDTHS)
def test_track_table_fits_and_labels_its_columns(width):
    from kinverify.tracking.track import default_trajectory, track

    spec = load_spec(MODELS / "arm3.toml")
    result = track(
        spec,
        ModelSources.from_spec(spec).urdf,
        default_trajectory(spec),
        ["computed-torque", "position"],
        render=False,
        plots=False,
    )
    console = Console(width=width, record=True, file=open("/dev/null", "w"))
    console.print(track_table(spec, result, console))
    text = console.export_text()
    assert max(len(ln.rstrip()) for ln in text.splitlines()) <= width
    header = " ".join(ln.strip() for ln in text.splitlines()[:6])
    assert "RMS error" in header and "(motion)" in header and "max error" in header and "[rad]" in header
    for m in result.metrics:
        row = next(ln for ln in text.splitlines() if ln.strip().startswith(m.controller)).split()
        assert row[1] == f"{m.rms_error:.3e}" and row[2] == f"{m.max_error:.3e}"  # RMS under RMS, max under max


def test_joint_space_units_follow_the_joint_types():
    assert display_unit("rad|m", [True, True]) == "rad" and display_unit("joint", [False]) == "m"
    assert display_unit("rad|m", [True, False]) == "rad|m" and display_unit("m/rad", [False]) == "m/rad"


def test_every_long_suite_reports_a_real_total():
    """Kinematics, IK, dynamics and tracking each report (done, total) with a fixed total they
    reach, so the bar shows a count and a time left."""
    calls: dict[str, list[tuple[int, int]]] = {}
    current = []
    opts = VerifyOptions(
        samples=30,
        extra={"ik_targets": 4, "tracking_controllers": ["computed-torque"]},
        suites=["kinematics", "ik", "dynamics", "tracking"],
    )
    opts.on_progress = lambda done, total: calls.setdefault(current[-1], []).append((done, total))
    verify(ModelSources.from_spec(load_spec(MODELS / "arm3.toml")), opts, progress=current.append)
    assert set(calls) == {"kinematics", "ik", "dynamics", "tracking"} <= set(UNITS)
    for suite, seen in calls.items():
        totals = {t for _, t in seen}
        assert len(totals) == 1 and totals.pop() > 0, (suite, seen)
        assert seen[-1][0] == seen[-1][1] and [d for d, _ in seen] == sorted(d for d, _ in seen)


def test_progress_bar_shows_counts_and_time_left_never_a_question_mark():
    console = Console(width=100, record=True, force_terminal=True, file=open("/dev/null", "w"))
    with VerifyProgress(console, "arm3") as bar:
        bar.suite("kinematics")
        for done in range(0, 1001, 250):
            bar.advance(done, 1000)
            bar._progress.refresh()
        bar.suite("workspace")
        bar._progress.refresh()
    text = console.export_text()
    assert "1000/1000 configurations" in text and "/?" not in text and "arm3: workspace" in text


def test_quiet_is_one_line(tmp_path, capsys):
    skip = [a for s in ("pictures", "tracking", "ik", "dynamics", "workspace", "diagnosis") for a in ("--skip", s)]
    code = main(
        [
            "verify",
            str(MODELS / "arm3.toml"),
            "--samples",
            "5",
            *skip,
            "--quiet",
            "--report",
            str(tmp_path / "r.html"),
            "--json",
            str(tmp_path / "r.json"),
        ]
    )
    out = capsys.readouterr().out
    assert code == 0 and len(out.strip().splitlines()) == 1, out
    assert out.startswith("arm3: pass (0 of ") and "r.html" in out


CHEAP = [
    "--samples",
    "20",
    "--ik-targets",
    "5",
    *(a for s in ("tracking", "pictures", "workspace", "diagnosis") for a in ("--skip", s)),
    "--json",
    "r.json",
    "--report",
    "r.html",
]  # every table row but tracking's (the full run: test_report.py)


@pytest.mark.parametrize("model, where", [("gripper", "terminal"), ("space_arm", "log")])
def test_verify_at_80_columns_in_a_terminal_and_in_a_log(model, where, tmp_path):
    """The real CLI in an 80-column pseudo-terminal (what ``script`` with ``stty cols 80`` gives)
    and with stdout to a file (rich falls back to 80 columns): what it leaves is the saved result
    printed at 80 columns, every row on one line. Every shipped spec is printed both ways from
    its result in tests/test_models.py; the full default arm3 run in tests/report/test_report.py."""
    argv = ["verify", str(MODELS / f"{model}.toml"), *CHEAP]
    lines, code = run_in_terminal(argv, tmp_path, 80) if where == "terminal" else run_to_file(argv, tmp_path)
    result = load_result_json(tmp_path / "r.json")
    assert code == 0 and result.passed
    assert_fits(lines, result, 80)
    assert lines[:-1] == render(result, 80, terminal=where == "terminal")  # the same as printed from the saved result
    assert lines[-1] == "report: r.html  json: r.json"


def test_findings_and_notes_wrap_under_their_text_and_keep_every_word(failing):
    """File mode prints long findings: a tag, then the message with a hanging indent, no word cut."""
    long = (
        "the MJCF's world is the URDF's moved by xyz = [0, 0, 0] m, rpy = [0, 0, 3.14159] rad (180° turn) in "
        "/a/rather/long/path/to/robot_description/urdf/robot_with_a_long_name.urdf, fitted over 7 frames"
    )
    finding = Finding("base_transform", "error", long, subject_type="model")
    lines = render(dataclasses.replace(failing, findings=[finding], notes=["note " + long]), 80)
    assert max(len(line) for line in lines) <= 80
    start = next(i for i, line in enumerate(lines) if line.startswith("error "))
    indent = lines[start].index("base_transform")  # continuation lines start under the text
    block = [lines[start]] + list(itertools.takewhile(lambda line: line[:indent].isspace(), lines[start + 1 :]))
    assert (
        len(block) > 1
        and all(line[indent] != " " for line in block)
        and " ".join(" ".join(block).split()) == f"error base_transform (model): {' '.join(long.split())}"
    )


def test_a_findings_message_and_subject_are_printed_literally_not_as_markup():
    """Messages quote the files (``[0.1 0.2]``, a joint named ``[bold]j``): printed as written."""
    message = "axis [0 0 1] in the URDF, [bold]0 1 0[/bold] in the MJCF [/]"
    finding = Finding("axis_direction", "error", message, "[red]joint3", "joint")
    result = VerifyResult("arm3", "files", 0, 0, ["joint3"], [], [], [], {}, findings=[finding])
    console = Console(width=200, record=True, color_system=None)
    print_result(result, console)
    text = console.export_text()
    assert f"axis_direction (joint [red]joint3): {message}" in text, text
