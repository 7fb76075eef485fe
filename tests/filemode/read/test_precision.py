"""The precision each file is written with: a number of many digits is off by half its last digit,
a rounded multiple of π/12 by its distance to it, a designer's short number not at all; a URDF's
masses and inertias carry a relative rounding; an MJCF's sites in the world carry their own; the
first number found at the coarsest rounding is the example."""

from __future__ import annotations

import math

import pytest

from kinverify.filemode.read.precision import Precision, mjcf_precision, rounding_of, urdf_precision


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
