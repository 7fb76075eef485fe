"""Known quirks of the libraries behind the backends, in one table (shown in reports).

Each entry: backend name -> list of (what happens, what kinverify does about it).
"""

from __future__ import annotations

QUIRKS: dict[str, list[tuple[str, str]]] = {
    "yourdfpy": [
        ("joint rotations below about 2e-8 rad come back as the identity (FK through trimesh's "
         "scene graph), so FK differs by up to |q|·lever ≤ 2e-8·lever there",
         "reported as is; property tests draw no |q| in (0, 1e-7) for this backend (tests/test_backends.py)"),
        ("no Jacobian", "finite differences of its FK, compared at the finite-difference tolerance"),
    ],
    "pinocchio-mjcf": [
        ("Pinocchio's MJCF parser ignores the pos/quat of a top-level body under <worldbody>",
         "generated MJCF hangs the arm from a zero-pose 'world_mount' body"),
    ],
    "mujoco": [
        ("compiler angle='degree' converts joint range but not actuator ctrlrange",
         "generated MJCF always uses angle='radian'"),
        ("the compiler marks a body's inertial frame as aligned with the body (body_sameframe) when its "
         "principal axes are rotated by less than about 1e-6 rad, and drops that rotation at run time",
         "the dynamics suite names such bodies in its notes (MujocoDynamics.snapped_inertia_frames)"),
    ],
}
