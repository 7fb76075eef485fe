"""The driver shared by suite ``tracking`` and ``kinverify track``: plan, execute under each
controller, measure.

On ``arm3`` the seed trajectory (0 → (60°, 45°, −30°) in 2 s, then a 2 s hold); on other models
a short default move (1 s, then a 0.5 s hold). Each controller gives one performance check
``tracking.<controller>``: the RMS joint error over the motion (rad, or m for prismatic joints),
or for controllers judged relative to the move (pd+gravity, position, seed-pid) that RMS as a
fraction of the move ``||q1 − q0||``; ``tracking.plan`` checks the plan against the joint and
speed limits.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from kinverify.errors import InputError
from kinverify.model.spec import ArmSpec
from kinverify.suites.base import PERFORMANCE, Check, Property, Section, VerifyOptions, joint_unit, value_check
from kinverify.tracking.controllers import CONTROLLERS
from kinverify.tracking.execute import Run, execute
from kinverify.tracking.figures import animations, error_plot, joint_plot
from kinverify.tracking.metrics import CRITERIA, Metrics, compute_metrics
from kinverify.tracking.quintic import hold, plan_violations, quintic


def _controller_property(name: str) -> Property:
    c = CRITERIA[name]
    if c.relative:
        return Property(
            f"tracking.{name}",
            "fraction of the move",
            c.rms,
            PERFORMANCE,
            f"{name}: RMS joint error over the motion as a fraction of the move ||q1 − q0||",
        )
    return Property(f"tracking.{name}", "joint", c.rms, PERFORMANCE, f"{name}: RMS joint error over the motion [rad or m]")


PROPERTIES = {
    p.name: p
    for p in [_controller_property(c) for c in CONTROLLERS]
    + [Property("tracking.plan", "joint", 0.0, PERFORMANCE, "the planned trajectory's excess over joint and speed limits")]
}

SEED_TARGET = tuple(math.radians(a) for a in (60.0, 45.0, -30.0))
VERIFY_CONTROLLERS = ("computed-torque", "pd+gravity", "position")
NEGATIVE_EXAMPLE = "seed-pid"


@dataclass
class Trajectory:
    q0: np.ndarray
    q1: np.ndarray
    duration: float
    hold: float


@dataclass
class TrackResult:
    trajectory: Trajectory
    runs: list[Run]
    metrics: list[Metrics]
    checks: list[Check]
    section: Section | None = None


def default_trajectory(spec: ArmSpec) -> Trajectory:
    """The seed trajectory on arm3; elsewhere a 1 s move of up to 0.3 rad (0.05 m) per joint from
    zero towards the roomier side. Zero is first moved 5 % of the range away from a limit: MuJoCo
    applies its (soft) limit constraint at the limit, which no controller here models."""
    if spec.name == "arm3" and spec.dof == 3:
        return Trajectory(np.zeros(3), np.array(SEED_TARGET), 2.0, 2.0)
    margin = 0.05 * (spec.upper - spec.lower)
    q0 = np.clip(np.zeros(spec.dof), spec.lower + margin, spec.upper - margin)
    step = np.array([0.3 if j.type == "revolute" else 0.05 for j in spec.joints])
    room_up, room_down = spec.upper - q0, q0 - spec.lower
    q1 = np.where(room_up >= room_down, q0 + np.minimum(step, 0.5 * room_up), q0 - np.minimum(step, 0.5 * room_down))
    return Trajectory(q0, q1, 1.0, 0.5)


def validate_target(spec: ArmSpec, q1, duration: float) -> np.ndarray:
    q1 = np.asarray(q1, dtype=float)
    if q1.shape != (spec.dof,):
        raise InputError(f"--to needs {spec.dof} joint values ({', '.join(spec.joint_names)}), got {q1.size}")
    if not math.isfinite(duration) or duration <= 0:
        raise InputError(f"--duration must be positive, got {duration:g}")
    for v, joint in zip(q1, spec.joints, strict=True):  # q1.shape == (dof,) checked above
        if not joint.limits.lower <= v <= joint.limits.upper:
            raise InputError(f"--to: {joint.name} = {v:g} is outside its limits [{joint.limits.lower:g}, {joint.limits.upper:g}]")
    return q1


def plan_check(spec: ArmSpec, plan, options: VerifyOptions | None) -> Check:
    vmax = [j.limits.velocity for j in spec.joints]
    problems = plan_violations(plan, spec.lower, spec.upper, vmax)
    excess = max(
        0.0,
        float(np.max(plan.q - spec.upper)),
        float(np.max(spec.lower - plan.q)),
        float(np.max(np.abs(plan.qd) - np.asarray(vmax))),
    )
    unit = joint_unit(j.type == "revolute" for j in spec.joints)
    return value_check(
        PROPERTIES["tracking.plan"],
        options,
        "joints",
        ("plan", "limits"),
        excess,
        plan.q[-1],
        samples=len(plan.t),
        unit=f"{unit} or {unit}/s",
        note="; ".join(problems) or "inside joint and speed limits",
    )


def run_check(spec: ArmSpec, run: Run, m: Metrics, options: VerifyOptions | None) -> Check:
    err = np.linalg.norm(run.plan.q[: len(run.q)] - run.q, axis=1)
    worst = run.q[int(np.argmax(err))] if len(err) else run.plan.q[0]
    c = CRITERIA[run.controller]
    move = float(np.linalg.norm(run.plan.q[-1] - run.plan.q[0]))
    unit = joint_unit(j.type == "revolute" for j in spec.joints)
    rms_limit, max_limit = c.limits(move)
    note = m.reason or (
        f"RMS {m.rms_error:.3g} {unit}, max {m.max_error:.2e} {unit}, final {m.final_error:.2e} {unit}, "
        f"residual speed {m.residual_speed:.2e} {unit}/s; criteria RMS {rms_limit:.3g}, max {max_limit:.3g}, "
        f"speed {c.residual_speed:g}"
    )
    frame = spec.tool_names[0] if spec.tools else spec.link_names[-1]
    error = m.rms_error / move if c.relative and move > 0 else m.rms_error
    if m.diverged or not np.isfinite(error):
        error = float("inf")  # a run that left the plan for good has no finite tracking error
    return value_check(
        PROPERTIES[f"tracking.{run.controller}"],
        options,
        frame,
        ("plan", "mujoco"),
        error,
        worst,
        note=note,
        unit="fraction of the move" if c.relative else unit,
        samples=len(err),
    )


def _fmt(x) -> str:
    return "-" if x is None else f"{x:.3g}"


def track(
    spec: ArmSpec,
    urdf: str,
    trajectory: Trajectory,
    controllers,
    checked=None,
    render: bool = True,
    plots: bool = True,
    animate=None,
    plan=None,
    options: VerifyOptions | None = None,
) -> TrackResult:
    """Plan, execute under each controller, measure; ``checked``: controllers that become checks
    (default: all). ``plots``/``render``: matplotlib figures / offscreen GIF in the section;
    ``animate``: controllers to animate (default: computed-torque and the negative example);
    ``plan``: a ready plan (e.g. several segments, hold included) instead of one quintic."""
    checked = list(controllers) if checked is None else list(checked)
    if plan is None:
        plan = hold(quintic(trajectory.q0, trajectory.q1, trajectory.duration, 0.001), trajectory.hold)
    checks = [plan_check(spec, plan, options)]
    runs, metrics = [], []
    report = (options.on_progress if options is not None else None) or (lambda done, total: None)
    steps = len(controllers) + bool(render)  # each controller's run, then the animation
    for k, name in enumerate(controllers):
        report(k, steps)
        run = execute(spec, urdf, plan, name, trajectory.duration)
        m = compute_metrics(spec, run)
        runs.append(run)
        metrics.append(m)
        if name in checked:
            checks.append(run_check(spec, run, m, options))
    rows = [
        [
            m.controller,
            "yes" if m.passed else "no",
            _fmt(m.rms_error),
            _fmt(m.max_error),
            _fmt(m.final_error),
            _fmt(m.ee_path_deviation),
            _fmt(m.overshoot),
            _fmt(m.settling_time),
            _fmt(m.residual_speed),
            _fmt(m.final_speed),
            _fmt(m.error_energy),
            _fmt(m.max_effort),
            f"{100 * m.saturation:.3g}",
            m.reason or ("checked" if m.controller in checked else ""),
        ]
        for m in metrics
    ]
    for row in rows:
        if row[0] not in checked:
            row[-1] = f"negative example, not a check: {row[-1]}"
    figures = [error_plot(runs)] + [joint_plot(r, spec.joint_names) for r in runs[:1]] if plots and runs else []
    notes = []
    if render and runs:
        from kinverify.generate import generate_mjcf
        from kinverify.model.kinematics import frame_poses
        from kinverify.tracking.models import MujocoDynamics

        tool = spec.frame_names.index(spec.tool_names[0] if spec.tools else spec.link_names[-1])
        scene = generate_mjcf(spec, target=frame_poses(spec, trajectory.q1)[0, tool, :3, 3])  # marker at the goal
        qadr = MujocoDynamics(scene, spec.joint_names).qadr
        if animate is None:
            animate = [r.controller for r in runs if r.controller in ("computed-torque", NEGATIVE_EXAMPLE)][:2] or [
                runs[0].controller
            ]
        wanted = [r for r in runs if r.controller in animate]
        gifs, reason = animations(wanted, scene, qadr) if wanted else ([], "")
        figures += [
            dataclasses.replace(fig, caption=fig.caption + "; translucent green sphere: the goal of the tool") for fig in gifs
        ]
        if reason:
            notes.append(f"{reason} (animation of {', '.join(r.controller for r in wanted)})")
    report(steps, steps)
    deg = ", ".join(
        f"{math.degrees(v):.4g}" if j.type == "revolute" else f"{v:.4g} m"
        for v, j in zip(trajectory.q1, spec.joints, strict=True)
    )
    u = joint_unit(j.type == "revolute" for j in spec.joints)
    force = "N·m" if u == "rad" else "N" if u == "m" else "N·m|N"
    section = Section(
        "Trajectory tracking (MuJoCo on the MJCF, model terms from Pinocchio on the URDF)",
        f"quintic from q0 to ({deg}) in {trajectory.duration:g} s, then a {trajectory.hold:g} s hold; "
        + "; ".join(f"{m.controller}: {'ok' if m.passed else 'below its goal'} (RMS {m.rms_error:.3g} {u})" for m in metrics),
        figures=figures,
        data={"metrics": [m.to_dict() for m in metrics]},
    )
    section.table(
        "Metrics per controller",
        [
            "controller",
            "meets its goals",
            f"RMS error [{u}]",
            f"max error [{u}]",
            f"final error [{u}]",
            "ee path deviation [m]",
            f"overshoot [{u}]",
            "settling time [s]",
            f"residual speed [{u}/s]",
            f"speed at end of hold [{u}/s]",
            f"hold error energy [{u}²·s]",
            f"max effort [{force}]",
            "at effort limit [%]",
            "reason",
        ],
        rows,
    )
    section.notes += notes + [
        "RMS error is sqrt(mean ||q_d − q||²) over the motion; residual speed is the max ||q̇|| from 0.2 s after the end "
        "of the motion.",
        "Tracking measures a controller's performance on the model, not whether the models agree: it is shown against "
        "its goals and does not decide the verdict unless gated (--gate tracking.<controller>).",
        "seed-pid: the seed's PID written into position-actuator ctrl, with velocity actuators, RK4 and colliding geoms, "
        "on the seed's MJCF pattern.",
    ]
    return TrackResult(trajectory, runs, metrics, checks, section)
