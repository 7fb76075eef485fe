"""Trajectories to Cartesian targets: IK (closest solution), quintic plan, execution in MuJoCo,
final end-effector error; ``kinverify track --target``."""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from kinverify.testing import strategies as kst
from kinverify.cli import main
from kinverify.errors import InputError
from kinverify.generate import generate_urdf
from kinverify.ik import Arm3ClosedForm, unreachable_targets
from kinverify.model.kinematics import frame_poses
from kinverify.model.specfile import load_spec
from kinverify.tracking.cartesian import (
    IK_TOL,
    UnreachableError,
    end_effector_errors,
    end_of_motion_index,
    ik_model,
    nearest_equivalent,
    parse_target,
    plan_cartesian,
    solve_target,
    track_waypoints,
)
from kinverify.tracking.quintic import plan_violations
from kinverify.tracking.track import Trajectory, default_trajectory, track
from tests.tracking.test_tracking import _within_effort

ARM3 = load_spec("models/arm3.toml")
SEED_IK_TARGET = (0.2, 0.1, 0.8)


def _track_single(spec, cplan, hold=0.3, controller="computed-torque"):
    c = cplan.choices[0]
    return track(
        spec,
        generate_urdf(spec),
        Trajectory(cplan.q_start, c.q, cplan.durations[0], hold),
        [controller],
        render=False,
        plots=False,
    )


def test_arm3_seed_ik_target_under_computed_torque():
    target, position_only = parse_target(SEED_IK_TARGET)
    cplan = plan_cartesian(ARM3, [target], np.zeros(3), position_only=position_only)
    c = cplan.choices[0]
    assert c.pos_error <= IK_TOL and np.all(c.q >= ARM3.lower) and np.all(c.q <= ARM3.upper)
    result = _track_single(ARM3, cplan)
    run, m = result.runs[0], result.metrics[0]
    assert m.passed, m.reason
    assert all(ch.passed for ch in result.checks)  # the plan is inside the joint and speed limits
    at_end, _ = end_effector_errors(ARM3, cplan.frame, run.q[end_of_motion_index(run)], target)
    after, _ = end_effector_errors(ARM3, cplan.frame, run.q[-1], target)
    assert at_end <= 1e-4 and after <= 1e-4


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.data())
def test_arm3_prefers_the_closed_form_branch_closest_to_the_start(data):
    goal = data.draw(kst.reachable_targets(ARM3))
    start = data.draw(kst.configurations(ARM3))
    model = ik_model(ARM3, "analytic")
    choice = solve_target(ARM3, model, goal.pose, True, start, extra_starts=2)
    assert choice.pos_error <= IK_TOL
    wrap = np.array([True, False, False])  # joint1 spans ±180°
    branches = Arm3ClosedForm.from_spec(ARM3).solve(goal.position).solutions
    best = min(np.linalg.norm(nearest_equivalent(q, start, ARM3.lower, ARM3.upper, wrap) - start) for q in branches)
    assert choice.distance <= best + 1e-7


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(kst.arm_specs(max_joints=4), st.data())
def test_random_reachable_targets_are_reached(spec, data):
    goal = data.draw(kst.reachable_targets(spec))  # FK of a random configuration: reachable
    q0 = default_trajectory(spec).q0
    cplan = plan_cartesian(spec, [goal.pose], q0, position_only=True, backend="analytic")
    c = cplan.choices[0]
    assert c.pos_error <= IK_TOL and np.all(c.q >= spec.lower) and np.all(c.q <= spec.upper)
    vmax = [j.limits.velocity for j in spec.joints]
    assert plan_violations(cplan.plan(0.001), spec.lower, spec.upper, vmax) == []  # automatic duration
    assume(_within_effort(spec, Trajectory(q0, c.q, cplan.durations[0], 0.3)))  # heavy random arms saturate
    result = _track_single(spec, cplan)
    run, m = result.runs[0], result.metrics[0]
    assert m.passed, m.reason
    at_end, _ = end_effector_errors(spec, cplan.frame, run.q[end_of_motion_index(run)], goal.pose)
    after, _ = end_effector_errors(spec, cplan.frame, run.q[-1], goal.pose)
    assert at_end <= 1e-4 and after <= 1e-6, (at_end, after)


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kst.arm_specs(max_joints=5), st.integers(0, 2**16))
def test_unreachable_targets_raise_with_the_closest_approach(spec, seed):
    frame = spec.frame_names[-1]
    targets, bound = unreachable_targets(spec, frame, 1, seed)
    assume(bound[0] > 1e-3)
    with pytest.raises(UnreachableError) as err:
        plan_cartesian(spec, targets, default_trajectory(spec).q0, backend="analytic")
    # the closest approach reported is a real configuration's distance, and no closer than the bound
    assert err.value.closest >= bound[0] - 1e-9
    pos, _ = end_effector_errors(spec, frame, err.value.q_closest, targets[0])
    assert abs(pos - err.value.closest) <= 1e-9
    assert isinstance(err.value, InputError) and "closest approach" in str(err.value)


