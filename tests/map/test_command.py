"""``kinverify map`` from the command line: the orders and maps of a shared real pair, the JSON for
deployment code, the exit codes of bad input; the map as a section of file mode's report."""

from __future__ import annotations

import json
import os
from pathlib import Path
from types import SimpleNamespace

import pytest

from kinverify.cli import main
from kinverify.filemode.pipeline import add_map
from kinverify.generate import generate_mjcf, generate_sdf, generate_urdf
from kinverify.model.specfile import load_spec
from tests.map import robot
from tests.paths import MODELS, REAL_ROBOTS

REAL = Path(os.environ.get("KINVERIFY_REAL_ROBOTS", REAL_ROBOTS))


def go2() -> list[str]:
    folder = REAL / "go2"
    if not folder.is_dir():
        pytest.skip(f"{folder} absent")
    return [str(folder / "go2_erd.urdf"), str(folder / "go2_menagerie.xml")]


def test_a_shared_pair_prints_both_orders_and_the_maps(tmp_path, capsys):
    out = tmp_path / "go2-map.json"
    assert main(["map", *go2(), "--keyframe", "home", "--json", str(out)]) == 0
    printed = capsys.readouterr().out
    for text in (
        "URDF declaration order",
        "MuJoCo qpos order",
        "go2_erd.urdf -> go2_menagerie.xml",
        "joints_to_actuators",
        "#11 qpos[18]",
        "FR_hip_joint",
    ):
        assert text in printed
    data = json.loads(out.read_text())
    assert data["sides"][0]["joints"][:3] == ["FL_hip_joint", "FL_thigh_joint", "FL_calf_joint"]
    assert data["sides"][1]["qpos_index"][0] == 7  # after the free base's 7 coordinates
    (to_ctrl,) = [m for m in data["maps"]["joints_to_actuators"] if m["from"] == "go2_erd.urdf"]
    assert to_ctrl["index"] == [3, 4, 5, 0, 1, 2, 9, 10, 11, 6, 7, 8]  # Menagerie's ctrl: FR, FL, RR, RL
    assert data["sides"][1]["values"]["FL_thigh_joint"]["default"] == 0.9  # the keyframe "home"
    assert data["verdict"] == "agree"


def test_three_generated_files_with_drake_agree(tmp_path, capsys):
    pytest.importorskip("pydrake")
    spec = load_spec(MODELS / "arm3.toml")
    paths = robot.write(tmp_path, arm_urdf=generate_urdf(spec), arm_xml=generate_mjcf(spec), arm_sdf=generate_sdf(spec))
    assert main(["map", *paths]) == 0
    printed = capsys.readouterr().out
    assert "Drake plant order" in printed and "AGREE" in printed


