"""Execute a plan in MuJoCo under a named controller and record what happened.

Sample ``k`` of a :class:`Run` is the state at ``plan.t[k]``, before ``ctrl`` is computed;
``tau[k]`` is the joint force the actuators applied over the following step (``qfrc_actuator``).
A run stops early, marked diverged, on a non-finite state, MuJoCo's bad-acceleration warning
(MuJoCo then silently resets the state) or a joint speed above :data:`SPEED_LIMIT`.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from kinverify.model.spec import ArmSpec
from kinverify.tracking.controllers import make_controller
from kinverify.tracking.models import MujocoDynamics, PinocchioDynamics
from kinverify.tracking.quintic import Plan

SPEED_LIMIT = 1e4  # rad/s or m/s: a state this fast has blown up


@dataclass
class Run:
    controller: str
    plan: Plan
    motion_end: float  # s, end of the motion (the rest is the hold)
    q: np.ndarray
    qd: np.ndarray
    tau: np.ndarray
    diverged: str = ""  # reason, or "" for a complete run

    @property
    def t(self) -> np.ndarray:
        return self.plan.t[: len(self.q)]


def pinocchio_dynamics(spec: ArmSpec, urdf: str) -> PinocchioDynamics:
    """Pinocchio on the URDF with the spec's armature (URDF cannot express it)."""
    return PinocchioDynamics(urdf, spec.joint_names, [j.armature for j in spec.joints])


def execute(spec: ArmSpec, urdf: str, plan: Plan, controller: str, motion_end: float, q0=None, mjcf: str | None = None) -> Run:
    """Run ``plan`` (motion then hold) in MuJoCo from ``q0`` (default ``plan.q[0]``, at rest).

    ``mjcf`` overrides the controller's MJCF (e.g. a deliberately wrong model)."""
    pin = pinocchio_dynamics(spec, urdf)
    ctl = make_controller(controller, spec, pin, plan, plan.dt)
    mj = MujocoDynamics(mjcf or ctl.mjcf(), spec.joint_names)
    m, d = mj.model, mj.data
    if abs(m.opt.timestep - plan.dt) > 1e-12:
        raise ValueError(f"plan sampled every {plan.dt} s but the model steps {m.opt.timestep} s")
    mujoco.mj_resetData(m, d)
    d.qpos[mj.qadr] = plan.q[0] if q0 is None else q0
    mujoco.mj_forward(m, d)
    K, n = len(plan.t), spec.dof
    q, qd, tau = np.zeros((K, n)), np.zeros((K, n)), np.zeros((K, n))
    reason = ""
    for k in range(K):
        q[k], qd[k] = d.qpos[mj.qadr], d.qvel[mj.vadr]
        if not (np.all(np.isfinite(q[k])) and np.all(np.isfinite(qd[k]))):
            reason = f"non-finite state at t = {plan.t[k]:.3f} s"
        elif np.abs(qd[k]).max() > SPEED_LIMIT:
            reason = f"joint speed {np.abs(qd[k]).max():.3g} above {SPEED_LIMIT:g} at t = {plan.t[k]:.3f} s"
        if reason:
            return Run(controller, plan, motion_end, q[:k], qd[:k], tau[:k], "diverged: " + reason)
        if k == K - 1:
            break
        d.ctrl[:n] = ctl(k, q[k], qd[k])
        mujoco.mj_step(m, d)
        tau[k] = d.qfrc_actuator[mj.vadr]
        if d.warning[mujoco.mjtWarning.mjWARN_BADQACC].number > 0:
            return Run(
                controller,
                plan,
                motion_end,
                q[: k + 1],
                qd[: k + 1],
                tau[: k + 1],
                f"diverged: MuJoCo reported a bad acceleration at t = {plan.t[k]:.3f} s",
            )
    tau[-1] = tau[-2] if K > 1 else 0.0
    return Run(controller, plan, motion_end, q, qd, tau)