def test_arm3_unreachable_reports_the_closed_form_closest_approach():
    target, _ = parse_target([2.0, 0.0, 0.8])
    with pytest.raises(UnreachableError) as err:
        plan_cartesian(ARM3, [target], np.zeros(3), backend="analytic")
    closed = Arm3ClosedForm.from_spec(ARM3).closest_distance([2.0, 0.0, 0.8])
    assert abs(err.value.closest - closed) <= 1e-3 and "closed form" in str(err.value)


def test_waypoints_are_passed_and_the_last_reached():
    points = [(0.2, 0.1, 0.8), (0.1, -0.2, 0.9)]
    cplan = plan_cartesian(ARM3, [parse_target(p)[0] for p in points], np.zeros(3), backend="analytic")
    assert len(cplan.durations) == 2 and np.linalg.norm(cplan.choices[1].q - cplan.choices[0].q) == pytest.approx(
        cplan.choices[1].distance
    )
    result = track_waypoints(ARM3, generate_urdf(ARM3), cplan, 0.3, ["computed-torque"])
    run, m = result.runs[0], result.metrics[0]
    assert m.passed, m.reason
    k_first = int(round(cplan.durations[0] / 0.001))
    first, _ = end_effector_errors(ARM3, cplan.frame, run.q[k_first], cplan.choices[0].target)
    last, _ = end_effector_errors(ARM3, cplan.frame, run.q[-1], cplan.choices[1].target)
    assert first <= 1e-4 and last <= 1e-6


def test_full_pose_target_on_a_six_joint_arm():
    spec = load_spec("models/ur5e.toml")
    tr = default_trajectory(spec)
    target = frame_poses(spec, tr.q1)[0, -1]
    cplan = plan_cartesian(spec, [target], tr.q0, position_only=False)
    c = cplan.choices[0]
    assert c.pos_error <= IK_TOL and c.rot_error <= IK_TOL
    run = _track_single(spec, cplan).runs[0]
    pos, rot = end_effector_errors(spec, cplan.frame, run.q[-1], target, position_only=False)
    assert pos <= 1e-6 and rot <= 1e-6


def test_track_target_cli_reports_the_final_error(tmp_path, capsys):
    path = tmp_path / "t.json"
    assert main(["track", "models/arm3.toml", "--target", *map(str, SEED_IK_TARGET), "--hold", "0.3", "--json", str(path)]) == 0
    out = capsys.readouterr().out
    assert "target 1: xyz = [0.2, 0.1, 0.8] m -> q = " in out and "final end-effector error" in out
    cart = json.loads(path.read_text())["sections"]["tracking"]["data"]["cartesian"]
    errors = cart["end_effector_errors"][0]
    assert errors["controller"] == "computed-torque" and errors["position_error_end_of_motion"] <= 1e-4
    assert max(cart["ik_position_error"]) <= IK_TOL


@pytest.mark.parametrize(
    "argv, words",
    [
        (["--target", "0.2", "0.1"], "--target needs 3 values"),
        (["--target", "0.2", "nan", "0.8"], "must be finite"),
        (["--target", "0.2", "x", "0.8"], "not a number"),
        (["--target", "0.2", "0.1", "0.8", "--to", "0", "0", "0"], "mutually exclusive"),
        (["--target", "0.2", "0.1", "0.8", "--rpy", "0", "0", "0"], "needs at least 6"),
        (["--target", "0.2", "0.1", "0.8", "--ik-backend", "mujoco"], "IK backend must be"),
        (["--target", "0.2", "0.1", "0.8", "--duration", "0"], "must be positive"),
        (["--target", "2", "0", "0.8", "--ik-backend", "analytic"], "closest approach"),
        (["--target", "0.2", "0.1", "0.8", "--target", "0.1", "0.1", "0.9", "--rpy", "0", "0", "0"], "one --rpy per --target"),
        (["--target", "0.2", "0.1", "0.8", "--deg"], "--deg applies to --to only"),
    ],
)
def test_track_target_bad_input_is_one_line_and_exit_2(argv, words, capsys):
    assert main(["track", "models/arm3.toml", *argv]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1
