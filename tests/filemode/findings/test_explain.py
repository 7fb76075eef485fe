"""The written-precision floor of the kinematics checks: raised to it where the files are rounded,
never over a tolerance the user set for that property on the command line."""

from __future__ import annotations

import dataclasses

import tests.filemode.pairs as P
from kinverify.filemode.compare.context import FileModeInfo
from kinverify.filemode.findings.explain import apply_floors
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.precision import Floors
from kinverify.run import VerifyOptions
from kinverify.suites.base import Check

FAST = VerifyOptions(samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics"])


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


def test_file_mode_keeps_a_tolerance_the_user_set_below_the_written_precision(tmp_path):
    """The MJCF writes link3 0.25123 m up where the URDF says 0.2512345: 4.5 µm, within the MJCF's
    written precision (5 significant digits: ±5 µm), so a pass with a rounding note; with
    ``fk.position`` set to 1e-9 by the user, the same pair fails at link3."""
    urdf, mjcf = P.generated_pair("arm3")
    urdf = P.sub_once(r'(<joint name="joint3".*?<origin xyz="0\.0 0\.0 )0\.25"', lambda m: m[1] + '0.2512345"', urdf)
    mjcf = P.body_attr(mjcf, "link3", "pos", lambda v: "0.0 0.0 0.25123")
    files = P.write_pair(tmp_path, urdf, mjcf)
    rounded = verify_files(*files, FAST)
    assert rounded.verdict == "pass" and "rounding" in {f.kind for f in rounded.findings}
    strict = verify_files(*files, dataclasses.replace(FAST, tolerances={"fk.position": 1e-9}))
    failing = [(f.kind, f.subject) for f in strict.findings if f.fails]
    assert strict.verdict == "fail" and failing == [("disagreement_starts", "link3")], failing
