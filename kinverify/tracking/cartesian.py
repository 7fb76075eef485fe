"""Quintic joint trajectories to Cartesian targets, through the IK of :mod:`kinverify.ik`.

Each target (a tool-frame position, or a full pose with roll-pitch-yaw on arms with ≥ 6 joints)
is solved with the Levenberg-Marquardt solver on the ``pinocchio-urdf`` (default) or
``analytic`` backend: one solve starts at the previous configuration (with random restarts),
:data:`EXTRA_STARTS` more start at random configurations, and on ``arm3``-shaped arms every
closed-form branch inside the limits is added. Among the candidates whose residual is within
:data:`IK_TOL`, the one closest to the previous configuration (Euclidean joint distance; a
revolute joint whose range spans 2π is taken the short way round) is kept. The joint waypoints
then become a rest-to-rest quintic per segment (:func:`~.quintic.through_waypoints`).

A target no candidate reaches raises :class:`UnreachableError` (an :class:`InputError`: the CLI
prints one line with the closest approach found and exits 2) — there is nothing to execute.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kinverify.errors import InputError
from kinverify.ik import Arm3ClosedForm, FrameModel, IKOptions, residuals, solve_lm
from kinverify.ik.lm import wrappable
from kinverify.model.kinematics import frame_poses
from kinverify.model.spec import ArmSpec
from kinverify.model.transforms import make_transform, rpy_to_matrix
from kinverify.tracking.quintic import Plan, through_waypoints

IK_TOL = 1e-9  # m and rad: a candidate counts as a solution within this residual
EXTRA_STARTS = 8  # random-start solves besides the one from the previous configuration
SPEED_MARGIN = 0.8  # the automatic duration keeps the quintic's peak speed at 80 % of the limit
QUINTIC_PEAK = 1.875  # peak speed of a rest-to-rest quintic is 15/8 · |Δ| / T
# ...and at most the seed trajectory's peak speed (0.98 rad/s), where computed-torque's 1e-4 rad
# RMS bar was set: its error grows with the plan's acceleration (0.25 m/s for prismatic joints)
CRUISE_SPEED = {"revolute": 1.0, "prismatic": 0.25}


class UnreachableError(InputError):
    """No IK candidate reaches the target; ``closest`` [m] is the closest approach found."""

    def __init__(self, message: str, closest: float, q_closest: np.ndarray) -> None:
        super().__init__(message)
        self.closest, self.q_closest = closest, q_closest


@dataclass
class IKChoice:
    """The configuration chosen for one target and how it was found."""

    target: np.ndarray  # 4×4 (position-only: only the translation counts)
    q: np.ndarray
    pos_error: float  # m, from the solver backend's FK
    rot_error: float  # rad (0 for position-only)
    candidates: int  # distinct solutions found (closed-form branches included)
    distance: float  # joint distance from the previous configuration
    source: str  # "lm" or "closed-form"


@dataclass
class CartesianPlan:
    spec_name: str
    frame: str
    backend: str
    position_only: bool
    q_start: np.ndarray
    choices: list[IKChoice]
    durations: list[float]

    @property
    def waypoints(self) -> np.ndarray:
        return np.array([self.q_start] + [c.q for c in self.choices])

    @property
    def duration(self) -> float:
        return float(sum(self.durations))

    def plan(self, dt: float) -> Plan:
        return through_waypoints(self.waypoints, self.durations, dt)


def parse_target(xyz, rpy=None) -> tuple[np.ndarray, bool]:
    """``(T 4×4, position_only)`` from 3 position values [m] and optionally 3 rpy angles [rad]."""
    xyz = _finite("--target", xyz)
    if rpy is None or len(rpy) == 0:
        return make_transform(np.eye(3), xyz), True
    return make_transform(rpy_to_matrix(_finite("--rpy", rpy)), xyz), False


def _finite(name: str, values) -> np.ndarray:
    values = list(values)
    if len(values) != 3:
        raise InputError(f"{name} needs 3 values, got {len(values)}")
    out = []
    for v in values:
        try:
            x = float(v)
        except (TypeError, ValueError):
            raise InputError(f"{name}: not a number: {v!r}") from None
        if not math.isfinite(x):
            raise InputError(f"{name}: values must be finite, got {v!r}")
        out.append(x)
    return np.array(out)


def default_frame(spec: ArmSpec) -> str:
    """The frame ``kinverify ik`` places by default: the last frame (the last tool when there is one)."""
    return spec.frame_names[-1]


def ik_model(spec: ArmSpec, backend: str | None = None, frame: str | None = None) -> FrameModel:
    """The IK view of ``frame`` on ``backend`` (``pinocchio-urdf`` when available, else ``analytic``)."""
    from kinverify.backends import ModelSources, available_backends, build_backend

    registry = available_backends()
    name = backend or ("pinocchio-urdf" if registry["pinocchio-urdf"].available else "analytic")
    if name not in ("analytic", "pinocchio-urdf"):
        raise InputError(f"IK backend must be analytic or pinocchio-urdf, got {name!r}")
    sources = ModelSources.from_spec(spec)
    return FrameModel(build_backend(name, sources), frame or default_frame(spec), sources.revolute)


def nearest_equivalent(q: np.ndarray, ref: np.ndarray, lower, upper, wrap) -> np.ndarray:
    """``q`` with each wrappable joint moved by a multiple of 2π (same pose) to lie as close to
    ``ref`` as its limits allow."""
    q = np.array(q, dtype=float)
    for j in np.flatnonzero(wrap):
        options = q[j] + 2 * np.pi * np.arange(-2, 3)
        options = options[(options >= lower[j] - 1e-12) & (options <= upper[j] + 1e-12)]
        if len(options):
            q[j] = float(np.clip(options[np.argmin(np.abs(options - ref[j]))], lower[j], upper[j]))
    return q


def solve_target(
    spec: ArmSpec,
    model: FrameModel,
    target: np.ndarray,
    position_only: bool,
    q_ref: np.ndarray,
    seed: int = 0,
    extra_starts: int = EXTRA_STARTS,
) -> IKChoice:
    """The IK solution of ``target`` closest to ``q_ref`` (see the module docstring)."""
    lower, upper = spec.lower, spec.upper
    wrap = wrappable(lower, upper, model)
    first = solve_lm(model, target[None], lower, upper, position_only, IKOptions(seed=seed), q0=q_ref[None])
    spread = (
        solve_lm(
            model,
            np.repeat(target[None], extra_starts, axis=0),
            lower,
            upper,
            position_only,
            IKOptions(seed=seed + 1, max_restarts=0),
        )
        if extra_starts
        else None
    )
    qs, sources = [first.q], ["lm"]
    if spread is not None:
        qs.append(spread.q)
        sources += ["lm"] * extra_starts
    closed = _closed_form(spec, model.frame) if position_only else None
    if closed is not None:
        branches = closed.solve(target[:3, 3]).solutions
        qs.append(branches.reshape(-1, spec.dof))
        sources += ["closed-form"] * len(branches)
    q_all = np.concatenate(qs)
    pos, rot = residuals(model.poses(q_all), np.repeat(target[None], len(q_all), axis=0), position_only)
    ok = (pos <= IK_TOL) & (rot <= IK_TOL) & np.all((q_all >= lower) & (q_all <= upper), axis=1)
    if not ok.any():
        k = int(np.argmin(pos + rot))
        what = f"{pos[k]:.3e} m" + ("" if position_only else f", {rot[k]:.3e} rad")
        also = (
            ""
            if closed is None
            else f"; closed form: no branch inside the limits, closest {closed.closest_distance(target[:3, 3]):.3e} m"
        )
        raise UnreachableError(
            f"{model.frame} cannot reach xyz = {_fmt(target[:3, 3])} m"
            + ("" if position_only else " with that rpy")
            + f": closest approach {what} at q = {_fmt(q_all[k])} ({int(first.restarts[0]) + 1 + extra_starts} IK starts{also})",
            float(pos[k]),
            q_all[k],
        )
    candidates = [nearest_equivalent(q, q_ref, lower, upper, wrap) for q in q_all[ok]]
    where = np.flatnonzero(ok)
    dist = [float(np.linalg.norm(q - q_ref)) for q in candidates]
    best = int(np.argmin(dist))
    distinct: list[np.ndarray] = []
    for q in candidates:
        if not any(np.abs(q - p).max() <= 1e-6 for p in distinct):
            distinct.append(q)
    q = candidates[best]
    p, r = residuals(model.poses(q[None]), target[None], position_only)
    return IKChoice(target, q, float(p[0]), float(r[0]), len(distinct), dist[best], sources[where[best]])


def _closed_form(spec: ArmSpec, frame: str) -> Arm3ClosedForm | None:
    """The closed-form solver when ``spec`` has the arm3 shape and ``frame`` is its tool."""
    if frame not in spec.tool_names:
        return None
    try:
        return Arm3ClosedForm.from_spec(spec, frame)
    except InputError:
        return None


def auto_duration(spec: ArmSpec, qa, qb, minimum: float) -> float:
    """At least ``minimum`` s, and long enough that the quintic's peak speed stays within
    :data:`SPEED_MARGIN` of every joint's speed limit and :data:`CRUISE_SPEED` (rounded up to 0.1 s)."""
    vmax = np.array([min(SPEED_MARGIN * j.limits.velocity, CRUISE_SPEED[j.type]) for j in spec.joints])
    need = QUINTIC_PEAK * float(np.max(np.abs(np.asarray(qb) - np.asarray(qa)) / vmax))
    return max(float(minimum), math.ceil(need * 10 - 1e-9) / 10)