@pytest.mark.parametrize(
    "extra, table, message",
    [
        (["--keyframe", "stand"], None, "no such keyframe"),
        ([], 'units = "grad"\n[actuators.a]\njoint_names_expr = [".*"]\n', "units: expected 'radian' or 'degree'"),
        ([], '[actuators.a]\njoint_names_expr = ["nothing_.*"]\nstiffness = 1\n', "matches no joint"),
        ([], '[actuators.a]\njoint_names_expr = [".*"]\n[actuators.b]\njoint_names_expr = ["elbow"]\n', "in two actuator groups"),
        ([], '[actuators.a]\njoint_names_expr = [".*"]\nstiffnes = 1\n', "unknown key a.stiffnes"),
        ([], '[actuators.a]\njoint_names_expr = [".*"]\nstiffness = "high"\n', "expected a finite number"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, extra, table, message):
    paths = robot.write(tmp_path, arm_urdf=robot.urdf(), arm_xml=robot.mjcf())
    if table is not None:
        extra = ["--actuators", robot.write(tmp_path, t_toml=table)[0]]
    assert main(["map", *paths, *extra]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_one_file_alone_and_an_unknown_format_are_bad_input(tmp_path, capsys):
    (urdf, other) = robot.write(tmp_path, arm_urdf=robot.urdf(), notes_txt="hello")
    assert main(["map", urdf]) == 2
    assert main(["map", urdf, other]) == 2
    err = capsys.readouterr().err
    assert "two or more files" in err and "not a model kinverify map reads" in err


def test_a_yaml_table_in_isaac_lab_form_is_read(tmp_path):
    from kinverify.map.contract import MapOptions, map_files

    table = (
        "units: radian\nactuators:\n  arm:\n    joint_names_expr: ['shoulder', 'elbow', 'wrist']\n"
        "    stiffness: {'shoulder': 100.0, '.*': 50.0}\n    velocity_limit_sim: 3.0\n"
        "init_state:\n  joint_pos: {'elbow': 0.5}\n"
    )
    paths = robot.write(tmp_path, arm_urdf=robot.urdf(), t_yaml=table)
    with pytest.raises(Exception, match="several patterns"):
        map_files(paths[:1], MapOptions(actuators=paths[1]))
    paths = robot.write(tmp_path, t_yaml=table.replace("'.*': 50.0", "'elbow|wrist': 50.0"))
    result = map_files([str(tmp_path / "arm.urdf")], MapOptions(actuators=paths[0]))
    side = result.sides[1]
    assert (side.joint("shoulder").stiffness, side.joint("wrist").stiffness, side.joint("elbow").default) == (100.0, 50.0, 0.5)
    assert side.joint("finger_a").driven is None and side.joint("shoulder").velocity == 3.0


def test_file_mode_reports_carry_the_map_as_a_section(tmp_path):
    paths = robot.write(tmp_path, arm_urdf=robot.urdf(order=("elbow", "shoulder", "wrist")), arm_xml=robot.mjcf())
    result = SimpleNamespace(sections={}, notes=[], internal_errors=[])
    add_map(result, paths)
    section = result.sections["map"]
    assert section.tables[0].title.startswith("joint order") and section.tables[0].rows[0][0] == "elbow"
    assert section.data["maps"]["joints"][0]["index"] == [1, 0, 2, 3, 4]
    assert any("joint_order" in n for n in section.notes) and not result.internal_errors
    broken = robot.write(tmp_path, broken_xml="<mujoco><worldbody><body><joint/></body></worldbody>")
    add_map(result, [paths[0], broken[0]])
    assert result.notes and "map not made" in result.notes[0]


def test_menagerie_panda_gripper_tendon_and_inverse_equality_are_no_finding():
    """The URDF's finger_joint2 mimics finger_joint1; Menagerie's MJCF states the equality the other
    way round and drives both fingers through one tendon: the same coupling, no driven follower."""
    from kinverify.map.contract import map_files

    folder = REAL / "panda"
    if not folder.is_dir():
        pytest.skip(f"{folder} absent")
    result = map_files([str(folder / "panda_erd.urdf"), str(folder / "panda_menagerie.xml")])
    kinds = {f.kind for f in result.findings}
    assert not kinds & {"driven_follower", "coupling_difference", "coupling_one_file", "joint_order", "joint_missing"}
    assert result.maps["joints"][0]["index"] == list(range(9))
    (to_ctrl,) = [m for m in result.maps["joints_to_actuators"] if m["from"] == "panda_erd.urdf"]
    assert to_ctrl["index"] == [0, 1, 2, 3, 4, 5, 6, None]  # actuator8 drives the tendon "split"
    assert result.sides[1].joint("finger_joint1").stiffness is None  # a tendon's gains are no joint's


def test_without_drake_an_sdformat_file_is_read_in_declaration_order(tmp_path):
    from kinverify.filemode.read.loading import load_sdf
    from kinverify.map.sdf import declared_sdf

    (path,) = robot.write(tmp_path, arm3_sdf=generate_sdf(load_spec(MODELS / "arm3.toml")))
    side = declared_sdf(path, load_sdf(path))
    assert side.names == ["joint1", "joint2", "joint3"] and side.order == "SDFormat declaration order"
    assert (side.joint("joint1").effort, side.joint("joint1").velocity, side.joint("joint1").joint_damping) == (100.0, 3.0, 0.1)
    assert side.actuators is None
