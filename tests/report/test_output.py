"""Output safety: an output that is an input of the run, another output, a directory or a device
is refused (exit 2, one line, nothing written, every input byte-identical); a failed write
replaces nothing."""

from __future__ import annotations

import json
import os
import re
import resource
import signal
import socket
import subprocess
import sys
from pathlib import Path

import pytest

from kinverify.cli import main
from kinverify.errors import InputError
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import load_spec
from kinverify.io.plan import OutputPlan, check_target, default_output, output_plan
from kinverify.io.write import write_atomic
from tests.paths import MODELS

FAST = [
    "--samples",
    "3",
    "--skip",
    "ik",
    "--skip",
    "tracking",
    "--skip",
    "pictures",
    "--skip",
    "workspace",
    "--backends",
    "analytic,mujoco",
    "--quiet",
]


@pytest.fixture
def work(tmp_path, monkeypatch):
    """A folder holding a spec, its URDF and MJCF, a results JSON and a baseline; cwd there."""
    monkeypatch.chdir(tmp_path)
    spec = load_spec(MODELS / "arm3.toml")
    Path("m.toml").write_text((MODELS / "arm3.toml").read_text())
    Path("u.urdf").write_text(generate_urdf(spec))
    Path("r.xml").write_text(generate_mjcf(spec))
    return tmp_path


