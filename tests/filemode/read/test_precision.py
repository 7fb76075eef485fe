"""The precision each file is written with: a number of many digits is off by half its last digit,
a rounded multiple of π/12 by its distance to it, a designer's short number not at all; a URDF's
masses and inertias carry a relative rounding; an MJCF's sites in the world carry their own; the
first number found at the coarsest rounding is the example."""

from __future__ import annotations

import math

import pytest

from kinverify.filemode.read.precision import Floors, Precision, floors, mjcf_precision, quantum, rounding_of, urdf_precision


def test_the_rounding_of_a_written_number():
    assert rounding_of("0.9238795") == pytest.approx(0.5e-7)
    assert rounding_of("0.333") == 0.0 and rounding_of("0") == 0.0
    assert rounding_of("1.571", angle=True) == pytest.approx(abs(1.571 - math.pi / 2), abs=1e-15)
    assert rounding_of("0.785", angle=True) == pytest.approx(abs(0.785 - math.pi / 4), abs=1e-15)


def test_the_first_example_at_the_coarsest_rounding_is_kept():
    p = Precision("URDF")
    p.note("length", 1e-4, "0.12345")
    p.note("length", 1e-4, "0.54321")
    p.note("length", 1e-5, "0.543210")
    assert (p.length, p.examples["length"]) == (1e-4, "0.12345")


def test_a_urdf_mass_carries_a_relative_rounding():
    urdf = """<robot name="r"><link name="a"><inertial><mass value="1.23456"/>
      <inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link><link name="b"/></robot>"""
    p = urdf_precision(urdf)
    assert p.relative == pytest.approx(0.5e-5 / 1.23456) and p.examples["relative"] == "1.23456"
    assert p.frames == {"a": (0.0, 0.0), "b": (0.0, 0.0)}


def test_an_mjcf_site_in_the_world_carries_its_own_rounding():
    p = mjcf_precision('<mujoco><worldbody><site name="s" pos="0.1234567 0 0"/></worldbody></mujoco>')
    assert p.frames["s"] == pytest.approx((0.0, math.sqrt(3) * 0.5e-7))


# --- one written number ---------------------------------------------------------------------

D90 = abs(1.571 - math.pi / 2)  # a rounded right angle's distance to π/2
D45 = abs(0.785 - math.pi / 4)
DEG = math.pi / 180


@pytest.mark.parametrize(
    "word, found",
    [
        ("0.9238795", (1e-7, 7)),
        ("12.5", (0.1, 3)),
        ("-0.00120", (1e-5, 3)),
        ("+7", (1.0, 1)),
        ("1e-3", (1e-3, 1)),
        ("1.5E2", (10.0, 2)),
        (".25", (0.01, 2)),
        ("  3.0  ", (0.1, 2)),
    ],
)
def test_the_last_digit_and_the_significant_digits_of_a_written_number(word, found):
    q, digits = quantum(word)
    assert (q, digits) == (pytest.approx(found[0], rel=1e-12), found[1])


@pytest.mark.parametrize("word", ["", ".", "abc", "1e", "nan", "1.2.3", "--1"])
def test_what_is_not_a_written_number_has_no_quantum_and_no_rounding(word):
    assert quantum(word) is None and rounding_of(word) == 0.0 and rounding_of(word, angle=True) == 0.0


