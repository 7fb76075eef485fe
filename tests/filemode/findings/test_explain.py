"""The written-precision floor of the kinematics checks: raised to it where the files are rounded,
never over a tolerance the user set for that property on the command line."""

from __future__ import annotations

import dataclasses

import pytest

import tests.filemode.pairs as P
from kinverify.filemode.align.match import Matching
from kinverify.filemode.compare.context import FileModeInfo
from kinverify.filemode.findings.explain import apply_floors, dynamics_floors, explain, rounding_finding
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.precision import Floors, Precision
from kinverify.run import VerifyOptions
from kinverify.suites.base import EXPLAINED, Check, Finding

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


def mk(prop: str, frame: str, error: float, tol: float = 1e-6, unit: str = "m", **kw) -> Check:
    return Check(prop, frame, ("pinocchio-urdf", "mujoco"), error, error, tol, error <= tol, (0.0,), unit=unit, **kw)


def test_a_floor_applies_to_kinematics_only_and_only_above_the_tolerance():
    floors = info(frozenset())
    (lim,), raised = apply_floors([mk("limits.position", "link3", 5e-5)], floors)
    assert (lim.tolerance, lim.passed, lim.note, raised) == (1e-6, False, "", [])
    (same,), raised = apply_floors([mk("fk.position", "link3", 5e-5, tol=1e-4)], floors)  # the floor equals it
    assert (same.tolerance, same.passed, same.note, raised) == (1e-4, True, "", [])
    (ok,), raised = apply_floors([mk("fk.position", "link3", 1e-7, note="seen")], floors)  # passed before: not raised
    assert (ok.tolerance, ok.passed, raised) == (1e-4, True, [])
    assert ok.note == "seen; tolerance raised to the written precision (0.0001)"
    (far,), raised = apply_floors([mk("fk.position", "link3", 2e-4)], floors)  # beyond the floor: still fails
    assert (far.tolerance, far.passed, raised) == (1e-4, False, [])
    (other,), _ = apply_floors([mk("fk.position", "link9", 5e-5)], floors)  # exact there
    assert (other.tolerance, other.passed) == (1e-6, False)


def dyn(relative: float = 0.01, user: frozenset = frozenset()) -> FileModeInfo:
    return FileModeInfo(None, None, None, None, Floors(relative=relative), user_tolerances=user)


DEFAULTS = {"dynamics.gravity": 1e-6, "inertia.mass": 1e-6}


def test_the_dynamics_floor_is_relative_and_scales_with_a_tolerance_above_the_default():
    (c,) = dynamics_floors([mk("dynamics.gravity", "joints", 5e-3, unit="N·m")], dyn(), DEFAULTS)
    assert (c.tolerance, c.passed, c.note) == (0.01, True, "tolerance raised to the written precision (0.01)")
    (twice,) = dynamics_floors([mk("dynamics.gravity", "joints", 1.5e-2, tol=2e-6)], dyn(), DEFAULTS)
    assert (twice.tolerance, twice.passed) == (pytest.approx(0.02), True)
    (past,) = dynamics_floors([mk("dynamics.gravity", "joints", 0.5)], dyn(), DEFAULTS)
    assert (past.tolerance, past.passed) == (0.01, False)


def test_the_dynamics_floor_leaves_other_checks_exact_files_user_tolerances_and_tolerances_at_the_floor():
    gravity = mk("dynamics.gravity", "joints", 5e-3)
    for checks, where, defaults in [
        ([mk("inertia.mass", "link1", 5e-3)], dyn(), DEFAULTS),  # not a state of the dynamics
        ([gravity], dyn(0.0), DEFAULTS),  # exact files
        ([gravity], dyn(user=frozenset({"dynamics.gravity"})), DEFAULTS),  # the user's tolerance
        ([gravity], dyn(), {}),  # no default to scale from
        ([mk("dynamics.gravity", "joints", 5e-3, tol=0.01)], dyn(), {"dynamics.gravity": 0.01}),  # at the floor
    ]:
        assert dynamics_floors(checks, where, defaults) == checks


FRAMES = Matching([], [], [], [("link1", "L1", "same name"), ("link2", "L2", "same name"), ("link3", "L3", "same name")])


