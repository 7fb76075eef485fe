"""The written-precision floor of the kinematics checks: raised to it where the files are rounded,
never over a tolerance the user set for that property on the command line."""

from __future__ import annotations

from kinverify.filemode.compare.context import FileModeInfo
from kinverify.filemode.findings.explain import apply_floors
from kinverify.filemode.read.precision import Floors
from kinverify.suites.base import Check


def check(prop: str = "fk.position") -> Check:
    """link3 read 50 µm apart by the two files, against a tolerance of 1 µm."""
    return Check(prop, "link3", ("pinocchio-urdf", "mujoco"), 5e-5, 5e-5, 1e-6, False, (0.0,), unit="m")


def info(user: frozenset) -> FileModeInfo:
    """Files written to 0.1 mm at link3 (the floor); ``user``: the properties the user set."""
    return FileModeInfo(None, None, None, None, Floors(frames={"link3": (1e-4, 1e-4)}), user_tolerances=user)


def test_the_floor_of_the_written_precision_raises_a_default_tolerance():
    (c,), (raised,) = apply_floors([check()], info(frozenset()))
    assert (c.passed, c.tolerance) == (True, 1e-4) and raised == c and "written precision" in c.note


def test_a_tolerance_the_user_set_is_kept_below_the_floor():
    (c,), raised = apply_floors([check()], info(frozenset({"fk.position"})))
    assert (c.passed, c.tolerance, raised) == (False, 1e-6, []) and c.note == ""
    (r,), _ = apply_floors([check("fk.rotation")], info(frozenset({"fk.position"})))  # another property: floored
    assert (r.passed, r.tolerance) == (True, 1e-4)