@pytest.mark.parametrize(
    "word, kwargs, expected",
    [
        ("12345", {}, 0.5),  # five significant digits: computed, then rounded
        ("1234", {}, 0.0),  # four: a designer's exact number
        ("0.012345", {}, 0.5e-6),  # leading zeros are not significant
        ("1.00000", {}, 0.5e-5),  # trailing zeros are
        ("0.000000", {}, 0.0),  # zero carries no rounding
        ("0.12345", {"scale": 2.0}, 1e-5),  # scale converts the unit
        ("1.571", {}, 0.0),  # a short number that is not an angle is exact
        ("1.571", {"angle": True}, D90),
        ("-1.571", {"angle": True}, D90),
        ("0.785", {"angle": True}, D45),
        ("1.57", {"angle": True}, abs(1.57 - math.pi / 2)),  # two decimals: still a rounded angle
        ("0.79", {"angle": True}, abs(0.79 - math.pi / 4)),  # just within half the last digit
        ("0.77", {"angle": True}, 0.0),  # farther from π/4 than half its last digit: exact
        ("1.6", {"angle": True}, 0.0),  # one decimal: a designer's angle
        ("1.57079633", {"angle": True}, abs(1.57079633 - math.pi / 2)),  # eight decimals
        ("1.570796327", {"angle": True}, 0.5e-9),  # nine: half the last digit
        ("1.5707963e0", {"angle": True}, abs(1.5707963 - math.pi / 2)),  # the exponent is not a decimal
        ("1571e-3", {"angle": True}, 0.0),  # no decimal point: not a rounded angle
        ("1.571", {"angle": True, "scale": 2.0}, 0.0),  # in degrees (scaled): not snapped to π/12
        ("0.05", {"angle": True}, 0.0),  # near no multiple of π/12 but zero
        ("90.00001", {"angle": True, "scale": DEG}, 0.5e-5 * DEG),
    ],
)
def test_how_far_a_written_number_may_be_from_what_it_stands_for(word, kwargs, expected):
    assert rounding_of(word, **kwargs) == pytest.approx(expected, rel=1e-9, abs=1e-18)


# --- a file's precision and its description ------------------------------------------------


def test_a_coarser_rounding_replaces_the_example_and_a_finer_one_does_not():
    p = Precision("MJCF")
    p.note("com", 1e-6, "0.123456")
    p.note("com", 1e-5, "0.12345")
    p.note("com", 1e-6, "0.654321")
    assert (p.com, p.examples) == (1e-5, {"com": "0.12345"})


def test_the_description_names_each_category_with_its_digits_and_example():
    p = Precision("URDF")
    p.note("angle", 4 * D90, "1.571")
    p.note("length", 1e-7, "0.1234567")
    p.note("relative", 1e-6, "1.23456")
    p.note("com", 0.5e-4, "12345")
    p.note("inertial_angle", 1e-3, "0.785")
    p.note("limit", 1e-3, "2.35619")
    assert p.describe() == (
        "the URDF writes frame orientations to 3 decimals (1.571), frame positions to 7 decimals (0.1234567), "
        "masses and inertias to 6 significant digits (1.23456), centres of mass to 0 decimals (12345), "
        "inertial orientations to 3 decimals (0.785), joint limits to 5 decimals (2.35619)"
    )
    assert p.describe(["limit", "relative"]) == (
        "the URDF writes joint limits to 5 decimals (2.35619), masses and inertias to 6 significant digits (1.23456)"
    )


def test_a_file_of_exact_values_says_so_and_an_example_without_rounding_is_not_named():
    p = Precision("MJCF")
    assert p.describe() == "the MJCF writes exact values"
    p.examples["angle"] = "1.5"  # an example whose rounding is 0
    p.note("length", 1e-5, "0.12345")
    assert p.describe() == "the MJCF writes frame positions to 5 decimals (0.12345)"
    assert p.describe(["angle"]) == "the MJCF writes exact values"


def test_a_number_with_a_positive_exponent_has_no_decimals():
    p = Precision("URDF")
    p.note("length", 50.0, "1.5e3")  # its last digit is the hundreds
    assert p.describe() == "the URDF writes frame positions to 0 decimals (1.5e3)"


# --- a URDF's precision ---------------------------------------------------------------------

S3 = math.sqrt(3)
CHAIN = """<robot name="r">
  <link name="base"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0.1234567 0 0" rpy="0 0 1.571"/><axis xyz="0 0 1"/><limit lower="-1.571" upper="0.5"/></joint>
  <link name="l1"/>
  <joint name="j2" type="prismatic"><parent link="l1"/><child link="l2"/>
    <origin xyz="0.12345 0 0"/><axis xyz="1 0 0"/><limit lower="-0.785" upper="0.5"/></joint>
  <link name="l2"/>
  <joint name="j3" type="fixed"><parent link="l2"/><child link="l3"/></joint>
  <link name="l3"/>
  <joint name="orphan" type="fixed"><child link="l4"/><origin xyz="0.1234567 0 0" rpy="0 0 1.571"/></joint>
  <link name="l4"/>
</robot>"""


