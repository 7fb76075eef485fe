"""A library that ends the process or runs away cannot end the run: Drake's parsers are tried in a
bounded child process first and a parser that dies is a ``parser_refused`` warning naming Drake
and the reason, the other libraries going on (a pair whose robots agree still passes); xacro
evaluates in a child bounded in memory and time, so a runaway expression is one line naming the
file; a deleted current folder does not stop Drake (docs/robustness.md, libraries that crash)."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from kinverify.backends.drake_plant import load_plant
from kinverify.cli import main
from kinverify.errors import BackendError
from kinverify.generate import generate_sdf
from kinverify.io.isolate import LibraryDied, in_child
from kinverify.model.specfile import load_spec
from kinverify.pipeline import limits
from tests.fuzz.conftest import FILES, XACRO_NS
from tests.fuzz.harness import deadline, refused

MASSLESS = (
    '<mujoco model="m"><worldbody><body name="b"><joint type="hinge"/><inertial pos="0 0 0" mass="0" '
    'diaginertia="0 0 0"/><body name="c"><joint type="hinge"/><inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>'
    "</body></body></worldbody></mujoco>"
)


def test_a_drake_parser_that_ends_the_process_is_a_refusal_not_the_end_of_the_run():
    with pytest.raises(BackendError, match=r"Drake's MJCF parser ended the process: .*condition 'mass > 0' failed"):
        load_plant(MASSLESS, "mjcf", name="drake-mjcf")
    plant, _, _ = load_plant(MASSLESS.replace('mass="0" diaginertia="0 0 0"', 'mass="1" diaginertia="1 1 1"'), "mjcf")
    assert plant.num_bodies() == 3  # this process still parses


def test_a_child_that_dies_or_runs_away_is_reported_with_the_reason():
    assert in_child(lambda: 6 * 7) == 42
    with pytest.raises(LibraryDied, match="killed by SIGSEGV"):
        in_child(lambda: os.kill(os.getpid(), 11))
    with pytest.raises(LibraryDied, match="ran longer than 1 s"):
        in_child(lambda: sum(iter(int, 1)), seconds=1)  # zeros for ever
    with pytest.raises(LibraryDied, match="needed more than the 64 MB"):
        in_child(lambda: bytearray(2**30), memory=64 * 2**20)
    with pytest.raises(KeyError, match="raised as itself"):
        in_child(lambda: {}["raised as itself"])


@pytest.fixture
def massless_pair(work) -> Path:
    """arm3's URDF and MJCF with a massless link fixed to the end (as panda's panda_link8, which
    states mass 0): in the MJCF ``<inertial mass="0">``, as MuJoCo writes it, on which Drake aborts."""
    urdf = (
        (work / "u.urdf")
        .read_text()
        .replace(
            "</robot>",
            (
                '<link name="flange"><inertial><mass value="0"/><inertia ixx="0" iyy="0" izz="0" ixy="0" ixz="0" iyz="0"/></inertial>'
                '</link><joint name="flange_fix" type="fixed"><parent link="link3"/><child link="flange"/><origin xyz="0 0 0.05"/>'
                "</joint></robot>"
            ),
        )
    )
    body = '<body name="link3" pos="0.0 0.0 0.25">'
    mjcf = (work / "r.xml").read_text()
    assert body in mjcf
    mjcf = mjcf.replace(
        body, body + '<body name="flange" pos="0 0 0.05"><inertial pos="0 0 0" mass="0" diaginertia="0 0 0"/></body>', 1
    )
    (work / "massless.urdf").write_text(urdf)
    (work / "massless.xml").write_text(mjcf)
    return work


def test_a_pair_whose_mjcf_drake_cannot_parse_passes_when_the_robots_agree(capfd, massless_pair):
    capfd.readouterr()
    with deadline():
        code = main(["verify", "--urdf", "massless.urdf", "--mjcf", "massless.xml", *FILES, "--json", "out/r.json"])
    err = capfd.readouterr().err
    assert code == 0, err
    findings = json.loads((massless_pair / "out/r.json").read_text())["findings"]
    refusals = [f for f in findings if f["kind"] == "parser_refused"]
    assert len(refusals) == 1 and refusals[0]["severity"] == "warning", refusals
    assert "drake-mjcf" in refusals[0]["message"] and "mass > 0" in refusals[0]["message"]


def _xacro(folder: Path, expression: str) -> str:
    (folder / "bomb.urdf.xacro").write_text(
        f'<robot name="r" {XACRO_NS}><xacro:property name="v" value="${{{expression}}}"/><link name="a"><inertial>'
        '<mass value="${v}"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>\n'
    )
    return "bomb.urdf.xacro"


def test_a_xacro_expression_that_takes_all_memory_is_one_line_naming_the_file(capfd, work):
    name = _xacro(work, "len('x'*10**10)")
    refused(capfd, ["verify", "--urdf", name, *FILES], work, name, "needed more than the 512 MB of memory")


def test_a_xacro_expression_that_never_ends_is_stopped(capfd, work, monkeypatch):
    monkeypatch.setattr(limits, "LIBRARY_SECONDS", 1.0)  # the default (30 s) works alike, slower
    name = _xacro(work, "9**9**9")
    refused(capfd, ["verify", "--urdf", name, *FILES], work, name, "ran longer than 1 s")


def test_a_deleted_current_folder_does_not_stop_drake(capfd, work, tmp_path_factory):
    (work / "r.sdf").write_text(generate_sdf(load_spec(work / "m.toml")))
    gone = tmp_path_factory.mktemp("gone")
    os.chdir(gone)
    gone.rmdir()
    capfd.readouterr()
    with deadline():
        code = main(
            [
                "verify",
                "--urdf",
                str(work / "u.urdf"),
                "--sdf",
                str(work / "r.sdf"),
                *FILES,
                "--json",
                str(work / "out/r.json"),
                "--report",
                str(work / "out/r.html"),
            ]
        )
    err = capfd.readouterr().err
    assert code == 0, err
    assert (work / "out/r.json").is_file()
