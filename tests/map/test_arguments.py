"""``kinverify map`` with hostile arguments (tolerances, keyframes, tables, output paths that are
inputs, folders or devices): exit 0, 1 or 2, one line, no traceback, the inputs untouched."""

from __future__ import annotations

import tempfile
from pathlib import Path

from hypothesis import given
from hypothesis import strategies as st

from tests.fuzz.harness import fuzz_settings, run_checked
from tests.map import robot

TABLES = [
    'units = "degree"\n[actuators.a]\njoint_names_expr = [".*"]\nstiffness = 1e308\n',
    '[actuators.a]\njoint_names_expr = ["(("]\n',
    "actuators: [1, 2]\n",
    "",
    "{{{",
    "[joints.'.*']\narmature = -1\n",
    'init_state:\n  joint_pos: {".*": .nan}\n',
]
OPTIONS = st.lists(
    st.one_of(
        st.tuples(st.just("--rtol"), st.sampled_from(["nan", "inf", "0", "-1", "0.5", "abc", "1e-12"])),
        st.tuples(st.just("--keyframe"), st.sampled_from(["home", "", "nope", "#0"])),
        st.tuples(st.just("--json"), st.sampled_from(["IN_URDF", "DIR", "/dev/null", "OUT/map.json", "missing/deep/x.json"])),
        st.tuples(
            st.just("--actuators"),
            st.sampled_from(["TABLE0", "TABLE1", "TABLE2", "TABLE3", "TABLE4", "TABLE5", "TABLE6", "DIR", "IN_URDF"]),
        ),
    ),
    max_size=3,
)


@fuzz_settings(12)
@given(options=OPTIONS)
def test_hostile_arguments_exit_0_1_or_2_with_one_line(capfd, options):
    with tempfile.TemporaryDirectory() as folder:
        tmp = Path(folder)
        urdf, mjcf = robot.write(tmp, arm_urdf=robot.urdf(), arm_xml=robot.mjcf())
        tables = {
            f"TABLE{k}": robot.write(tmp, **{f"t{k}_{'yaml' if k >= 2 else 'toml'}": text})[0] for k, text in enumerate(TABLES)
        }
        (tmp / "dir").mkdir()
        (tmp / "out").mkdir()
        names = {
            "IN_URDF": urdf,
            "DIR": str(tmp / "dir"),
            "OUT/map.json": str(tmp / "out" / "map.json"),
            "missing/deep/x.json": str(tmp / "missing" / "deep" / "x.json"),
            **tables,
        }
        argv = ["map", urdf, mjcf]
        for flag, value in options:
            argv += [flag, names.get(value, value)]
        try:
            run_checked(capfd, argv, [Path(urdf), Path(mjcf)], tmp / "out")
        except SystemExit as exc:  # argparse's own refusals (a tolerance that is not a number in (0, 1))
            err = capfd.readouterr().err
            assert exc.code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
