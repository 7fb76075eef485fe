"""Every file every command reads, replaced by something hostile: a FIFO (would block forever), a
device that never ends (``/dev/zero``), a 3 GB sparse file, a folder, text nested thousands of
levels deep. Each is refused within seconds, in one line naming the file, exit 2, with nothing
written (docs/robustness.md: one reader for every input)."""

from __future__ import annotations

import os
import types
from pathlib import Path

import numpy as np
import pytest

from kinverify.errors import InputError
from kinverify.io import read as read_mod
from kinverify.io.read import InputFileError, read_bytes, read_head
from kinverify.pipeline.limits import MAX_DATA_BYTES, MAX_MODEL_BYTES
from tests.fuzz.conftest import FAST, FILES
from tests.fuzz.harness import refused

# slot: (command line with X for the hostile file, X's name). X is also found by name: the
# accepted-differences file beside the URDF, a file an MJCF or a xacro includes, a baseline beside a spec.
SLOTS = {
    "verify MODEL": (["verify", "X", *FAST], "x.toml"),
    "verify --urdf": (["verify", "--urdf", "X", "--mjcf", "r.xml", *FILES], "x.urdf"),
    "verify --mjcf": (["verify", "--urdf", "u.urdf", "--mjcf", "X", *FILES], "x.xml"),
    "verify --accept": (["verify", "--urdf", "u.urdf", "--mjcf", "r.xml", *FILES, "--accept", "X"], "x.toml"),
    "the accepted differences beside the URDF": (
        ["verify", "--urdf", "u.urdf", "--mjcf", "r.xml", *FILES],
        "kinverify-accepted.toml",
    ),
    "an MJCF <include>": (["verify", "--mjcf", "main.xml", *FILES], "inc.xml"),
    "a xacro include": (["verify", "--urdf", "robot.urdf.xacro", *FILES], "part.xacro"),
    "verify --urdf alone": (["verify", "--urdf", "X", *FILES], "x.urdf"),
    "generate MODEL": (["generate", "X", "--out", "out"], "x.toml"),
    "report RESULTS": (["report", "X", "--out", "out/r.html"], "x.json"),
    "ik MODEL": (["ik", "X", "--target", "0.2", "0.1", "0.6"], "x.toml"),
    "ik --urdf": (["ik", "--urdf", "X", "--tip", "link3", "--target", "0.2", "0.1", "0.6"], "x.urdf"),
    "ik --targets": (["ik", "m.toml", "--targets", "X", "--json", "out/ik.json"], "x.npy"),
    "ik --initial": (["ik", "m.toml", "--targets", "t.npy", "--initial", "X", "--json", "out/ik.json"], "x.npy"),
    "track MODEL": (["track", "X", "--duration", "0.1", "--hold", "0"], "x.toml"),
    "baseline save MODEL": (["baseline", "save", "X", "--out", "out/b.json"], "x.toml"),
    "baseline check MODEL": (["baseline", "check", "X", "--baseline", "b.json"], "x.toml"),
    "baseline check --baseline": (["baseline", "check", "m.toml", "--baseline", "X"], "x.json"),
    "diff OLD (specs)": (["diff", "X", "m.toml", "--report", "out/d.html"], "x.toml"),
    "diff NEW (URDFs)": (["diff", "u.urdf", "X", "--report", "out/d.html"], "x.urdf"),
    "diff OLD (MJCFs)": (["diff", "X", "r.xml", "--report", "out/d.html"], "x.xml"),
    "check FILE": (["check", "X", "--samples", "0"], "x.toml"),
    "check: the baseline beside the spec": (["check", "m.toml", "--samples", "0", "--suites", "kinematics"], "baselines/m.json"),
}


def _hostile(path: Path, kind: str) -> None:
    path.parent.mkdir(exist_ok=True)
    path.unlink(missing_ok=True)
    if kind == "fifo":
        os.mkfifo(path)
    elif kind == "device":
        path.symlink_to("/dev/zero")
    elif kind == "sparse":
        with open(path, "wb") as f:
            f.truncate(3 * 2**30)  # no disk used
    elif kind == "folder":
        path.mkdir()


