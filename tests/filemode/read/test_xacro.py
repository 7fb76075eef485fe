"""xacro input: a ROS-style description package (macros from ``$(find pkg)``, expressions,
``<xacro:arg>``, ``package://`` meshes) compiles to the URDF kinverify generates for the same
arm; what xacro cannot resolve is one line naming the file."""

from __future__ import annotations

import json
import os
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from kinverify.errors import InputError
from kinverify.filemode.read.xacro import XACRO_NAMESPACE, _compile, _out_of_memory, compile_xacro, is_xacro, parse_pairs
from kinverify.io.plan import output_plan
from xacrodoc import packages as xpackages
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import load_spec
from tests.paths import MODELS, ROOT
from kinverify.cli import main

PACKAGE = ROOT / "tests" / "data" / "xacro" / "my_arm_description"
XACRO = PACKAGE / "urdf" / "arm3.urdf.xacro"


def _joints(urdf: str) -> dict[str, dict]:
    out = {}
    for j in ET.fromstring(urdf).iter("joint"):
        limit, origin = j.find("limit"), j.find("origin")
        out[j.get("name")] = {
            "type": j.get("type"),
            "origin": origin.get("xyz") if origin is not None else None,
            "limits": None if limit is None else (float(limit.get("lower")), float(limit.get("upper"))),
        }
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


@pytest.mark.parametrize(
    "body, words",
    [
        ('<xacro:nope a="1"/>', "unknown macro name: xacro:nope"),
        (
            '<xacro:include filename="$(find nowhere_pkg)/x.xacro"/>',
            "xacro package 'nowhere_pkg' not found (give it with --package",
        ),
        ('<link name="${undefined_thing}"/>', "name 'undefined_thing' is not defined"),
    ],
)
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


# --- wired in: verify (file mode and one-file audit) and ik read xacro -------------------------


def _verify(tmp_path, capsys, *argv) -> tuple[int, dict, str]:
    out = tmp_path / "out.json"
    code = main(["verify", *argv, "--samples", "20", "--quiet", "--json", str(out), "--report", str(tmp_path / "out.html")])
    captured = capsys.readouterr()
    return code, (json.loads(out.read_text()) if out.exists() else {}), captured.err.strip()


def test_the_example_verifies_against_the_mjcf_kinverify_generates_for_arm3(tmp_path, capsys):
    mjcf = tmp_path / "arm3.xml"
    mjcf.write_text(generate_mjcf(load_spec(MODELS / "arm3.toml")))
    code, data, _ = _verify(
        tmp_path, capsys, "--urdf", str(XACRO), "--mjcf", str(mjcf), "--package", f"my_arm_description={PACKAGE}"
    )
    assert code == 0 and data["verdict"] == "pass" and not [f for f in data["findings"] if f["severity"] == "error"]
    assert any("compiled from xacro" in n for n in data["notes"])


def test_the_example_audited_alone_with_an_argument(tmp_path, capsys):
    code, data, _ = _verify(tmp_path, capsys, "--urdf", str(XACRO), "--xacro-arg", "table_height=0.5")
    assert code == 0 and data["verdict"] == "pass" and len(data["backends"]) >= 2
    base = next(j for j in ET.fromstring(data["model_info"]["urdf"]).iter("joint") if j.get("name") == "world_to_base")
    assert base.find("origin").get("xyz") == "0.0 0.0 0.5"  # the argument reached the compiled URDF


@pytest.mark.parametrize(
    "argv, words",
    [
        (["--package", "my_arm_description=/no/such/folder"], "--package my_arm_description=/no/such/folder: not a folder"),
        (["--package", "oops"], "--package: expected NAME=VALUE"),
    ],
)
def test_bad_packages_are_one_line_exit_2(tmp_path, capsys, argv, words):
    code, data, err = _verify(tmp_path, capsys, "--urdf", str(XACRO), *argv)
    assert code == 2 and words in err and "\n" not in err and not data


def test_an_unresolved_package_or_macro_is_one_line_naming_the_file(tmp_path, capsys):
    path = tmp_path / "r.urdf.xacro"
    path.write_text(
        '<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:include filename="$(find nowhere_pkg)/x.xacro"/></robot>'
    )
    code, _, err = _verify(tmp_path, capsys, "--urdf", str(path))
    assert code == 2 and str(path) in err and "'nowhere_pkg' not found" in err and "\n" not in err
    plain = tmp_path / "plain.urdf"
    plain.write_text(generate_urdf(load_spec(MODELS / "arm3.toml")))
    code, _, err = _verify(tmp_path, capsys, "--urdf", str(plain), "--xacro-arg", "a=1")
    assert code == 2 and "is not a xacro file" in err