def test_a_urdf_frame_carries_the_rounding_of_every_joint_on_its_path():
    """j1 turns by a rounded π/2 (4 × its distance: a rotation bound) and moves by a 7-digit
    position (√3 × half its last digit); j2 adds a 5-digit position; a fixed joint without an
    origin adds nothing; a joint without a parent places nothing."""
    p = urdf_precision(CHAIN)
    assert set(p.frames) == {"base", "l1", "l2", "l3", "l4"}
    assert p.frames["base"] == (0.0, 0.0) and p.frames["l4"] == (0.0, 0.0)
    assert p.frames["l1"] == pytest.approx((4 * D90, S3 * 0.5e-7), rel=1e-9)
    assert p.frames["l2"] == pytest.approx((4 * D90, S3 * (0.5e-7 + 0.5e-5)), rel=1e-9)
    assert p.frames["l3"] == pytest.approx(p.frames["l2"], rel=1e-12)
    # the rotation of j1 is the coarser of its two bounds: it is the example of orientations
    assert (p.angle, p.examples["angle"]) == (pytest.approx(4 * D90, rel=1e-9), "1.571")
    # j2 only moves: its position is the example of positions
    assert (p.length, p.examples["length"]) == (pytest.approx(S3 * 0.5e-5, rel=1e-9), "0.12345")


def test_a_urdf_revolute_limit_is_a_rounded_angle_and_a_prismatic_one_a_length():
    p = urdf_precision(CHAIN)
    # -1.571 rad is π/2 rounded; -0.785 m on the prismatic joint is a designer's length (exact)
    assert (p.limit, p.examples["limit"]) == (pytest.approx(D90, rel=1e-9), "-1.571")


def test_a_rounded_urdf_axis_turns_the_frame():
    urdf = """<robot name="r"><link name="a"/><link name="b"/>
      <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0.70711 0.70711 0"/>
      <limit lower="-1" upper="1"/></joint></robot>"""
    p = urdf_precision(urdf)
    assert p.frames["b"] == pytest.approx((4 * 0.5e-5, 0.0), rel=1e-9, abs=1e-15)
    assert (p.angle, p.examples["angle"], p.length, p.limit) == (pytest.approx(2e-5, rel=1e-9), "0.70711", 0.0, 0.0)


def test_a_urdf_inertial_origin_gives_the_centre_of_mass_and_orientation_roundings():
    urdf = """<robot name="r"><link name="a"><inertial><origin xyz="0 0.1234567 0" rpy="0 0.785 0"/>
      <mass value="2"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>"""
    p = urdf_precision(urdf)
    assert (p.com, p.examples["com"]) == (pytest.approx(0.5e-7, rel=1e-9), "0.1234567")
    assert (p.inertial_angle, p.examples["inertial_angle"]) == (pytest.approx(D45, rel=1e-9), "0.785")
    assert p.relative == 0.0 and p.angle == 0.0 and p.length == 0.0


