"""A URDF or MJCF that no library may see: links that do not form one tree (a cycle crashed
Pinocchio: exit 139, no message), non-finite poses and axes, joint types URDF does not have,
MJCF includes that loop, repeat or are not MJCF. Every command that reads the file refuses it
with one line naming the file and the joint, link or attribute (exit 2), before any library
reads it; ``ik --urdf`` never walks a cycle."""

from __future__ import annotations

import json
import re

import pytest
from hypothesis import given, note
from hypothesis import strategies as st

from tests.fuzz.conftest import FILES
from tests.fuzz.harness import fuzz_settings, refused

LOOP = '<joint name="loop" type="fixed"><parent link="link3"/><child link="base"/></joint>\n</robot>'
COMMANDS = {  # every command that reads a URDF, with X for it
    "verify pair": ["verify", "--urdf", "X", "--mjcf", "r.xml", *FILES],
    "audit": ["verify", "--urdf", "X", *FILES],
    "diff": ["diff", "X", "u.urdf", "--report", "out/d.html"],
    "ik": ["ik", "--urdf", "X", "--tip", "link3", "--target", "0.2", "0.1", "0.6"],
    "ik --per-target": ["ik", "--urdf", "X", "--tip", "link3", "--targets", "t.npy", "--per-target"],
    "check": ["check", "X", "--samples", "0", "--suites", "kinematics"],
}
URDF_CASES = {
    "cycle": (lambda u: u.replace("</robot>", LOOP), "link 'base' is the child of two joints ('world_to_base' and 'loop')"),
    "cycle without a root": (
        lambda u: u.replace('<link name="world"/>', "").replace(
            '<joint name="world_to_base" type="fixed">\n    <parent link="world"/>',
            '<joint name="world_to_base" type="fixed">\n    <parent link="end_effector"/>',
        ),
        "the joints form a cycle",
    ),
    "two parents": (
        lambda u: u.replace(
            "</robot>", '<joint name="again" type="fixed"><parent link="base"/><child link="link2"/></joint></robot>'
        ),
        "link 'link2' is the child of two joints",
    ),
    "missing link": (
        lambda u: u.replace(
            "</robot>", '<joint name="ghost" type="fixed"><parent link="link3"/><child link="nowhere"/></joint></robot>'
        ),
        "joint 'ghost': its child link 'nowhere'",
    ),
    "orphan": (lambda u: u.replace("</robot>", '<link name="orphan"/></robot>'), "'orphan' are all roots"),
    "ball joint": (
        lambda u: u.replace('name="joint2" type="revolute"', 'name="joint2" type="ball"'),
        "joint 'joint2' has type 'ball': unsupported",
    ),
    "NaN origin": (
        lambda u: re.sub(r'(name="joint2".*?<origin xyz=")[^ ]+', r"\1nan", u, flags=re.S),
        "joint 'joint2' <origin>: xyz='nan",
    ),
    "inf axis": (
        lambda u: re.sub(r'(name="joint3".*?<axis xyz=")[^"]+', r"\g<1>0 inf 0", u, flags=re.S),
        "joint 'joint3' <axis>: xyz='0 inf 0' is not 3 finite numbers",
    ),
    "NaN limit": (lambda u: re.sub(r'(name="joint1".*?<limit lower=")[^"]+', r"\1NaN", u, flags=re.S), "lower='NaN'"),
    "joint named twice": (lambda u: u.replace('name="joint3"', 'name="joint2"', 1), "joint 'joint2' is defined twice"),
    "link named twice": (
        lambda u: u.replace('<link name="end_effector"/>', '<link name="link3"/>'),
        "link 'link3' is defined twice",
    ),
    "text mass": (
        lambda u: re.sub(r'<mass value="[^"]*"', '<mass value="abc"', u, count=1),
        "link 'base' <mass>: value='abc' is not a number",
    ),
    "text origin": (
        lambda u: re.sub(r'(name="joint1".*?<origin xyz=")[^"]+', r"\1one two three", u, flags=re.S),
        "xyz='one two three'",
    ),
}


@pytest.mark.parametrize("case", sorted(URDF_CASES))
@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_a_urdf_that_is_not_one_tree_of_finite_poses_is_refused_by_every_command(capfd, work, command, case):
    mangle, words = URDF_CASES[case]
    text = mangle((work / "u.urdf").read_text())
    assert text != (work / "u.urdf").read_text()
    (work / "bad.urdf").write_text(text)
    refused(capfd, ["bad.urdf" if a == "X" else a for a in COMMANDS[command]], work, "bad.urdf", words)


