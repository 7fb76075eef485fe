"""Metrics of one run and the pass/fail judgement of a controller.

Joint error ``e = q_d − q`` is taken as a vector per sample; its size is the 2-norm [rad, or m
for prismatic joints]. ``rms_error`` is ``sqrt(mean ||e||²)`` over the motion (the seed's "RMS
joint error"); the hold is the time after the motion, with the goal held.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from kinverify.model.kinematics import frame_poses
from kinverify.model.spec import ArmSpec
from kinverify.tracking.execute import Run

SETTLE_BAND = 1e-3  # rad: settled once ||e|| stays below this
RESIDUAL_DELAY = 0.2  # s after the end of the motion from which the residual speed is measured


@dataclass(frozen=True)
class Criteria:
    """What a controller must achieve: RMS and max joint error over the motion [rad], and max
    joint speed [rad/s] in the hold from ``RESIDUAL_DELAY`` after the end of the motion. With
    ``relative``, ``rms`` and ``max`` are fractions of the move's size ``||q1 − q0||``."""

    rms: float
    max: float
    residual_speed: float
    relative: bool = False

    def limits(self, move: float) -> tuple[float, float]:
        scale = move if self.relative else 1.0
        return self.rms * scale, self.max * scale


# computed-torque: the absolute bar. pd+gravity and position (no feedforward; position
# has no gravity compensation either) lag by about 2·q̇/ω, so their error grows with the move:
# they must stay within 15 % (RMS) and 25 % (max) of it and come to rest (below 0.1 rad/s
# 0.2 s after the end; the coupled joints of a 7-DOF arm settle more slowly than one joint).
# seed-pid is held to the bar of the position servos it drives.
CRITERIA = {
    "computed-torque": Criteria(1e-4, 1e-3, 1e-3),
    "pd+gravity": Criteria(0.15, 0.25, 0.1, relative=True),
    "position": Criteria(0.15, 0.25, 0.1, relative=True),
    "seed-pid": Criteria(0.15, 0.25, 0.1, relative=True),
}


@dataclass(frozen=True)
class Metrics:
    controller: str
    rms_error: float  # rad, over the motion
    max_error: float  # rad, over the whole run
    final_error: float  # rad, at the end of the motion
    hold_final_error: float  # rad, at the end of the run
    ee_path_deviation: float  # m, max distance between the planned and the executed tool path
    overshoot: float  # rad, largest excursion past the goal along the direction of motion
    settling_time: float | None  # s after the end of the motion until ||e|| stays < SETTLE_BAND
    residual_speed: float  # rad/s, max ||q̇|| from RESIDUAL_DELAY after the end
    final_speed: float  # rad/s, ||q̇|| at the end of the run
    error_energy: float  # rad²·s, ∫||e||² dt over the hold
    max_effort: float  # N·m, largest applied joint force
    saturation: float  # fraction of steps with some joint force at its effort limit
    diverged: str
    passed: bool
    reason: str

    def to_dict(self) -> dict:
        return asdict(self)


def compute_metrics(spec: ArmSpec, run: Run, criteria: Criteria | None = None) -> Metrics:
    criteria = criteria or CRITERIA[run.controller]
    t, q = run.t, run.q
    qd_plan = run.plan.q[: len(q)]
    if len(q) < 2:
        inf = float("inf")
        return Metrics(
            run.controller,
            inf,
            inf,
            inf,
            inf,
            inf,
            inf,
            None,
            inf,
            inf,
            inf,
            inf,
            0.0,
            run.diverged or "no samples",
            False,
            run.diverged or "no samples",
        )
    err = np.linalg.norm(qd_plan - q, axis=1)
    motion, after = t <= run.motion_end + 1e-12, t > run.motion_end + 1e-12
    dt = run.plan.dt
    tool = spec.tool_names[0] if spec.tools else spec.link_names[-1]
    f = spec.frame_names.index(tool)
    path = np.linalg.norm(frame_poses(spec, qd_plan)[:, f, :3, 3] - frame_poses(spec, q)[:, f, :3, 3], axis=1)
    goal, start = run.plan.q[-1], run.plan.q[0]
    direction = np.sign(goal - start)
    overshoot = float(np.max(np.clip((q - goal) * direction, 0.0, None) * (direction != 0)))
    speed = np.linalg.norm(run.qd, axis=1)
    effort = np.array([j.limits.effort for j in spec.joints])
    late = t >= run.motion_end + RESIDUAL_DELAY - 1e-12
    outside = np.nonzero(err >= SETTLE_BAND)[0]
    if run.diverged or (len(outside) and outside[-1] == len(err) - 1):
        settling = None
    else:
        settling = max(0.0, float(t[outside[-1] + 1] - run.motion_end)) if len(outside) else 0.0
    m: dict[str, Any] = dict(
        rms_error=float(np.sqrt(np.mean(err[motion] ** 2))),
        max_error=float(err.max()),
        final_error=float(err[motion][-1]),
        hold_final_error=float(err[-1]),
        ee_path_deviation=float(path.max()),
        overshoot=overshoot,
        settling_time=settling,
        residual_speed=float(speed[late].max()) if late.any() else float("nan"),
        final_speed=float(speed[-1]),
        error_energy=float(np.sum(err[after] ** 2) * dt),
        max_effort=float(np.abs(run.tau).max()),
        saturation=float(np.mean(np.any(np.abs(run.tau) >= effort * (1 - 1e-9), axis=1))),
    )
    reasons = []
    if run.diverged:
        reasons.append(run.diverged)
    rms_limit, max_limit = criteria.limits(float(np.linalg.norm(goal - start)))
    if not m["rms_error"] <= rms_limit:
        reasons.append(f"RMS joint error {m['rms_error']:.3g} rad > {rms_limit:.3g}")
    if not m["max_error"] <= max_limit:
        reasons.append(f"max joint error {m['max_error']:.3g} rad > {max_limit:.3g}")
    if not late.any():
        reasons.append(f"no hold samples {RESIDUAL_DELAY} s after the motion")
    elif not m["residual_speed"] < criteria.residual_speed:
        reasons.append(
            f"oscillating: joints still move at {m['residual_speed']:.3g} rad/s "
            f"{RESIDUAL_DELAY} s after the end (limit {criteria.residual_speed:g})"
        )
    if reasons and m["saturation"] > 0:  # why it failed: the actuators could not deliver the law's torque
        reasons.append(f"joint forces at their effort limit for {100 * m['saturation']:.3g} % of the run")
    return Metrics(run.controller, **m, diverged=run.diverged, passed=not reasons, reason="; ".join(reasons))
