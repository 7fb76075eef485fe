"""Known quirks of the libraries behind the backends, in one table (shown in reports).

Each entry: backend name -> list of (what happens, what kinverify does about it).
"""

from __future__ import annotations

QUIRKS: dict[str, list[tuple[str, str]]] = {
    "yourdfpy": [
        ("FK goes through trimesh's scene graph, whose TransformForest.add_edge ignores an update "
         "that changes a 4×4 transform by less than 1e-8 (peak-to-peak) from the stored one, so "
         "FK is stale after a tiny joint change",
         "the adapter first moves such joints 1 rad away, then to the requested value"),
        ("the same rule at load time: a joint origin within 1e-8 of the identity (e.g. rpy of 1e-8 "
         "rad) is never written over the scene graph's initial identity edge, so it is dropped",
         "the adapter re-seats every joint transform once after loading; origin rotations of a few "
         "1e-9 rad can still come out up to their own size off along longer paths (cause not isolated), "
         "so kinverify.strategies draws origin rotations (each angle, and the turn the three make "
         "together) of 0 or at least 1e-6 rad"),
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
        ("a site less than about 1e-6 m from its body (or rotated less than about 1e-6 rad) is "
         "placed exactly at the body frame by the compiler's same-frame detection",
         "reported as is; kinverify.strategies never draws tool offsets in that band"),
        ("compiler angle='degree' converts joint range but not actuator ctrlrange",
         "generated MJCF always uses angle='radian'"),
        ("MjSpec.to_xml() writes numbers with 6 significant digits (masses, positions, and fullinertia "
         "re-expressed as rounded quat + diaginertia), so a round trip rounds the model",
         "file mode removes meshes by editing the XML tree and uses MjSpec only to check that it compiles"),
        ("the compiler marks a body's inertial frame as aligned with the body (body_sameframe) when its "
         "principal axes are rotated by less than about 1e-6 rad, and drops that rotation at run time",
         "the dynamics suite names such bodies in its notes (MujocoDynamics.snapped_inertia_frames)"),
    ],
}
