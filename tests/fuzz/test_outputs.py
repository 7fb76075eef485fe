"""No data lost: every file a run writes (``--json``, ``--report``, ``--junit``, ``--write-accepted``,
``ik --json``, generate's files) is refused when it names an input of the run, including the
files discovered while loading (the accepted differences beside the URDF, an MJCF's
``<include>``, a xacro's include), directly or through a link; the outputs of a run are written
together or not at all; a long valid output name works (docs/robustness.md, outputs)."""

from __future__ import annotations

import json
import os
import resource
from pathlib import Path

import pytest

from kinverify.cli import main
from kinverify.errors import InputError
from kinverify.io.plan import output_plan
from kinverify.io.write import NAME_MAX, temp_prefix, write_atomic
from tests.fuzz.conftest import FAST, FILES
from tests.fuzz.harness import refused, snapshot

PAIR = ["verify", "--urdf", "u.urdf", "--mjcf", "r.xml", *FILES]
FLIPPED = ["verify", "--urdf", "u.urdf", "--mjcf", "flip.xml", *FILES]  # fails: error findings to write


@pytest.fixture
def flipped(work) -> Path:
    text = (work / "r.xml").read_text()
    (work / "flip.xml").write_text(text.replace('axis="0.0 1.0 0.0"', 'axis="0.0 -1.0 0.0"', 1))
    os.symlink("u.urdf", work / "u_link.urdf")
    os.symlink("accept.toml", work / "acc_link.toml")
    os.mkfifo(work / "fifo")
    return work


@pytest.mark.parametrize(
    "extra, words",
    [
        (["--write-accepted", "u.urdf"], "--write-accepted u.urdf is --urdf u.urdf, an input of this run"),
        (["--write-accepted", "flip.xml"], "--write-accepted flip.xml is --mjcf flip.xml"),
        (["--write-accepted", "u_link.urdf"], "--write-accepted u_link.urdf is --urdf u.urdf"),
        (["--accept", "accept.toml", "--write-accepted", "accept.toml"], "is --accept accept.toml"),
        (["--accept", "accept.toml", "--write-accepted", "acc_link.toml"], "is --accept accept.toml"),
        (["--json", "o.json", "--write-accepted", "o.json"], "name the same file"),
        (["--write-accepted", "fifo"], "is a FIFO (named pipe), not a regular file"),
        (["--accept", "accept.toml", "--json", "accept.toml"], "--json accept.toml is --accept accept.toml"),
        (["--accept", "accept.toml", "--report", "acc_link.toml"], "--report acc_link.toml is --accept accept.toml"),
        (["--accept", "accept.toml", "--junit", "accept.toml"], "--junit accept.toml is --accept accept.toml"),
    ],
)
def test_write_accepted_and_the_accepted_file_are_checked_like_every_output(capfd, flipped, extra, words):
    refused(capfd, [*FLIPPED, *extra], flipped, words)


def test_the_accepted_differences_found_beside_the_urdf_are_an_input(capfd, work):
    (work / "kinverify-accepted.toml").write_text((work / "accept.toml").read_text())
    refused(capfd, [*PAIR, "--json", "kinverify-accepted.toml"], work, "the accepted differences", "an input of this run")
    refused(capfd, [*PAIR, "--write-accepted", "kinverify-accepted.toml"], work, "an input of this run")


@pytest.mark.parametrize(
    "argv, words",
    [
        (["ik", "m.toml", "--targets", "t.npy", "--json", "t.npy"], "--json t.npy is --targets t.npy"),
        (["ik", "m.toml", "--targets", "t.npy", "--initial", "q.npy", "--json", "q.npy"], "--json q.npy is --initial q.npy"),
        (["verify", "--mjcf", "main.xml", *FILES, "--report", "inc.xml"], "--report inc.xml is the MJCF's <include>"),
        (
            ["verify", "--urdf", "robot.urdf.xacro", *FILES, "--json", "part.xacro"],
            "--json part.xacro is robot.urdf.xacro: xacro include",
        ),
        (["generate", "m.toml", "--out", "."], None),
    ],
)
def test_files_a_run_reads_are_never_its_outputs(capfd, work, argv, words):
    if words is None:  # generate writes <name>.urdf: here the spec's own name, made the spec's
        (work / "arm3.urdf").symlink_to("m.toml")
        words = "is the spec MODEL m.toml"
    refused(capfd, argv, work, words)


def test_the_outputs_of_a_run_are_replaced_together_or_not_at_all(capfd, work):
    (work / "old.json").write_text("old results\n")
    (work / "old.html").write_text("old page\n")
    capfd.readouterr()
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    resource.setrlimit(resource.RLIMIT_FSIZE, (100_000, hard))  # the JSON (~55 kB) fits, the page (~260 kB) does not
    try:
        code = main(["verify", "m.toml", *FAST, "--json", "old.json", "--report", "old.html"])
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
    err = capfd.readouterr().err
    assert code == 2 and err == "kinverify: error: old.html: cannot write: File too large; nothing was replaced\n", err
    assert (work / "old.json").read_text() == "old results\n"  # not a new JSON beside an old page
    assert (work / "old.html").read_text() == "old page\n"
    assert not list(work.glob(".*.tmp"))


def test_a_staged_output_is_discarded_when_a_later_one_is_refused(tmp_path):
    (tmp_path / "a.json").write_text("old a")
    with pytest.raises(InputError, match="is a directory"):
        with output_plan([], [("--json", tmp_path / "a.json"), ("--report", tmp_path / "b.html")]):
            write_atomic(tmp_path / "a.json", "new a")
            (tmp_path / "b.html").mkdir()  # appeared since the outputs were claimed
            write_atomic(tmp_path / "b.html", "new b")
    assert (tmp_path / "a.json").read_text() == "old a"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json", "b.html"]


@pytest.mark.parametrize("length", [245, NAME_MAX])
def test_a_long_valid_output_name_is_written(capfd, work, length):
    name = "a" * (length - len(".json")) + ".json"
    assert main(["verify", "m.toml", *FAST, "--json", name, "--report", "r.html"]) == 0, capfd.readouterr().err
    assert json.loads((work / name).read_text())["verdict"] == "pass"
    assert len(temp_prefix(name).encode()) + 8 + len(".tmp") <= NAME_MAX
    assert len(temp_prefix("é" * 200).encode()) < NAME_MAX  # cut on a character boundary
    assert not list(work.glob(".*.tmp"))


def test_a_results_file_that_is_also_the_junit_output_is_refused(capfd, work):
    before = snapshot(work)
    refused(capfd, ["verify", "m.toml", *FAST, "--json", "x.xml", "--junit", "x.xml"], work, "name the same file")
    assert snapshot(work) == before