def snapshot(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def refused(capsys, argv, words: str) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("kinverify: error: ") and "Traceback" not in err, err
    assert words in err, err
    return err


@pytest.mark.parametrize(
    "argv, words",
    [
        (["verify", "m.toml", "--json", "m.toml"], "--json m.toml is the spec MODEL m.toml, an input of this run"),
        (["verify", "m.toml", "--report", "m.toml"], "--report m.toml is the spec MODEL m.toml"),
        (["verify", "--urdf", "u.urdf", "--mjcf", "r.xml", "--json", "u.urdf"], "--json u.urdf is --urdf u.urdf"),
        (["verify", "--urdf", "u.urdf", "--mjcf", "r.xml", "--report", "./r.xml"], "--report r.xml is --mjcf r.xml"),
        (["verify", "m.toml", "--json", "x.out", "--report", "x.out"], "name the same file"),
        (["baseline", "save", "m.toml", "--out", "m.toml"], "--out m.toml is the spec MODEL"),
        (["diff", "u.urdf", "u2.urdf", "--report", "u.urdf"], "--report u.urdf is OLD u.urdf"),
        (["track", "m.toml", "--json", "m.toml"], "--json m.toml is the spec MODEL"),
    ],
)
def test_an_output_that_is_an_input_or_another_output_is_refused_before_the_run(work, capsys, argv, words):
    Path("u2.urdf").write_text(Path("u.urdf").read_text())
    before = snapshot(work)
    refused(capsys, argv, words)
    assert snapshot(work) == before  # nothing written, nothing replaced


def test_report_out_equal_to_its_results_json_is_refused(work, capsys):
    assert main(["verify", "m.toml", *FAST, "--json", "r.json", "--report", "r.html"]) == 0
    capsys.readouterr()
    before = snapshot(work)
    refused(capsys, ["report", "r.json", "--out", "r.json"], "--out r.json is RESULTS r.json")
    assert snapshot(work) == before
    assert json.loads(Path("r.json").read_text())["model"] == "arm3"


def test_baseline_check_report_equal_to_the_baseline_is_refused(work, capsys):
    assert main(["baseline", "save", "m.toml", "--out", "b.json", "--samples", "2"]) == 0
    capsys.readouterr()
    before = snapshot(work)
    refused(capsys, ["baseline", "check", "m.toml", "--baseline", "b.json", "--report", "b.json"], "is --baseline b.json")
    assert snapshot(work) == before


def test_a_link_or_symlink_to_an_input_is_the_input(work, capsys):
    os.link("m.toml", "hard.json")
    os.symlink("u.urdf", "soft.json")
    before = snapshot(work)
    refused(capsys, ["verify", "m.toml", "--json", "hard.json"], "the same file through a link")
    refused(capsys, ["verify", "--urdf", "u.urdf", "--mjcf", "r.xml", "--json", "soft.json"], "is --urdf u.urdf")
    assert snapshot(work) == before


def test_a_default_output_path_colliding_with_another_output_is_refused_before_writing(work, capsys):
    # --json names the default HTML path: both are claimed before either is written
    refused(capsys, ["verify", "m.toml", *FAST, "--json", "reports/arm3.html"], "name the same file")
    assert not Path("reports/arm3.html").exists()


def test_a_mesh_the_model_references_is_an_input(work, capsys):
    Path("meshes").mkdir()
    Path("meshes/base.stl").write_bytes(b"solid base\nendsolid base\n")
    urdf = (
        Path("u.urdf")
        .read_text()
        .replace("<visual>", '<visual><geometry><mesh filename="meshes/base.stl"/></geometry></visual><visual>', 1)
    )
    Path("mesh.urdf").write_text(urdf)
    before = snapshot(work)
    refused(
        capsys,
        ["verify", "--urdf", "mesh.urdf", "--mjcf", "r.xml", "--samples", "0", "--json", "meshes/base.stl"],
        "a mesh the model references",
    )
    assert snapshot(work) == before


def test_directories_fifos_sockets_and_devices_are_never_replaced(work, capsys):
    Path("folder").mkdir()
    os.mkfifo("fifo")
    sock = socket.socket(socket.AF_UNIX)
    sock.bind("sock")
    targets = {"folder": "a directory", "fifo": "a FIFO (named pipe)", "sock": "a socket"}
    try:  # a character device like /dev/full (needs root), made here rather than touching /dev
        os.mknod("full", 0o666 | 0o020000, os.makedev(1, 7))
        targets["full"] = "a character device"
    except PermissionError:
        pass
    try:
        for name, kind in targets.items():
            for flag in ("--json", "--report"):
                refused(capsys, ["verify", "m.toml", flag, name], f"{flag} {name} is {kind}, not a regular file")
            with pytest.raises(InputError, match=re.escape(kind)):
                write_atomic(name, "data")  # the writer refuses on its own, without a plan
        assert Path("folder").is_dir() and Path("fifo").is_fifo() and Path("sock").is_socket()
        if "full" in targets:
            assert Path("full").is_char_device()
    finally:
        sock.close()


def test_the_writer_checks_every_target_against_the_open_plan(tmp_path):
    spec = tmp_path / "m.toml"
    spec.write_text("x")
    with output_plan([("the spec MODEL", spec)], [("--json", tmp_path / "r.json")]):
        write_atomic(tmp_path / "r.json", "{}")
        with pytest.raises(InputError, match="written twice"):
            write_atomic(tmp_path / "r.json", "{}")
        with pytest.raises(InputError, match="an input of this run"):
            write_atomic(spec, "y")
    assert spec.read_text() == "x"
    assert check_target(tmp_path / "new.json") == (tmp_path / "new.json").resolve()
    plan = OutputPlan()
    plan.claim(tmp_path / "a", "--json")
    plan.claim(tmp_path / "a", "--json")  # the same output claimed again (a pre-check, then the write)
    with pytest.raises(InputError, match="name the same file"):
        plan.claim(tmp_path / "sub" / ".." / "a", "--report")


def test_a_replaced_file_keeps_its_permissions_and_a_symlinked_output_keeps_its_link(tmp_path):
    target = tmp_path / "r.json"
    target.write_text("old")
    target.chmod(0o640)
    link = tmp_path / "link.json"
    link.symlink_to(target)
    write_atomic(link, "new")
    assert link.is_symlink() and target.read_text() == "new" and (target.stat().st_mode & 0o777) == 0o640


def _limit_file_size():
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # a write beyond the limit fails with EFBIG instead of killing
    resource.setrlimit(resource.RLIMIT_FSIZE, (20_000, 20_000))


def test_a_write_that_fails_part_way_replaces_nothing(work):
    Path("r.json").write_text("previous results\n")
    proc = subprocess.run(
        [sys.executable, "-m", "kinverify", "verify", "m.toml", *FAST, "--json", "r.json", "--report", "r.html"],
        capture_output=True,
        text=True,
        preexec_fn=_limit_file_size,
        timeout=600,
    )
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr.count("\n") == 1 and "Traceback" not in proc.stderr
    assert "r.json: cannot write: File too large; nothing was replaced" in proc.stderr
    assert Path("r.json").read_text() == "previous results\n"
    assert not Path("r.html").exists() and not list(work.glob(".*.tmp"))


@pytest.fixture
def full_disk(tmp_path):
    """A 16 kB tmpfs (needs root and a kernel that lets this process mount): a results JSON (~50 kB)
    does not fit."""
    mount = tmp_path / "small"
    mount.mkdir()
    if (
        os.geteuid() != 0
        or subprocess.run(["mount", "-t", "tmpfs", "-o", "size=16k", "tmpfs", str(mount)], capture_output=True).returncode != 0
    ):
        pytest.skip("cannot mount a small tmpfs here")
    yield mount
    subprocess.run(["umount", str(mount)], check=True)


def test_a_full_disk_is_an_error_and_replaces_nothing(work, full_disk, capsys):
    target = full_disk / "r.json"
    target.write_text("previous results\n")
    refused(
        capsys,
        ["verify", "m.toml", *FAST, "--json", str(target), "--report", str(full_disk / "r.html")],
        "cannot write: No space left on device; nothing was replaced",
    )
    assert target.read_text() == "previous results\n"
    assert sorted(p.name for p in full_disk.iterdir()) == ["r.json"]


def test_a_model_name_cannot_steer_a_default_output_out_of_reports(work, capsys):
    assert default_output("../../x", ".json") == "reports/_.._x.json"
    assert default_output("arm3", ".html") == "reports/arm3.html" and default_output("", ".json") == "reports/model.json"
    Path("inner").mkdir()
    hostile = "../../escaped"
    Path("inner/u.urdf").write_text(Path("u.urdf").read_text().replace('<robot name="arm3">', f'<robot name="{hostile}">'))
    Path("inner/r.xml").write_text(Path("r.xml").read_text().replace('<mujoco model="arm3">', f'<mujoco model="{hostile}">'))
    os.chdir("inner")
    assert main(["verify", "--urdf", "u.urdf", "--mjcf", "r.xml", "--samples", "0", "--quiet"]) == 0
    capsys.readouterr()
    assert sorted(p.name for p in Path("reports").iterdir()) == ["_.._escaped.html", "_.._escaped.json"]
    assert not list(work.glob("escaped*")) and not list(work.parent.glob("escaped*"))