def frames_info() -> FileModeInfo:
    return FileModeInfo(None, None, FRAMES, None, Floors(), (Precision("URDF"), Precision("MJCF")))


def test_the_rounding_finding_starts_at_the_first_frame_in_chain_order_and_names_the_culprits():
    raised = [mk("fk.position", "link3", 4e-5), mk("fk.rotation", "link2", 3e-5, unit="rad"), mk("fk.position", "tool", 9e-5)]
    culprit = ("MJCF", "body link2 quat", "0.70711", "link2", 5)
    f = rounding_finding(raised, frames_info(), [culprit])
    assert (f.kind, f.severity, f.subject, f.other, f.unit) == ("rounding", "info", "link2", "L2", "m|rad")
    assert f.magnitude == 9e-5 and f.values["position_m"] == 9e-5 and f.values["rotation_rad"] == 3e-5
    assert f.values["frames"] == ["link2", "link3", "tool"] and f.values["culprits"] == [list(culprit)]
    assert f.message == (
        "the files agree to 9e-05 m and 3e-05 rad only, from frame link2 on: within the precision they are written with "
        "(the MJCF writes 0.70711 for link2 at body link2 quat (rounded to 5 decimals))"
    )
    assert rounding_finding([], frames_info(), [culprit]) is None
    second = ("URDF", "joint joint3 origin rpy", "1.5708", "link3", 4)
    assert rounding_finding(raised, frames_info(), [culprit, second]).message.endswith(
        "(the MJCF writes 0.70711 for link2 at body link2 quat (rounded to 5 decimals); "
        "the URDF writes 1.5708 for link3 at joint joint3 origin rpy (rounded to 4 decimals))"
    )


def test_the_rounding_finding_without_a_culprit_describes_both_files_precision_and_an_unmatched_frame_comes_last():
    f = rounding_finding([mk("jacobian.linear", "tool", 1e-3), mk("fk.rotation", "link3", 2e-5, unit="rad")], frames_info(), [])
    assert (f.subject, f.other, f.magnitude) == ("link3", "L3", 2e-5) and f.values["position_m"] == 0.0
    assert f.message.endswith("(the URDF writes exact values; the MJCF writes exact values)")
    g = rounding_finding([mk("fk.position", "tool", 1e-5)], frames_info(), [])
    assert (g.subject, g.other, g.values["rotation_rad"]) == ("tool", "", 0.0)


def cause(kind: str, severity: str = "error", **values) -> Finding:
    return Finding(kind, severity, kind, "j2", "joint", values=values)


def test_what_no_finding_explains_starts_where_the_chain_first_differs():
    checks = [
        mk("fk.position", "link3", 4e-3),
        mk("fk.rotation", "link2", 2e-3, unit="rad"),
        mk("jacobian.linear", "end", 9.0),  # not a matched frame: last, whatever its name
        mk("fk.position", "link1", 1e-9),  # passes
        mk("fk.position", "link1", 5.0, kind="performance"),  # does not count
    ]
    out, findings = explain(checks, [], frames_info())
    (f,) = findings
    assert (f.kind, f.subject, f.other, f.magnitude, f.unit) == ("disagreement_starts", "link2", "L2", 4e-3, "m|rad")
    assert f.values == {"position_m": 4e-3, "rotation_rad": 2e-3, "frames": ["link2", "link3", "end"]}
    assert f.message.startswith(
        "forward kinematics differ from frame link2 on, by up to 0.004 m and 0.002 rad after alignment (3 frames;"
    )
    assert [c.kind for c in out] == [EXPLAINED, EXPLAINED, EXPLAINED, "agreement", "performance"]
    assert out[0].note == "explained by disagreement_starts on frame link2 / L2"