def plan_cartesian(
    spec: ArmSpec,
    targets,
    q_start,
    durations=None,
    position_only: bool = True,
    backend: str | None = None,
    frame: str | None = None,
    min_duration: float = 1.0,
    seed: int = 0,
) -> CartesianPlan:
    """Solve each target in turn (each preferring the solution closest to the previous one) and
    plan quintic segments through them. ``durations``: one per segment, or None (automatic)."""
    targets = np.asarray(targets, dtype=float).reshape(-1, 4, 4)
    if not position_only and spec.dof < 6:
        raise InputError(f"{spec.name} has {spec.dof} joints: a full-pose target (--rpy) needs at least 6; give a position only")
    q_start = np.asarray(q_start, dtype=float)
    model = ik_model(spec, backend, frame)
    choices, q_ref = [], q_start
    for k, target in enumerate(targets):
        choice = solve_target(spec, model, target, position_only, q_ref, seed + 2 * k)
        choices.append(choice)
        q_ref = choice.q
    points = [q_start] + [c.q for c in choices]
    if durations is None:
        durations = [auto_duration(spec, a, b, min_duration) for a, b in zip(points[:-1], points[1:], strict=False)]
    else:
        durations = [float(d) for d in np.atleast_1d(durations)]
        if len(durations) == 1 and len(choices) > 1:
            durations = durations * len(choices)
        for d in durations:
            if not (math.isfinite(d) and d > 0):
                raise InputError(f"--duration must be positive, got {d:g}")
    return CartesianPlan(spec.name, model.frame, model.name, position_only, q_start, choices, durations)


