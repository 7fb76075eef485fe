"""Trajectory tracking: quintic plans, execution in MuJoCo under each controller, metrics, the
``tracking`` suite and ``kinverify track``."""

from __future__ import annotations

import base64
import json
import math

import mujoco
import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from kinverify.testing import strategies as kst
from kinverify.cli import main
from kinverify.errors import InputError
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import load_spec, spec_from_dict
from kinverify.tracking.controllers import make_controller
from kinverify.tracking.execute import execute, pinocchio_dynamics
from kinverify.tracking.figures import animation
from kinverify.tracking.metrics import compute_metrics
from kinverify.tracking.models import MujocoDynamics
from kinverify.tracking.quintic import hold, plan_violations, quintic, through_waypoints
from kinverify.tracking.track import default_trajectory, track
from tests.suites.test_dynamics import heavier_link

ARM3 = load_spec("models/arm3.toml")
finite = st.floats(-4.0, 4.0, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    st.integers(1, 7).flatmap(
        lambda n: st.tuples(st.lists(finite, min_size=n, max_size=n), st.lists(finite, min_size=n, max_size=n))
    ),
    st.floats(0.01, 5.0),
    st.sampled_from([0.001, 0.002, 0.0005]),
)
def test_quintic_boundary_conditions(ends, duration, dt):
    q0, q1 = map(np.array, ends)
    plan = quintic(q0, q1, duration, dt)
    assert plan.t[0] == 0 and abs(plan.t[-1] - duration) <= dt / 2 + 1e-12  # whole steps
    assert (
        np.allclose(plan.q[0], q0, atol=1e-12)
        and np.allclose(plan.qd[0], 0, atol=1e-12)
        and np.allclose(plan.qdd[0], 0, atol=1e-12)
    )
    # the last sample is the end of the motion: q1 at rest
    assert (
        np.allclose(plan.q[-1], q1, atol=1e-12)
        and np.allclose(plan.qd[-1], 0, atol=1e-9)
        and np.allclose(plan.qdd[-1], 0, atol=1e-6)
    )
    # never beyond the segment (rest-to-rest quintic is monotonic) and peak speed 15/8 |Δ|/T
    lo, hi = np.minimum(q0, q1), np.maximum(q0, q1)
    assert np.all(plan.q >= lo - 1e-12) and np.all(plan.q <= hi + 1e-12)
    assert np.all(np.abs(plan.qd).max(axis=0) <= 1.875 * np.abs(q1 - q0) / plan.duration + 1e-9)
    if len(plan.t) > 20:  # qd, qdd are the derivatives of q: central differences err by <= dt^2/6 max|q^(3)|
        T, delta = plan.duration, np.abs(q1 - q0).max()
        fd = (plan.q[2:] - plan.q[:-2]) / (2 * dt)
        assert np.abs(fd - plan.qd[1:-1]).max() <= dt**2 / 6 * 60 * delta / T**3 + 1e-9
        fdd = (plan.qd[2:] - plan.qd[:-2]) / (2 * dt)
        assert np.abs(fdd - plan.qdd[1:-1]).max() <= dt**2 / 6 * 360 * delta / T**4 + 1e-9


@settings(max_examples=20, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.lists(finite, min_size=2, max_size=2), min_size=3, max_size=5), st.floats(0.1, 2.0))
def test_waypoints_are_reached_at_rest(points, seg):
    points = np.array(points)
    plan = through_waypoints(points, [seg] * (len(points) - 1), 0.001)
    for i, p in enumerate(points):
        k = i * max(1, round(seg / 0.001))  # segments last whole steps
        assert np.allclose(plan.q[k], p, atol=1e-9) and np.allclose(plan.qd[k], 0, atol=1e-6)


@pytest.mark.parametrize("duration", [0.0, -1.0, float("nan")])
def test_non_positive_duration_is_input_error(duration):
    with pytest.raises(InputError):
        quintic([0.0], [1.0], duration, 0.001)


def test_plan_checks_limits_and_speed():
    plan = quintic(np.zeros(3), np.radians([60, 45, -30]), 2.0, 0.001)
    assert plan_violations(plan, ARM3.lower, ARM3.upper, [3.0] * 3) == []
    fast = quintic(np.zeros(3), np.radians([60, 45, -30]), 0.3, 0.001)  # peak 6.5 rad/s
    assert any("speed" in v for v in plan_violations(fast, ARM3.lower, ARM3.upper, [3.0] * 3))
    beyond = quintic(np.zeros(3), [0.0, 2.0, 0.0], 2.0, 0.001)  # joint2 limit is ±90°
    assert any("outside limits" in v for v in plan_violations(beyond, ARM3.lower, ARM3.upper, [3.0] * 3))


def _seed_run(controller, mjcf=None):
    tr = default_trajectory(ARM3)
    plan = hold(quintic(tr.q0, tr.q1, tr.duration, 0.001), tr.hold)
    return compute_metrics(ARM3, execute(ARM3, generate_urdf(ARM3), plan, controller, tr.duration, mjcf=mjcf))