def test_an_error_or_warning_explains_the_kinematics_of_its_frames_and_the_checks_it_lists_an_info_nothing():
    axis = cause("axis_direction", frames=["link2", "link3"])
    mass = cause("mass_difference", "warning", checks=[["inertia.mass", "link2"]])
    info_only = cause("frame_convention", "info", frames=["link1"], checks=[["inertia.com", "link1"]])
    checks = [
        mk("fk.position", "link3", 4e-3, note="seen"),
        mk("inertia.mass", "link2", 1.0),
        mk("inertia.mass", "link3", 1.0),  # frames explain kinematics only
        mk("fk.position", "link1", 1e-3),
        mk("inertia.com", "link1", 1e-3),
    ]
    out, findings = explain(checks, [axis, mass, info_only], frames_info())
    assert out[0].kind == EXPLAINED and out[0].note == "seen; explained by axis_direction on joint j2"
    assert out[1].kind == EXPLAINED and out[1].note == "explained by mass_difference on joint j2"
    assert (out[2].kind, out[4].kind) == ("agreement", "agreement")
    (new,) = findings[3:]  # what neither explains: link1's position, where the chain first differs
    assert new.kind == "disagreement_starts" and new.subject == "link1" and new.values["frames"] == ["link1"]
    assert out[3].note == "explained by disagreement_starts on frame link1 / L1"


STATE = [mk("dynamics.gravity", "joints", 0.5, tol=0.1, unit="N·m"), mk("dynamics.bias", "joints", 3.0, tol=1.0, unit="N")]


def test_dynamics_nothing_explains_are_one_finding_sized_by_the_worst_ratio():
    """gravity 0.5 against 0.1 (5 times over), bias 3 against 1 (3 times): gravity is the worst, the
    larger number notwithstanding; a warning with frames is no kinematic error to blame."""
    out, findings = explain(STATE, [cause("mass_difference", "warning", frames=["link2"])], frames_info())
    f = findings[-1]
    assert (f.kind, f.severity, f.property, f.magnitude, f.unit) == (
        "dynamics_difference",
        "error",
        "dynamics.gravity",
        0.5,
        "N·m",
    )
    assert f.values == {"checks": [["dynamics.gravity", "joints"], ["dynamics.bias", "joints"]]}
    assert f.message == (
        "the dynamics still differ after substituting every difference reported: dynamics.gravity 0.5 N·m, dynamics.bias 3 N"
    )
    assert [c.note for c in out] == ["explained by dynamics_difference on model"] * 2
    zero = [mk("dynamics.gravity", "joints", 0.5, tol=0.0), mk("dynamics.bias", "joints", 0.25, tol=0.1)]
    assert explain(zero, [], frames_info())[1][-1].property == "dynamics.bias"  # no tolerance: no ratio


def test_dynamics_behind_a_kinematic_error_or_a_finding_that_lists_them_are_theirs():
    axis = cause("axis_direction", frames=["link2"])
    out, findings = explain(STATE, [axis], frames_info())
    assert findings == [axis] and [c.note for c in out] == ["explained by axis_direction on joint j2"] * 2
    damping = cause("damping_difference", checks=[["dynamics.bias", "joints"]])
    out, findings = explain(STATE, [damping], frames_info())
    assert findings == [damping] and out[1].note == "explained by damping_difference on joint j2"
    assert out[0].kind == "agreement"  # gravity: nothing lists it, no kinematic error to blame


def test_the_rounding_finding_without_a_culprit_says_each_files_angles_and_lengths_only():
    def written(file: str) -> Precision:
        p = Precision(file)
        p.note("angle", 5e-6, "0.70711")
        p.note("length", 5e-5, "0.1235")
        p.note("relative", 1e-3, "1.23")  # masses: not what FK agrees to
        return p

    where = FileModeInfo(None, None, FRAMES, None, Floors(), (written("URDF"), written("MJCF")))
    f = rounding_finding([mk("fk.position", "link3", 2e-5)], where, [])
    urdf, mjcf = (written(x).describe(["angle", "length"]) for x in ("URDF", "MJCF"))
    assert f.message.endswith(f"({urdf}; {mjcf})")
    assert mjcf.startswith("the MJCF writes") and "0.70711" in mjcf and "0.1235" in mjcf and "1.23" not in mjcf


def test_a_disagreement_in_rotation_only_is_no_position():
    (f,) = explain([mk("fk.rotation", "link3", 2e-3, unit="rad")], [], frames_info())[1]
    assert f.values == {"position_m": 0.0, "rotation_rad": 2e-3, "frames": ["link3"]} and f.magnitude == 2e-3
    (g,) = explain([mk("fk.position", "link3", 2e-3)], [], frames_info())[1]
    assert (g.values["position_m"], g.values["rotation_rad"]) == (2e-3, 0.0)
