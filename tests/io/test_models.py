"""The checks a model file passes before any library reads it, each refusal pinned with its
one-line message: a URDF is one tree of named links and joints (an undeclared ``world`` parent is
the world), its numbers are numbers (poses finite ones), an MJCF's poses and joint ranges are
finite numbers, and ``<include>`` files are expanded in place, named in their errors."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest

from kinverify.errors import InputError
from kinverify.io.models import check_mjcf_numbers, check_urdf_numbers, check_urdf_tree, expand_includes, tree_depth

LINK = '<link name="{}"/>'
JOINT = '<joint name="{}" type="revolute"><parent link="{}"/><child link="{}"/></joint>'


def urdf(*parts: str) -> ET.Element:
    return ET.fromstring("<robot>" + "".join(parts) + "</robot>")


def refused(call, *args) -> str:
    with pytest.raises(InputError) as err:
        call(*args)
    return str(err.value)


def test_a_tree_passes_and_an_undeclared_world_is_the_world():
    assert check_urdf_tree(urdf(LINK.format("a"), LINK.format("b"), JOINT.format("j", "a", "b")), "m.urdf") is None
    assert check_urdf_tree(urdf(LINK.format("a"), JOINT.format("fix", "world", "a")), "m.urdf") is None


def test_what_is_not_one_tree_is_refused():
    two_roots = urdf(LINK.format("a"), LINK.format("b"))
    assert refused(check_urdf_tree, two_roots, "m.urdf", "--urdf") == (
        "--urdf: m.urdf: links 'a', 'b' are all roots (no joint has them as child): a URDF is one tree"
    )
    assert refused(check_urdf_tree, urdf(), "m.urdf") == "m.urdf: no <link>"
    cycle = urdf(LINK.format("a"), LINK.format("b"), JOINT.format("j1", "a", "b"), JOINT.format("j2", "b", "a"))
    assert refused(check_urdf_tree, cycle, "m.urdf") == (
        "m.urdf: every link is a joint's child: the joints form a cycle ('a' -> 'b' -> 'a')"
    )
    nameless = urdf(LINK.format("a"), LINK.format("b"), '<joint type="fixed"><parent link="a"/><child link="b"/></joint>')
    assert refused(check_urdf_tree, nameless, "m.urdf") == "m.urdf: a <joint> has no name"


def test_urdf_numbers_are_numbers_and_poses_finite_ones():
    good = '<joint name="j" type="revolute"><origin xyz="0 0 1" rpy="0 0 0"/><mimic joint="k" multiplier="2"/></joint>'
    assert check_urdf_numbers(urdf(LINK.format("a"), good), "m.urdf") is None
    nan = urdf('<joint name="j" type="revolute"><origin xyz="0 0 nan"/></joint>')
    assert refused(check_urdf_numbers, nan, "m.urdf") == "m.urdf: joint 'j' <origin>: xyz='0 0 nan' is not 3 finite numbers"
    mimic = urdf('<joint name="j" type="revolute"><mimic joint="k" multiplier="x"/></joint>')
    assert refused(check_urdf_numbers, mimic, "m.urdf") == "m.urdf: joint 'j' <mimic>: multiplier='x' is not a number"
    box = urdf('<link name="a"><visual><geometry><box size="1 2"/></geometry></visual></link>')
    assert refused(check_urdf_numbers, box, "m.urdf") == "m.urdf: link 'a' <box>: size='1 2' is not 3 numbers"


def test_mjcf_poses_and_joint_ranges_are_finite_numbers():
    def mjcf(body: str) -> ET.Element:
        return ET.fromstring(f"<mujoco><worldbody>{body}</worldbody></mujoco>")

    assert check_mjcf_numbers(mjcf('<body pos="0 0 1"><joint name="j" range="-1 1"/></body>'), "m.xml") is None
    assert refused(check_mjcf_numbers, mjcf('<body pos="0 0 inf"/>'), "m.xml") == (
        "m.xml: <body>: pos='0 0 inf' is not 3 finite numbers"
    )
    assert refused(check_mjcf_numbers, mjcf('<body><joint name="j" range="1"/></body>'), "m.xml") == (
        "m.xml: <joint name='j'>: range='1' is not 2 finite numbers"
    )


def test_tree_depth():
    assert tree_depth(ET.fromstring("<a><b><c/></b><d/></a>")) == 3


def test_includes_are_expanded_in_place_and_named_in_their_errors(tmp_path):
    main = tmp_path / "main.xml"
    (tmp_path / "sub.xml").write_text('<mujoco><worldbody><body name="b"/></worldbody></mujoco>')
    root, files = expand_includes(ET.fromstring('<mujoco><include file="sub.xml"/></mujoco>'), main)
    assert [e.tag for e in root] == ["worldbody"] and files == [str(main.resolve()), str((tmp_path / "sub.xml").resolve())]
    assert refused(expand_includes, ET.fromstring("<mujoco><include/></mujoco>"), main) == f"{main}: an <include> has no file"
    (tmp_path / "bad.xml").write_text("<mujoco>")
    message = refused(expand_includes, ET.fromstring('<mujoco><include file="bad.xml"/></mujoco>'), main, "--mjcf")
    assert message.startswith(f"--mjcf: {main}: <include file='bad.xml'>: {tmp_path / 'bad.xml'} is not XML")