def test_arm3_seed_trajectory_under_computed_torque_meets_the_bar():
    m = _seed_run("computed-torque")
    assert m.passed, m.reason
    assert m.rms_error <= 1e-4 and m.max_error <= 1e-3 and m.residual_speed < 1e-3


def test_seed_pid_reproduces_the_seed_failure():
    m = _seed_run("seed-pid")
    assert not m.passed
    assert abs(m.rms_error - 2.46) < 0.01  # the seed's figure, recomputed
    assert 130 < m.final_speed < 150  # "still 140 rad/s after a 2 s hold"
    assert "RMS joint error 2.46" in m.reason and "oscillating" in m.reason


def test_mjcf_mass_20_percent_off_degrades_computed_torque():
    nominal = _seed_run("computed-torque")
    wrong = _seed_run("computed-torque", mjcf=generate_mjcf(heavier_link(ARM3, 1)))
    assert wrong.rms_error > 10 * nominal.rms_error
    assert not wrong.passed


def _within_effort(spec, trajectory) -> bool:
    """The plan's inverse-dynamics torques stay below 80 % of every effort limit."""
    from kinverify.tracking.execute import pinocchio_dynamics

    pin = pinocchio_dynamics(spec, generate_urdf(spec))
    plan = quintic(trajectory.q0, trajectory.q1, trajectory.duration, 0.01)
    effort = np.array([j.limits.effort for j in spec.joints])
    return all(np.all(np.abs(pin.inverse(q, v, a)) < 0.8 * effort) for q, v, a in zip(plan.q, plan.qd, plan.qdd, strict=True))


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(kst.arm_specs(max_joints=4))
def test_computed_torque_tracks_random_specs(spec):
    trajectory = default_trajectory(spec)
    assume(_within_effort(spec, trajectory))  # a random arm may be too heavy for its default effort limits
    result = track(spec, generate_urdf(spec), trajectory, ["computed-torque"], render=False, plots=False)
    m = result.metrics[0]
    assert m.passed, m.reason
    assert m.rms_error <= 1e-4 and m.residual_speed < 1e-3


def test_saturation_is_named_as_the_reason():
    # a 10 kg stack lifted by a prismatic joint with the default 100 N effort limit
    spec = spec_from_dict(
        {
            "name": "lift",
            "base": {"rpy": [0.0, math.pi / 2, 0.0]},
            "joints": [
                {
                    "name": "j1",
                    "type": "prismatic",
                    "axis": [1, 0, 0],
                    "limits": {"lower": 0.0, "upper": 0.25, "unit": "m"},
                    "link": {"name": "l1", "mass": 2.0},
                }
            ]
            + [
                {
                    "name": f"j{i}",
                    "axis": [0, 0, 1],
                    "limits": {"lower": 0.0, "upper": 1.0, "unit": "rad"},
                    "link": {"name": f"l{i}", "mass": 2.0 if i < 4 else 4.0},
                }
                for i in (2, 3, 4)
            ],
            "tools": [{"name": "tool", "parent": "l4"}],
        }
    )
    m = track(spec, generate_urdf(spec), default_trajectory(spec), ["computed-torque"], render=False, plots=False).metrics[0]
    assert not m.passed and m.saturation > 0 and "effort limit" in m.reason


def test_divergence_is_a_failed_check_with_reason():
    spec = load_spec("models/scara.toml")  # the seed's loop blows up on the light prismatic joint
    result = track(spec, generate_urdf(spec), default_trajectory(spec), ["seed-pid"], render=False, plots=False)
    m = result.metrics[0]
    assert not m.passed and m.reason.startswith("diverged")
    check = next(c for c in result.checks if c.property == "tracking.seed-pid")
    assert not check.passed and check.note.startswith("diverged")


def test_no_gl_gives_a_note_not_a_crash(monkeypatch):
    monkeypatch.setenv("MUJOCO_GL", "glx")  # GLX without an X display: the renderer cannot start
    monkeypatch.delenv("DISPLAY", raising=False)
    tr = default_trajectory(ARM3)
    run = execute(ARM3, generate_urdf(ARM3), quintic(tr.q0, tr.q1, 0.2, 0.001), "position", 0.2)
    fig, reason = animation(run, generate_mjcf(ARM3), [0, 1, 2])
    assert fig is None and reason.startswith("rendering unavailable")


def test_tracking_suite_in_verify(tmp_path):
    code = main(
        [
            "verify",
            "models/arm3.toml",
            "--samples",
            "10",
            "--json",
            str(tmp_path / "r.json"),
            "--report",
            str(tmp_path / "r.html"),
            "--quiet",
        ]
    )
    assert code == 0
    data = json.loads((tmp_path / "r.json").read_text())
    checks = {c["property"]: c for c in data["checks"]}
    for name in ("tracking.plan", "tracking.computed-torque", "tracking.pd+gravity", "tracking.position"):
        assert checks[name]["passed"]
    assert checks["tracking.computed-torque"]["max_error"] <= 1e-4
    assert "tracking.seed-pid" not in checks  # the negative example is shown, not checked
    section = data["sections"]["tracking"]
    rows = {r[0]: r for r in section["tables"][0]["rows"]}
    assert rows["seed-pid"][1] == "no" and float(rows["seed-pid"][2]) > 2
    for fig in section["figures"]:
        assert base64.b64decode(fig["data"])[:5] in (b"<?xml", b"GIF89", b"\x89PNG\r")