def end_effector_errors(
    spec: ArmSpec, frame: str, q: np.ndarray, target: np.ndarray, position_only: bool = True
) -> tuple[float, float]:
    """Position error [m] and rotation error [rad] (0 for position-only) of ``frame`` at
    configuration ``q`` against ``target``, by the analytic FK."""
    pose = frame_poses(spec, np.asarray(q, float)[None])[0, spec.frame_names.index(frame)]
    p, r = residuals(pose[None], np.asarray(target, float)[None], position_only)
    return float(p[0]), float(r[0])


def _fmt(v) -> str:
    return "[" + ", ".join(f"{float(x):.6g}" for x in v) + "]"


def end_of_motion_index(run) -> int:
    """Sample index of the end of the motion in ``run`` (its last sample if it stopped early)."""
    return min(len(run.q) - 1, int(round(run.motion_end / run.plan.dt)))


def track_waypoints(spec: ArmSpec, urdf: str, cplan: CartesianPlan, hold_s: float, controllers, options=None):
    """Execute a multi-segment Cartesian plan under each controller: the same checks and
    section table as :func:`~.suite.track` (which plans one segment), without figures."""
    from kinverify.tracking.quintic import hold
    from kinverify.tracking.track import Trajectory, track

    motion = cplan.plan(0.001)
    trajectory = Trajectory(cplan.q_start, cplan.choices[-1].q, motion.duration, hold_s)
    result = track(spec, urdf, trajectory, controllers, plots=False, render=False, plan=hold(motion, hold_s), options=options)
    assert result.section is not None  # track always makes its section
    result.section.title = "Trajectory tracking through Cartesian waypoints"
    result.section.summary = (
        f"{len(cplan.choices)} waypoints for {cplan.frame} solved by IK ({cplan.backend}), "
        f"quintic segments of {', '.join(f'{d:g}' for d in cplan.durations)} s, then a {hold_s:g} s hold"
    )
    return result