@pytest.mark.parametrize("kind", ["fifo", "device", "sparse", "folder"])
@pytest.mark.parametrize("slot", sorted(SLOTS))
def test_every_input_of_every_command_refuses_what_is_not_a_bounded_regular_file(capfd, work, slot, kind):
    if kind == "folder" and slot.startswith(("check", "the accepted")):
        pytest.skip("a folder of that name is looked into, not read (covered by the other kinds)")
    argv, name = SLOTS[slot]
    _hostile(work / name, kind)
    line = refused(capfd, [name if a == "X" else a for a in argv], work, Path(name).name)
    if kind == "sparse" and slot == "a xacro include":  # the files xacro opens share one budget
        assert "which would exceed the 8 MB the xacro file and its includes share: " in line, line
    elif kind == "sparse":
        assert "above the" in line and "MB kinverify" in line, line
    elif kind != "folder":
        assert "not a regular file" in line, line


DEEP = {
    ".toml": "a = " + "[" * 5000 + "]" * 5000 + "\n",
    ".json": "[" * 100_000 + "]" * 100_000,
    ".urdf": '<robot name="r"><link name="a">' + "<x>" * 1000 + "</x>" * 1000 + "</link></robot>",
    ".xml": "<mujoco><worldbody>" + "<body>" * 400 + "</body>" * 400 + "</worldbody></mujoco>",
}


@pytest.mark.parametrize(
    "slot",
    [
        "verify MODEL",
        "verify --accept",
        "report RESULTS",
        "baseline check --baseline",
        "verify --urdf",
        "verify --mjcf",
        "an MJCF <include>",
        "diff NEW (URDFs)",
    ],
)
def test_deeply_nested_inputs_are_bad_input_not_a_recursion_error(capfd, work, slot):
    argv, name = SLOTS[slot]
    text = DEEP[Path(name).suffix]
    if slot == "an MJCF <include>":
        text = "<mujoco>" + "<default>" * 400 + "</default>" * 400 + "</mujoco>"
    (work / name).write_text(text)
    line = refused(capfd, [name if a == "X" else a for a in argv], work, "levels deep")
    assert "main.xml" in line if slot == "an MJCF <include>" else Path(name).name in line


def test_the_size_is_measured_by_reading_not_by_stat(tmp_path):
    proc = Path("/proc/self/maps")  # a regular file whose size reads 0 and whose content is kilobytes
    if not proc.is_file() or proc.stat().st_size != 0:
        pytest.skip("no /proc here")
    with pytest.raises(InputFileError, match="is more than 100 bytes, above the 100 bytes kinverify reads"):
        read_bytes(proc, "--x", limit=100)
    assert len(read_bytes(proc, "--x", limit=MAX_MODEL_BYTES)) > 100
    exact = tmp_path / "exact.json"
    exact.write_bytes(b"1" * 1000)
    assert read_bytes(exact, limit=1000) == b"1" * 1000
    with pytest.raises(InputFileError, match="above the"):
        read_bytes(exact, limit=999)
    os.mkfifo(tmp_path / "fifo")
    with pytest.raises(InputError, match="FIFO"):
        read_head(tmp_path / "fifo")
    assert MAX_DATA_BYTES >= 128 * 2**20  # a panda baseline at the maximum sample count is about 120 MB


def test_ik_targets_are_bounded_in_number_and_distance(capfd, work):
    poses = np.tile(np.eye(4), (100_001, 1, 1))
    np.save(work / "many.npy", poses)
    refused(capfd, ["ik", "m.toml", "--targets", "many.npy"], work, "100,001 targets, above the 100,000")
    far = np.tile(np.eye(4), (2, 1, 1))
    far[1, :3, 3] = 1e308
    np.save(work / "far.npy", far)
    refused(capfd, ["ik", "m.toml", "--targets", "far.npy"], work, "far.npy: target 1 is more than 1e+06 m")
    refused(capfd, ["ik", "m.toml", "--target", "1e308", "1e308", "1e308"], work, "--target: 1e308 m is more than")
    refused(capfd, ["ik", "--urdf", "u.urdf", "--tip", "link3", "--target", "1e7", "0", "0"], work, "--target")