def test_ik_solves_on_the_compiled_chain(capsys):
    code = main(
        ["ik", "--urdf", str(XACRO), "--tip", "link3", "--target", "0.1", "0.1", "0.9", "--xacro-arg", "table_height=0.5"]
    )
    out = capsys.readouterr().out
    assert code in (0, 1) and "root -> link3" in out and "3 joints" in out


def test_diff_compiles_xacro_and_finds_the_generated_arm3(tmp_path, capsys):
    plain = tmp_path / "arm3.urdf"
    plain.write_text(generate_urdf(load_spec(MODELS / "arm3.toml")))
    report = str(tmp_path / "d.html")
    assert main(["diff", str(XACRO), str(plain), "--samples", "10", "--report", report]) == 0
    assert "IDENTICAL" in capsys.readouterr().out
    assert main(["diff", str(XACRO), str(plain), "--samples", "10", "--report", report, "--xacro-arg", "table_height=0.5"]) == 1


# --- the compiler's own decisions, called in this process (compile_xacro runs them in a child) ---


def _xacro_file(tmp_path, body: str) -> Path:
    path = tmp_path / "r.urdf.xacro"
    path.write_text(f'<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">{body}</robot>')
    return path


def test_compiling_gives_the_text_what_xacro_printed_and_every_file_it_read():
    xpackages.reset()  # no package known: $(find) and package:// are resolved by walking up from the file
    text, printed, read = _compile(XACRO, {"table_height": "0.5"})
    xpackages.reset()
    assert "package://" not in text and f"file://{PACKAGE}/meshes/base.stl" in text
    assert 'xyz="0.0 0.0 0.5"' in text and printed == ""
    assert read == [str(XACRO), str(PACKAGE / "urdf" / "macros.xacro")]


def test_what_the_child_read_is_an_input_of_the_run_named_by_the_file():
    with output_plan() as plan:
        compile_xacro(XACRO, {"my_arm_description": str(PACKAGE)})
    label = f"{XACRO}: xacro include"
    assert [(f.label, f.path) for f in plan.inputs] == [(label, XACRO), (label, PACKAGE / "urdf" / "macros.xacro")]


def test_xacros_warnings_are_kept_and_nothing_else_it_prints(tmp_path):
    path = _xacro_file(tmp_path, '<xacro:property name="pi" value="3"/><link name="l${pi}"/>')
    text, warnings = compile_xacro(path)
    assert warnings == ["xacro: warning: redefining global symbol: pi"] and '<link name="l3"/>' in text
    _, printed, _ = _compile(path, None)
    assert printed.splitlines()[0] == "warning: redefining global symbol: pi" and "when processing file" in printed


@pytest.mark.parametrize(
    "body, words",
    [
        ('<xacro:nope a="1"/>', "xacro cannot compile it: unknown macro name: xacro:nope"),
        (
            '<xacro:include filename="$(find nowhere_pkg)/x.xacro"/>',
            "xacro package 'nowhere_pkg' not found (give it with --package NAME=PATH)",
        ),
        ('<link name="$(arg side)"/>', "side"),
    ],
)
def test_a_file_xacro_cannot_compile_is_one_input_error_naming_it(tmp_path, body, words):
    path = _xacro_file(tmp_path, body)
    with pytest.raises(InputError) as info:
        _compile(path, {})
    assert str(info.value).startswith(f"{path}: ") and words in str(info.value) and "\n" not in str(info.value)
    assert type(info.value) is InputError and info.value.__cause__ is None


def test_an_argument_given_reaches_the_expression():
    text, _, _ = _compile(XACRO, {"table_height": "0.25"})
    assert 'xyz="0.0 0.0 0.25"' in text


