"""Errors relayed from a library keep the library's reason, on one line: MuJoCo (reason first,
element after), Pinocchio's URDF parser (reason printed on stderr) and MJCF parser (reason after
C++ source locations), through the backends and through ``kinverify verify`` (real libraries)."""

from __future__ import annotations

import pytest

from kinverify.backends.mujoco_ import MujocoBackend
from kinverify.backends.pinocchio_ import PinocchioBackend, build_urdf_model
from kinverify.cli import main
from kinverify.errors import BackendError, library_reason

# a geom of size 0: MuJoCo says why on its first line and where on its second
ZERO_GEOM = """<mujoco model="r"><worldbody><body name="b"><joint name="j" type="hinge"/>
<geom name="if_tip" type="sphere" size="0"/></body></worldbody></mujoco>"""
NO_LIMITS = """<robot name="r"><link name="a"/><link name="b"/>
<joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint></robot>"""


def test_mujoco_keeps_its_reason_and_where(tmp_path):
    with pytest.raises(BackendError) as err:
        MujocoBackend.from_mjcf(ZERO_GEOM, ["j"], ["b"])
    message = str(err.value)
    assert "size 0 must be positive in geom" in message and "Element name 'if_tip'" in message and "\n" not in message


def test_verify_on_an_mjcf_mujoco_refuses_names_the_reason_on_one_line(tmp_path, capsys):
    path = tmp_path / "x.xml"
    path.write_text(ZERO_GEOM)
    assert main(["verify", "--mjcf", str(path), "--json", str(tmp_path / "r.json"), "--report", str(tmp_path / "r.html")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert f"cannot load {path}: size 0 must be positive in geom; Element name 'if_tip'" in err


def test_pinocchio_urdf_refusal_carries_the_reason_it_printed(capfd):
    with pytest.raises(BackendError) as err:
        PinocchioBackend.from_urdf(NO_LIMITS, ["j"], ["b"])
    message = str(err.value)
    assert "Joint [j] is of type REVOLUTE but it does not specify limits" in message and "\n" not in message
    assert "urdfdom" not in message and "at line" not in message  # the parser's own source locations are dropped
    assert "does not specify limits" not in capfd.readouterr().err  # said once, in the error, not on the terminal too


def test_pinocchio_urdf_that_loads_passes_its_printed_warnings_on(capfd):
    model = build_urdf_model('<robot name="r"><link name="a"/></robot>')
    assert model.nq == 0 and capfd.readouterr().err == ""


def test_pinocchio_mjcf_refusal_keeps_the_message_not_the_cpp_location():
    with pytest.raises(BackendError) as err:
        PinocchioBackend.from_mjcf("<mujoco><nothing/></mujoco>", ["j"], ["b"])
    message = str(err.value)
    assert "no body found" in message and "From file" not in message and "in function" not in message


@pytest.mark.parametrize(
    "said, reason",
    [
        (
            "Error: size 0 must be positive in geom\nElement name 'tip', id 25, line 199\n",
            "size 0 must be positive in geom; Element name 'tip', id 25, line 199",
        ),
        (
            "From file: /x/mjcf-graph.cpp\nin function: void f()\nat line: 962\nmessage:\nNot a standard model.\n",
            "Not a standard model.",
        ),
        ("Error:   Joint [j] has no limits\n         at line 607 in /p/joint.cpp\n", "Joint [j] has no limits"),
        ("XML Error: unknown element\n  line 3", "XML Error: unknown element; line 3"),
    ],
)
def test_library_reason_joins_lines_and_drops_source_locations(said, reason):
    assert library_reason(ValueError(said)) == reason


def test_a_library_error_that_says_nothing_is_named_by_its_type():
    assert library_reason(KeyError()) == "KeyError" and library_reason(RuntimeError("  \n ")) == "RuntimeError"
