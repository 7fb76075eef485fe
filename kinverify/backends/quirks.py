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
    "mujoco-urdf": [
        ("MuJoCo's URDF import fuses fixed links into their parent (fusestatic) unless told otherwise",
         "the adapter adds <mujoco><compiler fusestatic='false'/></mujoco> so every URDF link stays a frame"),
    ],
    "mujoco": [
        ("compiler angle='degree' converts joint range but not actuator ctrlrange",
         "generated MJCF always uses angle='radian'"),
        ("MjSpec.to_xml() writes numbers with 6 significant digits (masses, positions, and fullinertia "
         "re-expressed as rounded quat + diaginertia), so a round trip rounds the model",
         "file mode removes meshes by editing the XML tree and uses MjSpec only to check that it compiles"),
    ],
}