def _refused_by_argparse(capfd, argv: list[str], words: str) -> None:
    from kinverify.cli import main

    capfd.readouterr()
    with pytest.raises(SystemExit) as exit_:
        main(argv)
    err = capfd.readouterr().err
    assert exit_.value.code == 2 and err.count("\n") == 1 and words in err, err


def test_values_that_would_pass_anything_or_overflow_are_bad_input(capfd, work):
    refused(capfd, ["verify", "m.toml", *FAST, "--tolerance", "fk.position=inf"], work, "must be a non-negative finite number")
    refused(capfd, ["verify", "m.toml", *FAST, "--gate", "ik.success_rate=inf"], work, "must be a non-negative finite number")
    _refused_by_argparse(
        capfd,
        ["baseline", "check", "m.toml", "--baseline", "b.json", "--tolerance", "inf"],
        "--tolerance: must be a finite number > 0, got inf",
    )
    refused(capfd, ["track", "m.toml", "--target", "1e308", "1e308", "1e308"], work, "is more than 1e+06 m from the base")


def test_nothing_compared_is_not_a_pass(capfd, work):
    from kinverify.suites.registry import suite_names

    every = [a for s in suite_names() for a in ("--skip", s)]
    refused(capfd, ["verify", "m.toml", "--quiet", *every], work, "--skip: every suite is skipped")
    only_diagnosis = [a for s in suite_names() if s != "diagnosis" for a in ("--skip", s)]  # it runs, compares nothing
    refused(capfd, ["verify", "m.toml", "--quiet", "--samples", "2", *only_diagnosis], work, "m.toml: nothing was compared")


def test_an_unreachable_dask_scheduler_is_bad_input_at_once(capfd, work):
    pytest.importorskip("dask.distributed")
    refused(
        capfd,
        ["verify", "m.toml", *FAST, "--executor", "dask", "--scheduler", "tcp://127.0.0.1:1"],
        work,
        "--scheduler tcp://127.0.0.1:1: no Dask scheduler answers there within 5 s (Connection refused)",
    )


def test_a_file_swapped_for_a_fifo_after_the_check_is_refused_on_its_descriptor(tmp_path, monkeypatch):
    """The path is a regular file when checked and a FIFO when opened (swapped in between, here
    right after the check): the non-blocking open returns at once and the descriptor's own fstat
    refuses it, the descriptor closed."""
    target = tmp_path / "robot.urdf"
    target.write_text("<robot/>")
    real_stat, swapped = os.stat, []

    def stat_then_swap(path, *args, **kwargs):
        st = real_stat(path, *args, **kwargs)
        if os.fspath(path) == str(target) and not swapped:
            swapped.append(path)
            os.unlink(target)
            os.mkfifo(target)
        return st

    monkeypatch.setattr(read_mod.os, "stat", stat_then_swap)
    before = len(os.listdir("/proc/self/fd"))
    with pytest.raises(InputFileError, match=r"is a FIFO \(named pipe\), not a regular file"):
        read_mod._open(str(target), "--urdf")
    monkeypatch.undo()
    assert swapped and target.is_fifo() and len(os.listdir("/proc/self/fd")) == before


def test_files_a_library_opens_share_one_byte_budget(tmp_path):
    """Inside :func:`library_reads` (xacro's includes) the files read together stay within the
    limit: two of 60 bytes each fit 120, not 100, though each alone fits."""
    first, second = tmp_path / "a.xacro", tmp_path / "b.xacro"
    first.write_bytes(b"a" * 60)
    second.write_bytes(b"b" * 60)
    library = types.ModuleType("library")
    with read_mod.library_reads([library], "robot.urdf.xacro: xacro include", limit=120):
        assert library.open(first).read() + library.open(second).read() == "a" * 60 + "b" * 60
    with read_mod.library_reads([library], "robot.urdf.xacro: xacro include", limit=100):
        assert library.open(first).read() == "a" * 60
        with pytest.raises(
            InputFileError,
            match=r"b\.xacro is 60 bytes, which would exceed the 100 bytes the files the library opens share: 60 bytes already read",
        ) as err:
            library.open(second)
    assert err.value.too_large and "open" not in vars(library)
