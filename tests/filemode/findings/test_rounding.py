"""Recognising rounded constants (1.5708 for π/2, 2.96706 for 170°, a value cut to fewer decimals)
and where the files write them: each rule pinned by the smallest written value where it and its
nearest wrong variant disagree."""

from __future__ import annotations

import math

import pytest

from kinverify.filemode.findings.rounding import _label, _quat, nice_constant, rounded_constants, rounded_from

HALF_PI = (math.pi / 2, "π/2")


@pytest.mark.parametrize(
    "k, label",
    [
        (1, "π/12"),
        (-1, "-π/12"),
        (3, "π/4"),
        (6, "π/2"),
        (-6, "-π/2"),
        (8, "2π/3"),
        (12, "π"),
        (-12, "-π"),
        (24, "2π"),
        (-24, "-2π"),
    ],
)
def test_label_of_a_multiple_of_fifteen_degrees(k, label):
    assert _label(k) == label


def test_rounded_from_names_the_exact_value_and_the_decimals_either_way():
    assert rounded_from(1.23456, 1.235) == {"exact": 1.23456, "rounded": 1.235, "decimals": 3}
    assert rounded_from(1.235, 1.23456) == {"exact": 1.23456, "rounded": 1.235, "decimals": 3}
    assert rounded_from(1.24, 1.2) == {"exact": 1.24, "rounded": 1.2, "decimals": 1}
    assert rounded_from(0.123456789, 0.12345679) == {"exact": 0.123456789, "rounded": 0.12345679, "decimals": 8}
    assert rounded_from(0.1234567891, 0.123456789) is None  # 9 decimals: beyond what is looked for
    assert rounded_from(1.5, 1.5) is None  # equal: nothing rounded
    assert rounded_from(1.4, 1.0) is None  # a whole number is not a value cut to fewer decimals
    assert rounded_from(1.23456, 1.236) is None  # not the rounding of each other


@pytest.mark.parametrize(
    "text, expected",
    [
        ("1.571", (HALF_PI, 3)),
        ("1.5708", (HALF_PI, 4)),
        ("1.57080", (HALF_PI, 5)),
        ("-1.5708", ((-math.pi / 2, "-π/2"), 4)),
        ("3.14159265", ((math.pi, "π"), 8)),
        ("2.96706", ((math.radians(170), "170°"), 5)),
        ("6.26573", ((math.radians(359), "359°"), 5)),
        ("0.01745", ((math.radians(1), "1°"), 5)),
        ("-2.96706", ((math.radians(-170), "-170°"), 5)),
    ],
)
def test_nice_constant_found(text, expected):
    assert nice_constant(float(text), text) == expected


@pytest.mark.parametrize(
    "text",
    [
        "1.57",  # 2 decimals: too few to tell
        "1.570796327",  # 9 decimals: written exactly enough
        "0.000",
        "1.5708e0",
        "1.5708E0",
        "157.08e-2",
        "157.08E-2",
        "15708",  # zero, an exponent, no decimals
        "6.30064",
        "-6.30064",  # 361°: beyond a whole turn
        "1.5709",  # not π/2 at 4 decimals
    ],
)
def test_nice_constant_none(text):
    assert nice_constant(float(text), text) is None


@pytest.mark.parametrize(
    "text, expected",
    [
        ("0.70711 0 0 0.70710", (HALF_PI, 5)),
        ("-0.70711 0 0 0.70710", (HALF_PI, 5)),
        ("0.70711 0 0 0.70709", (HALF_PI, 5)),  # 2.8e-5 off π/2: within 4 units of the last decimal
        ("0.70710678 0 0 0.70710677", (HALF_PI, 8)),
        ("0.70711 0 0.70710 0", (HALF_PI, 5)),
        ("0.707 0 0 0.708", (HALF_PI, 3)),
    ],
)
def test_quaternion_rounded_from_a_nice_angle(text, expected):
    assert _quat(text) == expected


@pytest.mark.parametrize(
    "text",
    [
        "0.70711 0 0 0.70708",  # 4.2e-5 off π/2: more than 4 units of the last decimal
        "0.71 0 0 0.71",
        "0.707106781 0 0 0.707106780",  # 2 and 9 decimals
        "0.500 0.500 0.500 0.500",  # exactly 2π/3: not rounded
        "1 0 0",
        "a b c d",
        "",
    ],
)
def test_quaternion_not_rounded(text):
    assert _quat(text) is None


URDF = """<robot>
  <link name="l1"><visual name="v"><origin rpy="0 1.5708 0"/></visual></link>
  <joint name="j1"><origin xyz="0 0 0.1" rpy="0 1.5708 0"/></joint>
  <joint name="j2"><origin rpy="0 0 0.5"/></joint>
  <joint name="j3"/>
  <joint name="j4"><origin xyz="0 0 0.1"/></joint>
</robot>"""


def mjcf(compiler: str) -> str:
    return f"""<mujoco>{compiler}<worldbody>
  <body name="a" euler="0 0 2.96706"><body name="b" quat="0.70711 0 0 0.70710"/></body>
  <body name="c" axisangle="1.5708 0 1 3.14159"><geom name="g" euler="0 0 1.5708" quat="0.70711 0 0 0.70710"/></body>
</worldbody></mujoco>"""


def test_rounded_constants_of_both_files_in_radians():
    found = list(rounded_constants(URDF, mjcf('<compiler angle="radian"/>')))
    assert found == [
        ("URDF", "j1", "1.5708", HALF_PI, 4),
        ("MJCF", "a", "2.96706", (math.radians(170), "170°"), 5),
        ("MJCF", "b", 'quat="0.70711 0 0 0.70710"', HALF_PI, 5),
        ("MJCF", "c", "3.14159", (math.pi, "π"), 5),  # the axis (1.5708 0 1) is no angle
    ]  # a link's visual, a body's geom: not the kinematics


@pytest.mark.parametrize("compiler", ['<compiler angle="degree"/>', "<compiler/>", ""])
def test_an_mjcf_in_degrees_has_no_rounded_radians(compiler):
    """MuJoCo reads angles in degrees unless the compiler says radian (also with no <compiler>)."""
    assert list(rounded_constants(URDF, mjcf(compiler))) == [("URDF", "j1", "1.5708", HALF_PI, 4)]