def test_a_memory_error_is_found_behind_what_xacro_wraps_it_in():
    def chained(depth: int, cause: BaseException, how: str = "__cause__") -> BaseException:
        err = cause
        for _ in range(depth):
            outer = RuntimeError("wrapped")
            setattr(outer, how, err)
            err = outer
        return err

    assert _out_of_memory(MemoryError())
    assert _out_of_memory(chained(1, MemoryError())) and _out_of_memory(chained(3, MemoryError(), "__context__"))
    assert _out_of_memory(chained(19, MemoryError()))  # 20 links looked at: the 20th is the MemoryError
    assert not _out_of_memory(chained(20, MemoryError()))  # deeper than that is not looked for
    assert not _out_of_memory(chained(2, ValueError())) and not _out_of_memory(None)
    loop = RuntimeError("a loop")
    loop.__cause__ = loop
    assert not _out_of_memory(loop)  # ends


def test_the_xacro_namespace_counts_in_the_files_first_4096_characters_only():
    head = '<robot name="r">'
    declared = f'<robot name="r" xmlns:xacro="{XACRO_NAMESPACE}">'
    assert is_xacro("r.urdf", declared + "<!-- " + "x" * 5000 + ' -->${a}<link name="b"/></robot>')
    last = 4096 - declared.index(XACRO_NAMESPACE) - len(XACRO_NAMESPACE)  # ends at character 4096: counted; one later: not
    assert is_xacro("r.urdf", " " * last + declared + '<link name="${a}"/></robot>')
    assert not is_xacro("r.urdf", " " * (last + 1) + declared + '<link name="${a}"/></robot>')
    assert not is_xacro(
        "r.urdf",
        head + "</robot>",
    ) and not is_xacro("r.urdf")
    assert not is_xacro("r.urdf", declared + '<!-- <xacro:macro name="m"/> ${a} --><link name="b"/></robot>')
    assert is_xacro(Path("r.xacro")) and not is_xacro(Path("r.urdf"), None)


def test_an_included_file_kinverify_will_not_read_is_the_input_error_its_reader_gives(tmp_path):
    os.mkfifo(tmp_path / "pipe.xacro")
    path = _xacro_file(tmp_path, f'<xacro:include filename="{tmp_path}/pipe.xacro"/>')
    with pytest.raises(InputError) as info:
        _compile(path, {})
    assert str(info.value).startswith(f"{path}: xacro include: {tmp_path}/pipe.xacro is a FIFO")
    assert type(info.value) is InputError and info.value.__suppress_context__


def test_a_relative_include_is_read_beside_the_file_whatever_compiled_before(tmp_path):
    """xacro keeps the stack of files it is in as a module global: a relative include is found
    beside the file on top, the working folder when the stack is empty (a file compiled from
    elsewhere failed), or the file of an earlier compile that failed inside an include."""
    first, second = tmp_path / "first", tmp_path / "second"
    first.mkdir(), second.mkdir()
    (first / "part.xacro").write_text('<robot xmlns:xacro="http://www.ros.org/wiki/xacro">${undefined}</robot>')
    (second / "part.xacro").write_text('<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="b"/></robot>')
    with pytest.raises(InputError, match="undefined"):
        _compile(_xacro_file(first, '<xacro:include filename="part.xacro"/>'), {})
    text, _, read = _compile(_xacro_file(second, '<xacro:include filename="part.xacro"/>'), {})
    assert '<link name="b"' in text and read == [str(second / "r.urdf.xacro"), str(second / "part.xacro")]


def test_an_expression_that_runs_out_of_memory_is_a_memory_error_then_one_line(tmp_path):
    """[0] × 10^15 asks for 8 PB: refused at once, in this process a MemoryError, through
    compile_xacro (its child) one line naming the file."""
    path = _xacro_file(tmp_path, '<link name="${len([0] * (10**15))}"/>')
    with pytest.raises(MemoryError) as info:
        _compile(path, {})
    assert info.value.__suppress_context__
    with pytest.raises(InputError) as line:
        compile_xacro(path)
    message = str(line.value)
    assert message.startswith(f"{path}: xacro cannot compile it: its evaluation needed more than")
    assert message.endswith("(see docs/robustness.md)") and "\n" not in message


@pytest.mark.parametrize("item", ["=1", " =1", "a=", "a"])
def test_a_pair_needs_a_name_an_equals_sign_and_a_value(item):
    with pytest.raises(InputError, match=f"--xacro-arg: expected NAME=VALUE, got {item!r}"):
        parse_pairs([item], "--xacro-arg")
    assert parse_pairs([" a =1"], "--xacro-arg") == {"a": "1"} and parse_pairs(None, "--xacro-arg") == {}