@pytest.mark.parametrize(
    "argv, words",
    [
        (["--controller", "nope"], "unknown controller"),
        (["--to", "200", "0", "0", "--deg"], "outside its limits"),
        (["--duration", "0"], "must be positive"),
        (["--duration", "-2"], "must be positive"),
        (["--to", "1"], "needs 3 joint values"),
    ],
)
def test_track_bad_input_is_one_line_and_exit_2(argv, words, capsys):
    assert main(["track", "models/arm3.toml", *argv]) == 2
    err = capsys.readouterr().err
    assert words in err and err.count("\n") == 1


def test_track_seed_pid_exits_1_and_writes_json(tmp_path, capsys):
    path = tmp_path / "t.json"
    assert main(["track", "models/arm3.toml", "--controller", "seed-pid", "--json", str(path)]) == 1
    assert "seed-pid fails" in capsys.readouterr().out
    data = json.loads(path.read_text())
    check = next(c for c in data["checks"] if c["property"] == "tracking.seed-pid")
    move = np.linalg.norm(np.radians([60.0, 45.0, -30.0]))  # the seed's move, rad
    assert not check["passed"] and check["unit"] == "fraction of the move"
    assert math.isclose(check["max_error"] * move, 2.46, abs_tol=0.01)  # the seed's RMS joint error, rad
    metrics = data["sections"]["tracking"]["data"]["metrics"]
    assert math.isclose(metrics[0]["rms_error"], 2.46, abs_tol=0.01)


def test_track_to_a_target_passes():
    assert main(["track", "models/arm3.toml", "--to", "0.5", "-0.3", "0.4", "--duration", "1", "--hold", "0.3"]) == 0


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(kst.arm_specs(max_joints=5), kst.data())
def test_seed_mjcf_is_the_same_arm(spec, data):
    """The negative example runs on the same kinematic chain as kinverify's MJCF: only the seed's
    actuators, integrator, collisions and geometry-derived inertia differ."""
    import mujoco

    from kinverify.tracking.seed import seed_mjcf

    ours, seed = (mujoco.MjModel.from_xml_string(x) for x in (generate_mjcf(spec), seed_mjcf(spec)))
    d_ours, d_seed = mujoco.MjData(ours), mujoco.MjData(seed)
    q = data.draw(kst.configurations(spec))
    for j, name in enumerate(spec.joint_names):
        d_ours.qpos[ours.joint(name).qposadr[0]] = q[j]
        d_seed.qpos[seed.joint(name).qposadr[0]] = q[j]
    mujoco.mj_kinematics(ours, d_ours)
    mujoco.mj_kinematics(seed, d_seed)
    for link in spec.link_names:
        assert np.abs(d_ours.body(link).xpos - d_seed.body(link).xpos).max() < 1e-9
        assert np.abs(d_ours.body(link).xmat - d_seed.body(link).xmat).max() < 1e-9
    assert seed.opt.integrator == mujoco.mjtIntegrator.mjINT_RK4 and seed.nu == 2 * spec.dof


def test_computed_torque_gives_exactly_the_designed_acceleration_in_one_mujoco_step():
    """MuJoCo's Euler step treats joint damping implicitly: the acceleration it takes is
    (M + dt·D)⁻¹(τ − h − D·q̇). The computed torque includes the dt·D term, so one step away from
    the plan (position and speed errors) accelerates exactly as designed; without it arm3's damping
    0.1 leaves an error of order dt·D/M (about 1 % here)."""
    spec = load_spec("models/arm3.toml")
    pin = pinocchio_dynamics(spec, generate_urdf(spec))
    mj = MujocoDynamics(generate_mjcf(spec, actuators="motor"), spec.joint_names)
    dt = float(mj.model.opt.timestep)
    plan = quintic([0.0, 0.2, -0.3], [0.5, 0.8, -1.0], 0.5, dt)
    ctl = make_controller("computed-torque", spec, pin, plan, dt)
    k = len(plan.t) // 3
    q, qd = plan.q[k] + [0.01, -0.02, 0.015], plan.qd[k] + [0.1, -0.2, 0.05]
    designed = plan.qdd[k] + ctl.kp * (plan.q[k] - q) + ctl.kd * (plan.qd[k] - qd)
    m, d = mj.model, mj.data
    d.qpos[mj.qadr], d.qvel[mj.vadr] = q, qd
    d.ctrl[:3] = ctl(k, q, qd)
    mujoco.mj_step(m, d)
    taken = (d.qvel[mj.vadr] - qd) / dt
    assert np.allclose(taken, designed, rtol=1e-7, atol=1e-7), (taken, designed)
