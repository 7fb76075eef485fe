"""Controllers, selectable by name. Each says which MJCF it drives and what it writes into ``ctrl``.

- ``computed-torque``: ``τ = M(q)(q̈d + Kp·e + Kd·ė) + h(q, q̇) + D·q̇`` with ``M``, ``h`` and the
  damping ``D`` from Pinocchio on the URDF (armature from the spec), driving MuJoCo's MJCF
  through torque (``motor``) actuators. ``M`` is raised by ``dt·D``, the term MuJoCo's Euler
  integrator treats implicitly, so the discrete loop is exactly the designed one.
- ``pd+gravity``: ``τ = Kp·e + Kd·ė + g(q)`` (gravity from Pinocchio), per-joint gains scaled
  by the joint's own inertia ``M_ii`` at the start.
- ``position``: MuJoCo ``position`` actuators, ``ctrl = q_d``; ``kp = I·ω²``, ``kv = 2·I·ω`` with
  ``I = M_ii`` (link inertia seen by the joint, plus armature) so each joint is critically damped.
- ``seed-pid``: the seed's loop on the seed's MJCF (see :mod:`.seed`), the negative example.
"""

from __future__ import annotations

import numpy as np

from kinverify.errors import InputError
from kinverify.generate import generate_mjcf
from kinverify.model.spec import ArmSpec
from kinverify.tracking.models import PinocchioDynamics
from kinverify.tracking.quintic import Plan
from kinverify.tracking.seed import SeedPID, seed_mjcf

CONTROLLERS = ("computed-torque", "pd+gravity", "position", "seed-pid")
OMEGA = {"computed-torque": 50.0, "pd+gravity": 30.0, "position": 30.0}  # closed-loop bandwidth [rad/s]


class Controller:
    name = ""
    actuators = "motor"

    def __init__(self, spec: ArmSpec, pin: PinocchioDynamics, plan: Plan, dt: float) -> None:
        self.spec, self.pin, self.plan, self.dt = spec, pin, plan, dt
        self.inertia = np.diag(pin.mass(plan.q[0])).copy()  # kg·m² (kg for prismatic) per joint

    def mjcf(self) -> str:
        return generate_mjcf(self.spec, actuators="motor")

    def __call__(self, k: int, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        raise NotImplementedError


class ComputedTorque(Controller):
    name = "computed-torque"

    def __init__(self, *args) -> None:
        super().__init__(*args)
        w = OMEGA[self.name]
        self.kp, self.kd = w * w, 2.0 * w

    def __call__(self, k, q, qd):
        p = self.plan
        a = p.qdd[k] + self.kp * (p.q[k] - q) + self.kd * (p.qd[k] - qd)
        M = self.pin.mass(q) + np.diag(self.dt * self.pin.damping)
        return M @ a + self.pin.bias(q, qd) + self.pin.damping * qd


class PDGravity(Controller):
    name = "pd+gravity"

    def __init__(self, *args) -> None:
        super().__init__(*args)
        w = OMEGA[self.name]
        self.kp, self.kd = self.inertia * w * w, self.inertia * 2.0 * w

    def __call__(self, k, q, qd):
        p = self.plan
        return self.kp * (p.q[k] - q) + self.kd * (p.qd[k] - qd) + self.pin.gravity(q)


class Position(Controller):
    name = "position"
    actuators = "position"

    def gains(self) -> dict[str, tuple[float, float]]:
        w = OMEGA[self.name]
        return {j.name: (float(i * w * w), float(2.0 * i * w)) for j, i in zip(self.spec.joints, self.inertia, strict=True)}

    def mjcf(self) -> str:
        return generate_mjcf(self.spec, actuators="position", position_gains=self.gains())

    def __call__(self, k, q, qd):
        return self.plan.q[k].copy()


class SeedPid(Controller):
    name = "seed-pid"
    actuators = "seed"

    def __init__(self, *args) -> None:
        super().__init__(*args)
        self.pid = SeedPID(self.spec.dof, self.dt)

    def mjcf(self) -> str:
        return seed_mjcf(self.spec)

    def __call__(self, k, q, qd):
        return self.pid(self.plan.q[k], q)  # into ctrl[:n]; the velocity actuators keep ctrl = 0


_CLASSES = {c.name: c for c in (ComputedTorque, PDGravity, Position, SeedPid)}


def make_controller(name: str, spec: ArmSpec, pin: PinocchioDynamics, plan: Plan, dt: float) -> Controller:
    if name not in _CLASSES:
        raise InputError(f"unknown controller {name!r}; controllers: {', '.join(CONTROLLERS)}")
    return _CLASSES[name](spec, pin, plan, dt)
