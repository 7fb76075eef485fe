"""Suite ``tracking`` and the shared driver of ``kinverify track``.

On ``arm3`` the seed trajectory (0 → (60°, 45°, −30°) in 2 s, then a 2 s hold); on other models
a short default move (1 s, then a 0.5 s hold). Each controller gives one check
``tracking.<controller>`` whose error is the RMS joint error over the motion; ``tracking.plan``
checks the plan against the joint and speed limits. In ``verify`` the seed's loop (``seed-pid``)
runs as the negative example shown in the section, not as a check, so ``verify`` passes when the
models agree; ``kinverify track --controller seed-pid`` checks it (and fails).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..results import Check
from ..spec import ArmSpec
from .controllers import CONTROLLERS
from .execute import Run, execute
from .figures import animations, error_plot, joint_plot
from .metrics import CRITERIA, Metrics, compute_metrics
from .quintic import hold, plan_violations, quintic

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
    section: dict = field(default_factory=dict)


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
    for j, (v, joint) in enumerate(zip(q1, spec.joints)):
        if not joint.limits.lower <= v <= joint.limits.upper:
            raise InputError(f"--to: {joint.name} = {v:g} is outside its limits [{joint.limits.lower:g}, {joint.limits.upper:g}]")
    return q1


def _plan_check(spec: ArmSpec, plan) -> Check:
    vmax = [j.limits.velocity for j in spec.joints]
    problems = plan_violations(plan, spec.lower, spec.upper, vmax)
    excess = max(0.0, float(np.max(plan.q - spec.upper)), float(np.max(spec.lower - plan.q)),
                 float(np.max(np.abs(plan.qd) - np.asarray(vmax))))
    return Check("tracking.plan", "joints", ("plan", "limits"), excess, excess, 0.0, not problems, tuple(plan.q[-1].tolist()),
                 "rad or rad/s", len(plan.t), (), "; ".join(problems) or "inside joint and speed limits")


def _check(spec: ArmSpec, run: Run, m: Metrics) -> Check:
    err = np.linalg.norm(run.plan.q[: len(run.q)] - run.q, axis=1)
    worst = tuple((run.q[int(np.argmax(err))] if len(err) else run.plan.q[0]).tolist())
    c = CRITERIA[run.controller]
    rms_limit, max_limit = c.limits(float(np.linalg.norm(run.plan.q[-1] - run.plan.q[0])))
    note = m.reason or (f"max {m.max_error:.2e} rad, final {m.final_error:.2e} rad, residual speed {m.residual_speed:.2e} rad/s; "
                        f"limits RMS {rms_limit:.3g}, max {max_limit:.3g}, speed {c.residual_speed:g}")
    frame = spec.tool_names[0] if spec.tools else spec.link_names[-1]
    p99 = float(np.percentile(err, 99)) if len(err) else float("inf")
    return Check(f"tracking.{run.controller}", frame, ("plan", "mujoco"), m.rms_error, p99, rms_limit, m.passed, worst,
                 "rad", len(err), (), note)


def _fmt(x) -> str:
    return "-" if x is None else f"{x:.3g}"


def track(spec: ArmSpec, urdf: str, trajectory: Trajectory, controllers, checked=None, render: bool = True,
          plots: bool = True, animate=None, plan=None) -> TrackResult:
    """Plan, execute under each controller, measure; ``checked``: controllers that become checks
    (default: all). ``plots``/``render``: matplotlib figures / offscreen GIF in the section;
    ``animate``: controllers to animate (default: computed-torque and the negative example);
    ``plan``: a ready plan (e.g. several segments, hold included) instead of one quintic."""
    checked = list(controllers) if checked is None else list(checked)
    if plan is None:
        plan = hold(quintic(trajectory.q0, trajectory.q1, trajectory.duration, 0.001), trajectory.hold)
    checks = [_plan_check(spec, plan)]
    runs, metrics = [], []
    for name in controllers:
        run = execute(spec, urdf, plan, name, trajectory.duration)
        m = compute_metrics(spec, run)
        runs.append(run)
        metrics.append(m)
        if name in checked:
            checks.append(_check(spec, run, m))
    rows = [[m.controller, "ok" if m.passed else "FAIL", _fmt(m.rms_error), _fmt(m.max_error), _fmt(m.final_error),
             _fmt(m.ee_path_deviation), _fmt(m.overshoot), _fmt(m.settling_time), _fmt(m.residual_speed), _fmt(m.final_speed),
             _fmt(m.error_energy), _fmt(m.max_effort), f"{100 * m.saturation:.3g}", m.reason or ("checked" if m.controller in checked else "")]
            for m in metrics]
    for row in rows:
        if row[0] not in checked:
            row[-1] = f"negative example, not a check: {row[-1]}"
    figures = [error_plot(runs)] + [joint_plot(r, spec.joint_names) for r in runs[:1]] if plots and runs else []
    notes = []
    if render and runs:
        from ..generate import generate_mjcf
        from ..kinematics import frame_poses
        from .models import MujocoDynamics

        tool = spec.frame_names.index(spec.tool_names[0] if spec.tools else spec.link_names[-1])
        scene = generate_mjcf(spec, target=frame_poses(spec, trajectory.q1)[0, tool, :3, 3])  # marker at the goal
        qadr = MujocoDynamics(scene, spec.joint_names).qadr
        if animate is None:
            animate = [r.controller for r in runs if r.controller in ("computed-torque", NEGATIVE_EXAMPLE)][:2] or [runs[0].controller]
        wanted = [r for r in runs if r.controller in animate]
        gifs, reason = animations(wanted, scene, qadr) if wanted else ([], "")
        for fig in gifs:
            fig["caption"] += "; translucent green sphere: the goal of the tool"
        figures += gifs
        if reason:
            notes.append(f"{reason} (animation of {', '.join(r.controller for r in wanted)})")
    deg = ", ".join(f"{math.degrees(v):.4g}" for v in trajectory.q1)
    section = {
        "title": "Trajectory tracking (MuJoCo on the MJCF, model terms from Pinocchio on the URDF)",
        "summary": f"quintic from q0 to ({deg}) deg in {trajectory.duration:g} s, then a {trajectory.hold:g} s hold; "
                   + "; ".join(f"{m.controller}: {'ok' if m.passed else 'FAIL'} (RMS {m.rms_error:.3g} rad)" for m in metrics),
        "tables": [{"title": "Metrics per controller",
                    "columns": ["controller", "verdict", "RMS error [rad]", "max error [rad]", "final error [rad]",
                                "ee path deviation [m]", "overshoot [rad]", "settling time [s]", "residual speed [rad/s]",
                                "speed at end of hold [rad/s]", "hold error energy [rad²·s]", "max effort [N·m]", "at effort limit [%]", "reason"],
                    "rows": rows}],
        "figures": figures,
        "notes": notes + ["RMS error is sqrt(mean ||q_d − q||²) over the motion; residual speed is the max ||q̇|| from 0.2 s "
                          "after the end of the motion.",
                          "seed-pid: the seed's PID written into position-actuator ctrl, with velocity actuators, RK4 and "
                          "colliding geoms, on the seed's MJCF pattern."],
        "metrics": [m.to_dict() for m in metrics],
    }
    return TrackResult(trajectory, runs, metrics, checks, section)


def tracking_suite(ctx):
    from ..verify import SuiteResult

    spec = ctx.sources.spec
    if spec is None or not ctx.sources.urdf:
        return SuiteResult([], {"title": "Trajectory tracking", "summary": "skipped: tracking needs a spec (file mode has none)",
                                "tables": [], "figures": [], "notes": []})
    controllers = ctx.options.extra.get("tracking_controllers")
    if controllers is None:
        controllers, checked = list(VERIFY_CONTROLLERS) + [NEGATIVE_EXAMPLE], list(VERIFY_CONTROLLERS)
    else:
        unknown = [c for c in controllers if c not in CONTROLLERS]
        if unknown:
            raise InputError(f"unknown controller {unknown[0]!r}; controllers: {', '.join(CONTROLLERS)}")
        checked = list(controllers)
    main = [c for c in controllers if c == "computed-torque"] or list(controllers[:1])  # one small GIF keeps the page light
    result = track(spec, ctx.sources.urdf, default_trajectory(spec), controllers, checked, animate=main)
    return SuiteResult(result.checks, result.section)
