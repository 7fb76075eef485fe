"""Quintic joint trajectories: zero velocity and acceleration at both ends of every segment.

One segment from ``q0`` to ``q1`` in ``T`` seconds is ``q(t) = q0 + Δ·s(τ)``, ``τ = t/T``,
``s = 10τ³ − 15τ⁴ + 6τ⁵`` (the seed's a3, a4, a5). Through waypoints, each segment stops at
its waypoint (zero velocity and acceleration there), so no waypoint is overshot. Samples are
taken at the model timestep, ``t = 0, dt, ..., T_total`` inclusive; each segment's duration is
rounded to a whole number of steps so that every waypoint falls exactly on a sample.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from kinverify.errors import InputError


@dataclass(frozen=True)
class Plan:
    """A sampled joint trajectory: ``t`` (K,) [s], ``q``, ``qd``, ``qdd`` (K, n) [rad, rad/s, rad/s²]."""

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray

    @property
    def duration(self) -> float:
        return float(self.t[-1])

    @property
    def dt(self) -> float:
        return float(self.t[1] - self.t[0]) if len(self.t) > 1 else 0.0


def quintic_profile(tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``s, ds/dτ, d²s/dτ²`` of the rest-to-rest quintic at normalised time ``tau`` in [0, 1]."""
    tau = np.clip(tau, 0.0, 1.0)
    s = tau**3 * (10 - 15 * tau + 6 * tau**2)
    ds = 30 * tau**2 * (1 - tau) ** 2
    dds = 60 * tau * (1 - tau) * (1 - 2 * tau)
    return s, ds, dds


def _check_duration(duration: float) -> float:
    if not np.isfinite(duration) or duration <= 0:
        raise InputError(f"duration must be positive, got {duration:g} s")
    return float(duration)


def quintic(q0, q1, duration: float, dt: float) -> Plan:
    """Rest-to-rest quintic from ``q0`` to ``q1`` in ``duration`` seconds, sampled every ``dt``."""
    return through_waypoints([q0, q1], [duration], dt)


def through_waypoints(waypoints, durations, dt: float) -> Plan:
    """Quintic segments ``waypoints[i] -> waypoints[i+1]`` lasting ``durations[i]`` each."""
    points = np.atleast_2d(np.asarray(waypoints, dtype=float))
    durations = [_check_duration(d) for d in np.atleast_1d(np.asarray(durations, dtype=float))]
    if len(points) < 2 or len(durations) != len(points) - 1:
        raise InputError(f"need N >= 2 waypoints and N - 1 durations, got {len(points)} and {len(durations)}")
    if dt <= 0:
        raise InputError(f"timestep must be positive, got {dt:g}")
    durations = [max(1, round(d / dt)) * dt for d in durations]  # whole steps: every segment ends on a sample
    starts = np.concatenate([[0.0], np.cumsum(durations)])
    n_steps = int(round(starts[-1] / dt))
    t = np.arange(n_steps + 1) * dt
    q, qd, qdd = (np.empty((len(t), points.shape[1])) for _ in range(3))
    seg = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(durations) - 1)
    for i, T in enumerate(durations):
        rows = seg == i
        s, ds, dds = quintic_profile((t[rows] - starts[i]) / T)
        delta = points[i + 1] - points[i]
        q[rows] = points[i] + np.outer(s, delta)
        qd[rows] = np.outer(ds / T, delta)
        qdd[rows] = np.outer(dds / T**2, delta)
    return Plan(t, q, qd, qdd)


def hold(plan: Plan, seconds: float) -> Plan:
    """``plan`` followed by ``seconds`` of holding its last configuration at rest."""
    extra = int(round(seconds / plan.dt)) if seconds > 0 else 0
    if extra == 0:
        return plan
    t = np.concatenate([plan.t, plan.t[-1] + plan.dt * np.arange(1, extra + 1)])

    def pad(a, last):
        return np.concatenate([a, np.repeat(last[None], extra, axis=0)])

    zero = np.zeros_like(plan.q[-1])
    return Plan(t, pad(plan.q, plan.q[-1]), pad(plan.qd, zero), pad(plan.qdd, zero))


def plan_violations(plan: Plan, lower, upper, velocity) -> list[str]:
    """Joint-limit and speed-limit violations of the plan itself (empty list: the plan is valid)."""
    lower, upper, velocity = (np.asarray(a, dtype=float) for a in (lower, upper, velocity))
    out = []
    for j in range(plan.q.shape[1]):
        lo, hi = plan.q[:, j].min(), plan.q[:, j].max()
        if lo < lower[j] - 1e-12 or hi > upper[j] + 1e-12:
            out.append(f"joint {j}: plan spans [{lo:.4g}, {hi:.4g}] outside limits [{lower[j]:.4g}, {upper[j]:.4g}]")
        peak = np.abs(plan.qd[:, j]).max()
        if peak > velocity[j] * (1 + 1e-12):
            out.append(f"joint {j}: peak speed {peak:.4g} exceeds the limit {velocity[j]:.4g}")
    return out