@pytest.mark.parametrize("where", ["mass", "ixx", "iyy", "izz", "ixy", "ixz", "iyz"])
def test_every_urdf_mass_and_inertia_number_carries_a_relative_rounding(where):
    values = {a: "0.1" for a in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")} | {"mass": "2"}
    values[where] = "-0.0012345"  # relative to its magnitude
    inertia = " ".join(f'{a}="{values[a]}"' for a in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz"))
    urdf = (
        f'<robot name="r"><link name="a"><inertial><mass value="{values["mass"]}"/><inertia {inertia}/></inertial></link></robot>'
    )
    p = urdf_precision(urdf)
    assert (p.relative, p.examples["relative"]) == (pytest.approx(0.5e-7 / 0.0012345, rel=1e-9), "-0.0012345")


def test_a_urdf_inertial_without_an_origin_or_an_inertia_is_read():
    p = urdf_precision('<robot name="r"><link name="a"><inertial><mass value="1.23456"/></inertial></link></robot>')
    assert (p.relative, p.com, p.inertial_angle) == (pytest.approx(0.5e-5 / 1.23456, rel=1e-9), 0.0, 0.0)


def test_a_loop_of_urdf_joints_ends():
    urdf = """<robot name="r"><link name="a"/><link name="b"/>
      <joint name="ab" type="fixed"><parent link="a"/><child link="b"/><origin xyz="0.12345 0 0"/></joint>
      <joint name="ba" type="fixed"><parent link="b"/><child link="a"/><origin xyz="0.1234567 0 0"/></joint></robot>"""
    p = urdf_precision(urdf)
    assert p.frames["b"] == pytest.approx((0.0, S3 * (0.5e-5 + 0.5e-7)), rel=1e-9, abs=1e-15)


# --- an MJCF's precision --------------------------------------------------------------------

MJCF_CHAIN = """<mujoco><compiler angle="radian"/><worldbody>
  <body name="a" pos="0.1234567 0 0" quat="0.70711 0 0 0.70711">
    <joint name="ja" axis="0 0 1" range="-1.571 1.571"/>
    <site name="sa" pos="0.12345 0 0"/>
    <site pos="0.1 0 0"/>
    <body name="b" pos="0 0 0.12345"><joint name="jb" type="slide" axis="1 0 0" range="-0.785 0.5"/></body>
    <body pos="0.1 0 0"/>
  </body>
  <frame name="f" pos="0.12345 0 0"><body name="c"/></frame>
</worldbody></mujoco>"""


def test_an_mjcf_frame_carries_the_rounding_of_every_body_on_its_path():
    p = mjcf_precision(MJCF_CHAIN)
    assert set(p.frames) == {"a", "sa", "b", "c"}  # neither a <frame> nor an unnamed body or site
    a = (4 * 0.5e-5, S3 * 0.5e-7)  # the quaternion's components, the position's
    assert p.frames["a"] == pytest.approx(a, rel=1e-9)
    assert p.frames["sa"] == pytest.approx((a[0], a[1] + S3 * 0.5e-5), rel=1e-9)
    assert p.frames["b"] == pytest.approx((a[0], a[1] + S3 * 0.5e-5), rel=1e-9)
    assert p.frames["c"] == pytest.approx((0.0, S3 * 0.5e-5), rel=1e-9, abs=1e-15)
    assert (p.angle, p.examples["angle"]) == (pytest.approx(2e-5, rel=1e-9), "0.70711")
    assert (p.length, p.examples["length"]) == (pytest.approx(S3 * 0.5e-5, rel=1e-9), "0.12345")


def test_an_mjcf_hinge_range_in_radians_is_a_rounded_angle_and_a_slide_range_a_length():
    p = mjcf_precision(MJCF_CHAIN)
    assert (p.limit, p.examples["limit"]) == (pytest.approx(D90, rel=1e-9), "-1.571")


@pytest.mark.parametrize("compiler", ["", "<compiler/>", '<compiler angle="degree"/>'])
def test_an_mjcf_in_degrees_rounds_its_euler_angles_and_hinge_ranges_in_degrees(compiler):
    mjcf = f"""<mujoco>{compiler}<worldbody><body name="a" euler="0 0 90.00001">
      <joint name="j" range="-90.00001 1.571"/></body></worldbody></mujoco>"""
    p = mjcf_precision(mjcf)
    assert p.frames["a"] == pytest.approx((4 * 0.5e-5 * DEG, 0.0), rel=1e-9, abs=1e-15)
    # 1.571 degrees is no rounded π/2: only the 7-digit bound counts
    assert (p.limit, p.examples["limit"]) == (pytest.approx(0.5e-5 * DEG, rel=1e-9), "-90.00001")


def test_an_mjcf_in_radians_snaps_its_euler_angles_to_pi_over_12():
    p = mjcf_precision('<mujoco><compiler angle="radian"/><worldbody><body name="a" euler="0 0 1.571"/></worldbody></mujoco>')
    assert p.frames["a"] == pytest.approx((4 * D90, 0.0), rel=1e-9, abs=1e-15)


@pytest.mark.parametrize("attr", ["quat", "xyaxes", "zaxis"])
def test_every_mjcf_orientation_attribute_turns_the_frame(attr):
    p = mjcf_precision(f'<mujoco><worldbody><body name="a" {attr}="0.70711 0 0.70711"/></worldbody></mujoco>')
    assert p.frames["a"] == pytest.approx((4 * 0.5e-5, 0.0), rel=1e-9, abs=1e-15)


def test_an_mjcf_axisangle_rounds_by_its_angle_not_its_axis():
    p = mjcf_precision('<mujoco><worldbody><body name="a" axisangle="0.1234567 0 1 90.00001"/></worldbody></mujoco>')
    assert p.frames["a"] == pytest.approx((4 * 0.5e-5 * DEG, 0.0), rel=1e-9, abs=1e-15)


def test_an_mjcf_joint_axis_and_position_add_to_its_body():
    mjcf = """<mujoco><worldbody><body name="a"><joint name="j" axis="0.70711 0.70711 0" pos="0.12345 0 0"/>
      </body></worldbody></mujoco>"""
    p = mjcf_precision(mjcf)
    assert p.frames["a"] == pytest.approx((4 * 0.5e-5, S3 * 0.5e-5), rel=1e-9)
    assert p.examples["angle"] == "0.70711"


def test_an_mjcf_site_in_the_world_carries_its_orientation_too():
    p = mjcf_precision(
        '<mujoco><worldbody><site name="s" quat="0.70711 0 0 0.70711"/><site pos="0.12345 0 0"/></worldbody></mujoco>'
    )
    assert p.frames == {"s": pytest.approx((4 * 0.5e-5, 0.0), rel=1e-9, abs=1e-15)}


def test_an_mjcf_inertial_gives_centre_of_mass_orientation_and_relative_roundings():
    mjcf = """<mujoco><worldbody><body name="a"><body name="b">
      <inertial pos="0.1234567 0 0" quat="0.70711 0 0 0.70711" mass="1.23456" diaginertia="0.1 0.1 0.1"/>
      </body></body></worldbody></mujoco>"""
    p = mjcf_precision(mjcf)
    assert (p.com, p.examples["com"]) == (pytest.approx(0.5e-7, rel=1e-9), "0.1234567")
    assert (p.inertial_angle, p.examples["inertial_angle"]) == (pytest.approx(0.5e-5, rel=1e-9), "0.70711")
    assert (p.relative, p.examples["relative"]) == (pytest.approx(0.5e-5 / 1.23456, rel=1e-9), "1.23456")
    assert p.angle == 0.0 and p.length == 0.0


def test_an_mjcf_inertial_euler_is_in_the_compilers_unit():
    mjcf = """<mujoco><worldbody><body name="a"><inertial pos="0 0 0" euler="0 0 90.00001" mass="1"
      diaginertia="1 1 1"/></body></worldbody></mujoco>"""
    assert mjcf_precision(mjcf).inertial_angle == pytest.approx(0.5e-5 * DEG, rel=1e-9)
    radian = mjcf.replace("<mujoco>", '<mujoco><compiler angle="radian"/>').replace("90.00001", "0.785")
    assert mjcf_precision(radian).inertial_angle == pytest.approx(D45, rel=1e-9)


@pytest.mark.parametrize("attr", ["mass", "diaginertia", "fullinertia"])
def test_every_mjcf_mass_and_inertia_number_carries_a_relative_rounding(attr):
    values = {"mass": "2", "diaginertia": "0.1 0.1 0.1", "fullinertia": ""}
    values[attr] = "-0.0012345" if attr == "mass" else "0.1 0.1 0.0012345"
    said = " ".join(f'{k}="{v}"' for k, v in values.items() if v)
    p = mjcf_precision(f'<mujoco><worldbody><body name="a"><inertial pos="0 0 0" {said}/></body></worldbody></mujoco>')
    assert p.relative == pytest.approx(0.5e-7 / 0.0012345, rel=1e-9)


@pytest.mark.parametrize("angle, hinge, slide", [("radian", D90, 0.0), ("degree", 0.0, 0.0)])
def test_joint_ranges_in_class_defaults_are_limits(angle, hinge, slide):
    mjcf = f"""<mujoco><compiler angle="{angle}"/><default><default class="x"><joint range="-1.571 1.571"/></default>
      <default class="y"><joint type="slide" range="-0.785 0.5"/></default></default><worldbody/></mujoco>"""
    assert mjcf_precision(mjcf).limit == pytest.approx(max(hinge, slide), rel=1e-9, abs=1e-15)
    slides = mjcf.replace('range="-1.571 1.571"', 'range="-1 1"').replace("-0.785", "-0.12345")
    assert mjcf_precision(slides).limit == pytest.approx(0.5e-5, rel=1e-9)


# --- the floors both files' precision gives -------------------------------------------------


def test_the_floors_add_both_files_roundings_and_the_lever_arm_of_a_rotation():
    a, b = Precision("URDF"), Precision("MJCF")
    a.frames = {"x": (1e-3, 2e-4), "z": (1e-3, 1e-4)}
    b.frames = {"X": (2e-3, 3e-4)}
    a.limit, b.limit, a.relative, b.relative, a.com, b.com = 1e-4, 2e-4, 1e-5, 3e-5, 1e-6, 5e-6
    a.inertial_angle, b.inertial_angle = 1e-4, 2e-4
    f = floors(a, b, [("x", "X", "name"), ("z", "Z", "name")], {"x": 0.5, "y": 0.2}, dof=4)
    assert f.frames == {"x": pytest.approx((5e-4 + 3e-3 * 0.5, 3e-3), rel=1e-12), "z": pytest.approx((1e-4, 1e-3), rel=1e-12)}
    assert (f.dof, f.reach) == (4, 0.5)
    assert (f.limit, f.relative, f.com, f.inertial_angle) == pytest.approx((3e-4, 4e-5, 6e-6, 4 * 3e-4), rel=1e-12)
    assert floors(a, b, [], {}, dof=1).reach == 0.0


def test_the_floor_of_each_kinematics_check():
    f = Floors({"x": (2e-3, 3e-3)}, dof=4, reach=0.5)
    assert f.check("fk.position", "x") == pytest.approx(2e-3)
    assert f.check("fk.rotation", "x") == pytest.approx(3e-3)
    assert f.check("jacobian.linear", "x") == pytest.approx(2 * (3e-3 * 0.5 + 2 * 2e-3), rel=1e-12)
    assert f.check("jacobian.angular", "x") == pytest.approx(2 * 3e-3, rel=1e-12)
    assert f.check("dynamics.mass_matrix", "x") == 0.0
    assert [f.check(p, "elsewhere") for p in ("fk.position", "fk.rotation", "jacobian.linear")] == [0.0, 0.0, 0.0]
    # no joint compared: the Jacobian's column count is taken as one
    assert Floors({"x": (2e-3, 3e-3)}, dof=0, reach=0.5).check("jacobian.angular", "x") == pytest.approx(3e-3)


def test_the_kinematic_and_dynamics_floors():
    f = Floors({"x": (2e-3, 1e-3), "y": (1e-3, 4e-3)}, reach=0.5, relative=1e-5, inertial_angle=1e-4)
    assert f.kinematic == (2e-3, 4e-3)
    assert f.dynamics == pytest.approx(1e-5 + 2 * 1e-4 + 2 * 4e-3 + 2e-3 / 0.5, rel=1e-12)
    assert Floors().kinematic == (0.0, 0.0)
    assert Floors({"x": (2e-3, 1e-3)}, relative=1e-5).dynamics == pytest.approx(1e-5 + 2e-3, rel=1e-12)


@pytest.mark.parametrize("angle", ["degree", "radian"])
def test_a_slide_range_is_in_metres_whatever_the_compilers_angle(angle):
    mjcf = f"""<mujoco><compiler angle="{angle}"/><worldbody><body name="a">
      <joint name="s" type="slide" range="-0.12345 0.5"/></body></worldbody></mujoco>"""
    assert mjcf_precision(mjcf).limit == pytest.approx(0.5e-5, rel=1e-9)
