"""IK: FK -> IK -> FK on random specs, limits, arm3 closed-form branches, unreachable targets, the
seed's figures, the verify suite and the ``kinverify ik`` command (real pin, mujoco, yourdfpy)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, assume, given, settings
from hypothesis import strategies as st

from kinverify import load_spec, spec_from_dict
from kinverify.testing import strategies as kst
from kinverify.backends import FunctionBackend, ModelSources, build_backend
from kinverify.cli import main
from kinverify.ik import (
    Arm3ClosedForm,
    FrameModel,
    IKOptions,
    reach_bound,
    residuals,
    solve_lm,
    solve_seed_pinv,
    unreachable_targets,
)
from kinverify.model.kinematics import frame_poses
from kinverify.model.transforms import make_transform
from kinverify.run import VerifyOptions, verify_spec

ARM3 = load_spec("models/arm3.toml")
SEED_TARGET = make_transform(np.eye(3), [0.2, 0.1, 0.8])[None]
TOL = 1e-6


def _model(spec, name="analytic"):
    sources = ModelSources.from_spec(spec)
    return FrameModel(build_backend(name, sources), sources.frames[-1], sources.revolute), sources


@pytest.mark.parametrize("backend", ["analytic", "mujoco", "pinocchio-urdf"])
def test_seed_pinv_reproduces_the_seed_figures(backend):
    model, _ = _model(ARM3, backend)
    sol = solve_seed_pinv(model, SEED_TARGET, ARM3.lower, ARM3.upper)
    assert sol.iterations[0] == 64
    assert sol.pos_error[0] == pytest.approx(0.96e-3, abs=0.005e-3)
    np.testing.assert_allclose(np.degrees(sol.q[0]), [26.55555307, 84.48810787, 126.0462028], atol=1e-6)


@pytest.mark.parametrize("backend", ["analytic", "pinocchio-urdf", "mujoco"])
def test_lm_solves_the_seed_target_below_1e_9(backend):
    model, sources = _model(ARM3, backend)
    sol = solve_lm(model, SEED_TARGET, ARM3.lower, ARM3.upper, position_only=True)
    assert sol.success[0] and sol.pos_error[0] < 1e-9
    for other in ("analytic", "pinocchio-mjcf", "yourdfpy"):
        p = build_backend(other, sources).poses(sol.q)[0, -1, :3, 3]
        assert np.linalg.norm(p - SEED_TARGET[0, :3, 3]) < 1e-9


@settings(max_examples=25, deadline=None)
@given(kst.arm_specs(min_joints=1, max_joints=7), kst.data())
def test_fk_ik_fk_returns_the_target_inside_the_limits(spec, data):
    q_true = data.draw(kst.configuration_batches(spec, 1, 4))
    model, sources = _model(spec)
    position_only = spec.dof < 6
    targets = model.poses(q_true)
    sol = solve_lm(
        model, targets, spec.lower, spec.upper, position_only, IKOptions(seed=1, max_restarts=300, time_budget=math.inf)
    )
    assert sol.solved(TOL, TOL).all(), (sol.pos_error, sol.rot_error, q_true)
    assert ((sol.q >= spec.lower) & (sol.q <= spec.upper)).all()
    pin = build_backend("pinocchio-urdf", sources)
    pos, rot = residuals(pin.poses(sol.q)[:, -1], targets, position_only)
    assert (pos < TOL).all() and (rot < TOL).all()


def _revolute(name, rpy, axis, lower, upper):
    return {
        "name": name,
        "type": "revolute",
        "xyz": [0.0, 0.0, 0.0],
        "rpy": rpy,
        "axis": axis,
        "limits": {"lower": lower, "upper": upper, "unit": "rad"},
        "link": {"name": "l" + name[1:], "mass": 1.0},
    }


# found by hypothesis: seven axes through one point (only the orientation moves), narrow limits,
# the target at a corner of the limits (every joint on one); the solver clipped its steps far from
# the target and stopped against the limits short of a stationary point, 300 restarts long
AXES_AT_ONE_POINT = spec_from_dict(
    {
        "name": "random_arm",
        "joints": [
            _revolute("j1", [0.0, 0.0, 0.0], [0, 0, 1], 0.0, 2.0),
            _revolute("j2", [0.0, 0.0, 0.0], [-1.0, -0.5, 0.0], 0.0, 1.0),
            _revolute("j3", [-2.25, math.pi / 2, math.pi], [0.0, 1.0, -0.5], 0.0, 1.0),
            _revolute("j4", [0.0, -math.pi / 2, 0.0], [0, 0, -1], -2.0, 1.0),
            _revolute("j5", [0.0, 0.0, 0.0], [1.0, 0.0, 0.0], 0.0, 2.0),
            _revolute("j6", [0.0, -math.pi / 2, 0.0], [0.0, 0.25, 1.0], 0.0, 0.0625),
            _revolute("j7", [0.0, 0.0, math.pi / 2], [0, 1, 0], 0.0, 2.0),
        ],
        "tools": [{"name": "tool", "parent": "l7", "xyz": [0.0, 0.0, 0.0], "rpy": [0.0, 0.0, 0.0]}],
    }
)


@settings(max_examples=10, deadline=None)
@given(kst.arm_specs(min_joints=6, max_joints=7, prismatic=False).flatmap(lambda s: st.tuples(st.just(s), kst.configurations(s))))
@example((AXES_AT_ONE_POINT, np.array([0.0, 1.0, 0.0, -2.0, 0.0, 0.0, 0.0])))
def test_pinocchio_solver_full_pose_on_random_specs(spec_q):
    spec, q = spec_q
    q_true = q[None]
    model, sources = _model(spec, "pinocchio-urdf")
    target = model.poses(q_true)
    sol = solve_lm(model, target, spec.lower, spec.upper, False, IKOptions(seed=2, max_restarts=300, time_budget=math.inf))
    assert sol.solved(TOL, TOL).all()
    pos, rot = residuals(frame_poses(spec, sol.q)[:, -1], target, False)
    assert pos[0] < TOL and rot[0] < TOL


@settings(max_examples=60, deadline=None)
@given(kst.configurations(ARM3))
@example(np.array([-math.pi, -math.pi / 2, -(2.0**-23)]))  # shoulder on its limit, elbow nearly straight
@example(np.array([math.pi, math.pi / 2, 2.0**-26]))
@example(np.array([0.0, -math.pi / 2, math.radians(135)]))  # both pitch joints on limits
def test_arm3_closed_form_branches_reproduce_the_target(q):
    closed = Arm3ClosedForm.from_spec(ARM3)
    target = frame_poses(ARM3, q)[0, -1, :3, 3]
    res = closed.solve(target)
    assert res.reachable and len(res.solutions) >= 1
    assert ((res.solutions >= ARM3.lower) & (res.solutions <= ARM3.upper)).all()
    reached = frame_poses(ARM3, res.solutions)[:, -1, :3, 3]
    assert np.abs(reached - target).max() < 1e-12
    rho = math.hypot(*(target[:2] - closed.shoulder[:2]))
    if rho > 1e-6:  # off the yaw axis the generating configuration is one of the branches
        d = np.abs(np.angle(np.exp(1j * (res.solutions - q)))).max(axis=1)
        assert d.min() < 1e-6


@settings(max_examples=80, deadline=None)
@given(
    st.sampled_from([-math.pi, math.pi, 0.7]),
    st.sampled_from([-math.pi / 2, math.pi / 2, -0.4]),
    st.sampled_from([-1.0, 1.0]),
    st.floats(10, 60),
)
def test_arm3_closed_form_near_the_straight_elbow_on_the_limits(q1, q2, sign, k):
    """A nearly straight elbow on a joint limit: the target is reachable, every branch returned
    reaches it to 1e-12 m, and the generating configuration is a branch within the precision the
    target's floats determine the pitch angles to (the singularity's conditioning)."""
    closed = Arm3ClosedForm.from_spec(ARM3)
    q = np.array([q1, q2, sign * 2.0**-k])
    target = frame_poses(ARM3, q)[0, -1, :3, 3]
    res = closed.solve(target)
    assert res.reachable
    assert ((res.solutions >= ARM3.lower) & (res.solutions <= ARM3.upper)).all()
    assert np.abs(frame_poses(ARM3, res.solutions)[:, -1, :3, 3] - target).max() < 1e-12
    d = np.abs(np.angle(np.exp(1j * (res.solutions - q)))).max(axis=1)
    assert d.min() <= closed.pitch_precision(target) + 1e-9


def test_arm3_closed_form_returns_every_branch():
    closed = Arm3ClosedForm.from_spec(ARM3)
    # shoulder front/back x elbow up/down: all four inside the limits for a target above the shoulder
    res = closed.solve([0.05, 0.02, 1.05])
    assert len(res.solutions) == 4
    assert len({tuple(np.sign(s[1:]).tolist()) for s in res.solutions}) == 4


@settings(max_examples=12, deadline=None)
@given(kst.arm_specs(min_joints=1, max_joints=6), st.integers(0, 1000))
def test_unreachable_targets_are_never_solved(spec, seed):
    model, sources = _model(spec)
    frame = sources.frames[-1]
    centre, radius = reach_bound(spec, frame)
    assume(radius > 0)
    targets, bound = unreachable_targets(spec, frame, 3, seed)
    sol = solve_lm(model, targets, spec.lower, spec.upper, spec.dof < 6, IKOptions(max_restarts=2, seed=seed))
    assert not sol.success.any()
    assert (sol.pos_error >= bound - 1e-9).all()  # the closest approach respects the reach bound


@settings(max_examples=20, deadline=None)
@given(st.floats(0, 2 * np.pi), st.floats(-np.pi / 2, np.pi / 2), st.floats(0.31, 1.0))
def test_arm3_closed_form_unreachable_outside_the_workspace(yaw, elevation, distance):
    closed = Arm3ClosedForm.from_spec(ARM3)
    d = np.array([math.cos(elevation) * math.cos(yaw), math.cos(elevation) * math.sin(yaw), math.sin(elevation)])
    res = closed.solve(closed.shoulder + distance * d)  # reach from the shoulder is at most 0.25 + 0.05
    assert not res.reachable and len(res.solutions) == 0
    assert res.closest_distance >= distance - 0.3 - 1e-9


def test_verify_ik_suite_passes_and_detects_a_wrong_model():
    shifted = FunctionBackend(
        "shifted", lambda q: frame_poses(ARM3, q)[:, -1, :3, 3] + [1e-4, 0, 0], ARM3.joint_names, ["end_effector"]
    )
    result = verify_spec(
        ARM3,
        VerifyOptions(samples=0, suites=["ik"], extra={"ik_targets": 8}, backends=["analytic", "pinocchio-urdf", "mujoco"]),
        extra_backends=[shifted],
    )
    props = {c.property for c in result.checks}
    assert props == {"ik.failure_rate", "ik.cross_fk", "ik.limits", "ik.closed_form", "ik.unreachable"}
    bad = [c for c in result.checks if not c.passed]
    assert bad and all(c.property == "ik.cross_fk" and c.backends[1] == "shifted" for c in bad)
    assert all(c.max_error == pytest.approx(1e-4, rel=1e-3) for c in bad)
    section = result.sections["ik"]
    assert section.tables[0].rows and "fraction" in " ".join(section.notes)


def test_ik_command_solves_and_confirms(capsys):
    assert main(["ik", "models/arm3.toml", "--target", "0.2", "0.1", "0.8", "--all-solutions"]) == 0
    out = capsys.readouterr().out
    assert "2 solution(s)" in out and "confirmed by: analytic" in out and "DISAGREE" not in out


def test_ik_command_reports_unreachable(capsys):
    assert main(["ik", "models/arm3.toml", "--target", "0.2", "0.1", "0.3", "--backend", "analytic"]) == 1
    assert "unreachable" in capsys.readouterr().out


@pytest.mark.parametrize(
    "argv",
    [
        ["--target", "0.2", "0.1"],
        ["--target", "0.2", "0.1", "nan"],
        ["--target", "0.2", "0.1", "0.8", "--backend", "nope"],
        ["--target", "0.2", "0.1", "0.8", "--rpy", "0", "1"],
        ["--target", "a", "0", "0"],
    ],
)
def test_ik_command_bad_input_is_one_line_exit_2(argv, capsys):
    assert main(["ik", "models/arm3.toml", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("kinverify: error:") and err.count("\n") == 1


@pytest.mark.parametrize("q", [[1.0, -math.pi / 2, 6.10351562e-05], [-math.pi, math.pi / 2, 6.10351562e-05]])
def test_arm3_closed_form_on_a_limit_with_a_nearly_straight_elbow(q):
    # found by hypothesis: acos near the straight elbow put these branches ~1e-11 rad beyond a limit
    closed = Arm3ClosedForm.from_spec(ARM3)
    target = frame_poses(ARM3, np.array(q))[0, -1, :3, 3]
    res = closed.solve(target)
    assert res.reachable
    assert np.abs(np.angle(np.exp(1j * (res.solutions - q)))).max(axis=1).min() < 1e-9
    assert np.abs(frame_poses(ARM3, res.solutions)[:, -1, :3, 3] - target).max() < 1e-12


def test_the_reach_bound_counts_a_prismatic_joints_travel_both_ways():
    """A slide along y going 0.5 m back and 0.1 m forth, 0.3 m out from a base yaw: at its lower
    limit the carriage is √(0.3² + 0.5²) ≈ 0.58 m from the yaw's origin, beyond 0.3 + 0.1 (the
    upper limit taken for the travel); the bound is 0.3 + 0.5."""
    spec = spec_from_dict(
        {
            "name": "slider",
            "base": {"link": {"name": "base"}},
            "joints": [
                {
                    "name": "yaw",
                    "type": "revolute",
                    "xyz": [0.0, 0.0, 0.1],
                    "axis": [0.0, 0.0, 1.0],
                    "limits": {"lower": -3.0, "upper": 3.0, "unit": "rad"},
                    "link": {"name": "arm", "mass": 1.0},
                },
                {
                    "name": "slide",
                    "type": "prismatic",
                    "parent": "arm",
                    "xyz": [0.3, 0.0, 0.0],
                    "axis": [0.0, 1.0, 0.0],
                    "limits": {"lower": -0.5, "upper": 0.1, "unit": "m"},
                    "link": {"name": "carriage", "mass": 0.5},
                },
            ],
        }
    )
    centre, radius = reach_bound(spec, "carriage")
    assert np.allclose(centre, [0.0, 0.0, 0.1]) and radius == pytest.approx(0.8, abs=1e-12)
    at_lower = frame_poses(spec, np.array([[0.0, -0.5]]))[0, spec.frame_names.index("carriage"), :3, 3]
    distance = float(np.linalg.norm(at_lower - centre))
    assert distance == pytest.approx(math.hypot(0.3, 0.5), abs=1e-12) and distance <= radius
