"""Terminal output read back from rich's recording console at 80 and 200 columns: every line fits,
no number or name is cut, the labels say what the numbers are; ``kinverify track``'s table; the
progress every long suite reports; ``--quiet``."""

from __future__ import annotations

import re

import numpy as np
import pytest
from rich.console import Console

from kinverify.backends import ModelSources
from kinverify.cli import main
from kinverify.model.specfile import load_spec
from kinverify.report.progress import UNITS, VerifyProgress
from kinverify.report.terminal import display_unit, fit_table, print_result, track_table
from kinverify.run import VerifyOptions, verify
from kinverify.suites.base import value_check
from kinverify.suites.registry import get_property
from tests.paths import MODELS
from tests.report.flipped import FLIPPED, flipped_backend

WIDTHS = (80, 200)


@pytest.fixture(scope="module")
def failing():
    """Kinematics, IK and dynamics with one backend whose joint2 axis is flipped, and tracking
    checks as the tracking suite makes them (one below its goal)."""
    sources = ModelSources.from_spec(load_spec(MODELS / "arm3.toml"))
    opts = VerifyOptions(samples=10, suites=["kinematics", "ik", "dynamics"], extra={"ik_targets": 5})
    result = verify(sources, opts, extra_backends=[flipped_backend(sources, "joint2")])
    result.checks.append(value_check(get_property("tracking.computed-torque"), None, "end_effector", ("plan", "mujoco"), 3.5e-5,
                                     samples=4001, unit="rad"))
    result.checks.append(value_check(get_property("tracking.pd+gravity"), None, "end_effector", ("plan", "mujoco"), 0.42,
                                     samples=4001, unit="fraction of the move"))
    return result


def _render(result, width: int) -> str:
    console = Console(width=width, record=True, file=open("/dev/null", "w"))
    print_result(result, console)
    return console.export_text()


def rows_of(text: str, name: str) -> list[str]:
    """Every table row whose first cell is ``name``, its wrapped lines joined: a row's
    continuation lines are blank in the first column."""
    lines, out = text.splitlines(), []
    for i, line in enumerate(lines):
        if line.startswith(f"  {name} "):
            block = [line]
            for more in lines[i + 1:]:
                if not more.strip() or more[2:3] != " ":
                    break
                block.append(more)
            out.append(" ".join(" ".join(block).split()))
    return out


@pytest.mark.parametrize("width", WIDTHS)
def test_results_fit_the_terminal_and_cut_no_number(failing, width):
    text = _render(failing, width)
    assert max(len(l.rstrip()) for l in text.splitlines()) <= width
    for prop in {c.property for c in failing.failed}:  # its own row, blamed on the flipped backend, the value whole
        worst = max(c.max_error for c in failing.failed if c.property == prop)
        assert any(FLIPPED in row and f" {worst:.2e} " in row and "FAIL" in row for row in rows_of(text, prop)), rows_of(text, prop)
    for c in failing.checks:
        assert rows_of(text, c.property)  # names whole, never folded
        assert any(f"{c.tolerance:.0e}" in row or f"{c.tolerance:.3g}" in row for row in rows_of(text, c.property))
    assert "verdict: FAIL" in text


@pytest.mark.parametrize("width", WIDTHS)
def test_labels_say_what_each_number_is(failing, width):
    text = _render(failing, width)
    lines = text.splitlines()
    agreement = next(i for i, l in enumerate(lines) if l.strip().startswith("property") and "max error" in l)
    assert "tolerance" in lines[agreement] and ("p99 error" in lines[agreement]) == (width == 200)
    assert any("measured" in l and "goal" in l for l in lines[agreement + 1:])  # the performance table's header
    rms = rows_of(text, "tracking.computed-torque")[0]
    assert " 3.5e-05 0.0001 " in rms  # 'measured' is the check's value (an RMS here), then the goal
    pd = rows_of(text, "tracking.pd+gravity")[0]
    assert " 0.42 0.15 " in pd and "fraction" in pd and "below" in pd and "FAIL" not in pd
    assert ("RMS joint error over the motion" in rms) == (width == 200)  # what is measured: dropped before any number
    assert "rad|m" not in text  # every joint of arm3 is revolute: joint-space errors are in rad


def test_suites_get_one_line_each(failing):
    text = _render(failing, 80)
    lines = [l for l in text.splitlines() if re.match(r"^[✓✗·] ", l)]
    assert [l.split()[1] for l in lines] == ["kinematics", "ik", "dynamics"]
    assert "✗ kinematics" in text and "checks fail" in lines[0] and lines[0].rstrip().endswith("s")


def test_fit_table_drops_optional_columns_before_cutting_a_word():
    console = Console(width=40, record=True, file=open("/dev/null", "w"))
    cols = [("name", {}), ("value", {"justify": "right"}), ("comment", {})]
    rows = [["fk.position", "1.234567e-16", "a long explanation of the number"]]
    console.print(fit_table(console, cols, rows, optional=("comment",)))
    text = console.export_text()
    assert "fk.position" in text and "1.234567e-16" in text and "explanation" not in text
    assert max(len(l.rstrip()) for l in text.splitlines()) <= 40


@pytest.mark.parametrize("width", WIDTHS)
def test_track_table_fits_and_labels_its_columns(width):
    from kinverify.tracking.track import default_trajectory, track

    spec = load_spec(MODELS / "arm3.toml")
    result = track(spec, ModelSources.from_spec(spec).urdf, default_trajectory(spec), ["computed-torque", "position"],
                   render=False, plots=False)
    console = Console(width=width, record=True, file=open("/dev/null", "w"))
    console.print(track_table(spec, result, console))
    text = console.export_text()
    assert max(len(l.rstrip()) for l in text.splitlines()) <= width
    header = " ".join(l.strip() for l in text.splitlines()[:6])
    assert "RMS error" in header and "(motion)" in header and "max error" in header and "[rad]" in header
    for m in result.metrics:
        row = next(l for l in text.splitlines() if l.strip().startswith(m.controller)).split()
        assert row[1] == f"{m.rms_error:.3e}" and row[2] == f"{m.max_error:.3e}"  # RMS under RMS, max under max


def test_joint_space_units_follow_the_joint_types():
    assert display_unit("rad|m", [True, True]) == "rad" and display_unit("joint", [False]) == "m"
    assert display_unit("rad|m", [True, False]) == "rad|m" and display_unit("m/rad", [False]) == "m/rad"


def test_every_long_suite_reports_a_real_total():
    """Kinematics, IK, dynamics and tracking each report (done, total) with a fixed total they
    reach, so the bar shows a count and a time left."""
    calls: dict[str, list[tuple[int, int]]] = {}
    current = []
    opts = VerifyOptions(samples=30, extra={"ik_targets": 4, "tracking_controllers": ["computed-torque"]},
                         suites=["kinematics", "ik", "dynamics", "tracking"])
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
    code = main(["verify", str(MODELS / "arm3.toml"), "--samples", "5", *skip,
                 "--quiet", "--report", str(tmp_path / "r.html"), "--json", str(tmp_path / "r.json")])
    out = capsys.readouterr().out
    assert code == 0 and len(out.strip().splitlines()) == 1, out
    assert out.startswith("arm3: pass (0 of ") and "r.html" in out