@fuzz_settings(20)
@given(st.data())
def test_any_extra_joint_between_two_links_of_an_arm_is_refused_before_a_library_reads_it(capfd, work, data):
    """Adding a joint to a tree gives a link a second parent (or closes a cycle): never a crash."""
    urdf = (work / "u.urdf").read_text()
    links = re.findall(r'<link name="([^"]+)"', urdf)
    parent, child = data.draw(st.sampled_from(links)), data.draw(st.sampled_from(links))
    kind = data.draw(st.sampled_from(["fixed", "revolute", "continuous"]))
    note(f"{parent} -> {child} ({kind})")
    extra = (
        f'<joint name="extra" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
        '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
    )
    (work / "bad.urdf").write_text(urdf.replace("</robot>", extra + "</robot>"))
    command = data.draw(st.sampled_from(["verify pair", "diff", "ik"]))
    refused(capfd, ["bad.urdf" if a == "X" else a for a in COMMANDS[command]], work, "bad.urdf", f"'{child}'")


MJCF_CASES = {
    "NaN axis": (lambda m: m.replace('axis="0.0 1.0 0.0"', 'axis="nan 1.0 0.0"', 1), "<joint name='joint2'>: axis='nan 1.0 0.0'"),
    "inf pos": (
        lambda m: m.replace('<body name="link1" pos="0.0 0.0 0.1">', '<body name="link1" pos="0 0 inf">'),
        "<body name='link1'>: pos='0 0 inf'",
    ),
    "NaN range": (lambda m: m.replace('range="-3.141592653589793 3.141592653589793"', 'range="nan 1"', 1), "range='nan 1'"),
    "include missing": (
        lambda m: m.replace("<worldbody>", '<include file="absent.xml"/><worldbody>', 1),
        "<include file='absent.xml'>",
    ),
    "include itself": (
        lambda m: m.replace("<worldbody>", '<include file="bad.xml"/><worldbody>', 1),
        "bad.xml is included twice",
    ),
    "include a URDF": (lambda m: m.replace("<worldbody>", '<include file="u.urdf"/><worldbody>', 1), "is not MJCF"),
    "include twice": (
        lambda m: m.replace("<worldbody>", '<include file="inc.xml"/><include file="inc.xml"/><worldbody>', 1),
        "inc.xml is included twice",
    ),
}


@pytest.mark.parametrize("case", sorted(MJCF_CASES))
@pytest.mark.parametrize("command", ["verify pair", "audit", "diff"])
def test_an_mjcf_with_non_finite_poses_or_bad_includes_is_refused(capfd, work, command, case):
    mangle, words = MJCF_CASES[case]
    (work / "bad.xml").write_text(mangle((work / "r.xml").read_text()))
    argv = {
        "verify pair": ["verify", "--urdf", "u.urdf", "--mjcf", "bad.xml", *FILES],
        "audit": ["verify", "--mjcf", "bad.xml", *FILES],
        "diff": ["diff", "r.xml", "bad.xml", "--report", "out/d.html"],
    }[command]
    refused(capfd, argv, work, "bad.xml", words)


def test_an_mjcf_include_is_read_from_the_model_folder_whatever_the_current_folder(capfd, work, monkeypatch):
    """MuJoCo reads an include relative to the main file; kinverify expands it itself (through its
    reader), so the run does not depend on the current folder."""
    from kinverify.cli import main

    (work / "sub").mkdir()
    monkeypatch.chdir(work / "sub")
    assert main(["verify", "--urdf", "../u.urdf", "--mjcf", "../main.xml", *FILES, "--json", "r.json"]) == 0, capfd.readouterr()
    assert (work / "sub" / "r.json").exists()


def test_an_include_loop_through_two_files_is_refused(capfd, work):
    (work / "a.xml").write_text('<mujoco><include file="b.xml"/></mujoco>')
    (work / "b.xml").write_text('<mujoco><include file="a.xml"/></mujoco>')
    (work / "bad.xml").write_text((work / "r.xml").read_text().replace("<worldbody>", '<include file="a.xml"/><worldbody>', 1))
    refused(capfd, ["verify", "--mjcf", "bad.xml", *FILES], work, "bad.xml", "a.xml is included twice")


def test_a_library_complaining_on_the_terminal_is_not_heard_there(capfd, work, monkeypatch):
    """urdfdom (Pinocchio's URDF parser) prints "Error: Inertial element must have inertia element
    at line 387 in /project/urdfdom/..." to file descriptor 2; MuJoCo's importer refuses the file.
    The run reports the refusal as a finding; the terminal shows kinverify's lines only (with
    KINVERIFY_DEBUG=1, the libraries' too)."""
    from kinverify.cli import main

    (work / "quiet.urdf").write_text(re.sub(r"<inertia [^>]*/>", "", (work / "u.urdf").read_text(), count=1))
    argv = ["verify", "--urdf", "quiet.urdf", *FILES, "--json", "out/r.json", "--report", "out/r.html"]
    capfd.readouterr()
    assert main(argv) in (0, 1)
    assert capfd.readouterr().err == ""
    refusals = [
        f["message"] for f in json.loads((work / "out" / "r.json").read_text())["findings"] if f["kind"] == "parser_refused"
    ]
    assert any("refuses the URDF" in m for m in refusals), refusals
    monkeypatch.setenv("KINVERIFY_DEBUG", "1")
    assert main(argv) in (0, 1)
    assert "Error:   Inertial element must have inertia element" in capfd.readouterr().err  # what was kept off
