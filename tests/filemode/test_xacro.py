"""xacro input: a ROS-style description package (macros from ``$(find pkg)``, expressions,
``<xacro:arg>``, ``package://`` meshes) compiles to the URDF kinverify generates for the same
arm; what xacro cannot resolve is one line naming the file."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest

from kinverify.errors import InputError
from kinverify.filemode.xacro import compile_xacro, is_xacro, parse_pairs
from kinverify.generate import generate_urdf
from kinverify.model.specfile import load_spec
from tests.paths import MODELS, ROOT

PACKAGE = ROOT / "tests" / "data" / "xacro" / "my_arm_description"
XACRO = PACKAGE / "urdf" / "arm3.urdf.xacro"


def _joints(urdf: str) -> dict[str, dict]:
    out = {}
    for j in ET.fromstring(urdf).iter("joint"):
        limit, origin = j.find("limit"), j.find("origin")
        out[j.get("name")] = {"type": j.get("type"), "origin": origin.get("xyz") if origin is not None else None,
                              "limits": None if limit is None else (float(limit.get("lower")), float(limit.get("upper")))}
    return out


def test_the_example_compiles_to_the_generated_arm3_urdf_joints():
    text, warnings = compile_xacro(XACRO, {"my_arm_description": str(PACKAGE)})
    assert warnings == []
    generated = _joints(generate_urdf(load_spec(MODELS / "arm3.toml")))
    compiled = _joints(text)
    assert compiled.keys() == generated.keys()
    for name, joint in generated.items():
        assert compiled[name]["type"] == joint["type"]
        assert compiled[name]["limits"] == pytest.approx(joint["limits"]) if joint["limits"] else compiled[name]["limits"] is None
    assert "package://" not in text  # resolved from --package


def test_arguments_and_walking_up_to_the_package():
    text, _ = compile_xacro(XACRO, args={"table_height": "0.5"})  # found from the file's folders, ROS style
    base = next(j for j in ET.fromstring(text).iter("joint") if j.get("name") == "world_to_base")
    assert base.find("origin").get("xyz") == "0.0 0.0 0.5"


@pytest.mark.parametrize("body, words", [
    ('<xacro:nope a="1"/>', "unknown macro name: xacro:nope"),
    ('<xacro:include filename="$(find nowhere_pkg)/x.xacro"/>', "xacro package 'nowhere_pkg' not found (give it with --package"),
    ('<link name="${undefined_thing}"/>', "name 'undefined_thing' is not defined"),
])
def test_what_xacro_cannot_resolve_is_one_line_naming_the_file(tmp_path, body, words):
    path = tmp_path / "r.urdf.xacro"
    path.write_text(f'<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">{body}</robot>')
    with pytest.raises(InputError) as info:
        compile_xacro(path)
    message = str(info.value)
    assert message.startswith(str(path)) and words in message and "\n" not in message


def test_options_and_detection():
    assert parse_pairs(["a=/x", "b=1=2"], "--package") == {"a": "/x", "b": "1=2"}
    with pytest.raises(InputError, match="--package: expected NAME=VALUE"):
        parse_pairs(["nope"], "--package")
    with pytest.raises(InputError, match="not a folder"):
        compile_xacro(XACRO, {"my_arm_description": "/no/such/folder"})
    declared = '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">'
    assert is_xacro("robot.urdf.xacro") and is_xacro("r.urdf", declared + '<xacro:property name="a" value="1"/></robot>')
    assert is_xacro("r.urdf", declared + '<link name="${prefix}base"/></robot>')
    assert not is_xacro("r.urdf", "<robot name='r'/>")
    assert not is_xacro("r.urdf", declared + '<link name="base"/></robot>')  # xacro's output keeps the declaration
