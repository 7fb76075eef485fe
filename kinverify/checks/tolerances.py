"""Default tolerances per property, with units. Kinematics computed in double precision by
different code paths agree to ~1e-15; 1e-9 leaves room for long chains while catching any real
modelling difference (a 1 mm offset is 1e6 times larger)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Tolerance:
    value: float
    unit: str


DEFAULT_TOLERANCES: dict[str, Tolerance] = {
    "fk.position": Tolerance(1e-9, "m"),
    "fk.rotation": Tolerance(1e-9, "rad"),
    "jacobian.linear": Tolerance(1e-9, "m/rad"),
    "jacobian.angular": Tolerance(1e-9, "rad/rad"),
    # A Jacobian against central differences of FK (step 1e-6): truncation ~1e-12, round-off
    # ~1e-10, so 1e-6 flags only a wrong Jacobian, never numerical noise.
    "jacobian.fd": Tolerance(1e-6, "norm"),
    # Dynamics of the URDF through Pinocchio against the MJCF through MuJoCo (checks/dynamics.py):
    # the same double-precision recursions agree to ~1e-13 on the shipped arms.
    "dynamics.mass_matrix": Tolerance(1e-9, "kg·m²"),
    "dynamics.gravity": Tolerance(1e-9, "N·m"),
    "dynamics.bias": Tolerance(1e-9, "N·m"),
    "dynamics.inverse": Tolerance(1e-9, "N·m"),
    "dynamics.armature": Tolerance(1e-12, "kg·m²"),
    "dynamics.damping": Tolerance(1e-12, "N·m·s/rad"),
    "dynamics.friction": Tolerance(1e-12, "N·m"),
    "tracking.forward": Tolerance(1e-9, "rad"),
}
