"""Known quirks of the libraries behind the backends, in one table (shown in reports).

Each entry: backend name -> list of (what happens, what kinverify does about it). Drake's were
seen in Drake 1.51.1, Newton's in Newton 1.8.0 with Warp 1.19.0.
"""

from __future__ import annotations

QUIRKS: dict[str, list[tuple[str, str]]] = {
    "yourdfpy": [
        (
            "FK goes through trimesh's scene graph, whose TransformForest.add_edge ignores an update "
            "that changes a 4×4 transform by less than 1e-8 (peak-to-peak) from the stored one, so "
            "FK is stale after a tiny joint change",
            "the adapter first moves such joints 1 rad away, then to the requested value",
        ),
        (
            "the same rule at load time: a joint origin within 1e-8 of the identity (e.g. rpy of 1e-8 "
            "rad) is never written over the scene graph's initial identity edge, so it is dropped",
            "the adapter re-seats every joint transform once after loading; origin rotations of a few "
            "1e-9 rad can still come out up to their own size off along longer paths (cause not isolated), "
            "so kinverify.strategies draws origin rotations (each angle, and the turn the three make "
            "together) of 0 or at least 1e-6 rad",
        ),
        ("no Jacobian", "finite differences of its FK, compared at the finite-difference tolerance"),
    ],
    "pinocchio-mjcf": [
        (
            "Pinocchio's MJCF parser ignores the pos/quat of a top-level body under <worldbody>",
            "generated MJCF hangs the arm from a zero-pose 'world_mount' body",
        ),
    ],
    "mujoco-urdf": [
        (
            "MuJoCo's URDF import fuses fixed links into their parent (fusestatic) unless told otherwise",
            "the adapter adds <mujoco><compiler fusestatic='false'/></mujoco> so every URDF link stays a frame",
        ),
    ],
    "mujoco": [
        (
            "a site less than about 1e-6 m from its body (or rotated less than about 1e-6 rad) is "
            "placed exactly at the body frame by the compiler's same-frame detection",
            "reported as is; kinverify.strategies never draws tool offsets in that band",
        ),
        ("compiler angle='degree' converts joint range but not actuator ctrlrange", "generated MJCF always uses angle='radian'"),
        (
            "MjSpec.to_xml() writes numbers with 6 significant digits (masses, positions, and fullinertia "
            "re-expressed as rounded quat + diaginertia), so a round trip rounds the model",
            "file mode removes meshes by editing the XML tree and uses MjSpec only to check that it compiles",
        ),
        (
            "the compiler marks a body's inertial frame as aligned with the body (body_sameframe) when its "
            "principal axes are rotated by less than about 1e-6 rad, and drops that rotation at run time",
            "the dynamics suite gives Pinocchio MuJoCo's inertial for them against MuJoCo and names them in its notes "
            "(MujocoDynamics.run_inertials)",
        ),
        (
            "the same same-frame detection puts a centre of mass less than about 1e-6 m from its body origin "
            "at the origin at run time (xipos), while body_ipos keeps the stated position",
            "file mode allows that distance between the files' centres of mass and gives Pinocchio MuJoCo's in its dynamics; "
            "so does the dynamics suite on a spec (MujocoDynamics.moved_coms; a link 1e-6 m long moved M by 5e-7)",
        ),
    ],
    "drake-urdf": [
        (
            "Drake 1.51.1 (drake-mjcf and drake-sdf alike) turns a revolute or prismatic axis within about "
            "1.8e-8 (relative) of a coordinate axis onto that axis (its axial mobilizer): an axis (0, 1, 1e-9) "
            "is read as (0, 1, 0), so FK and Jacobians differ by that much times the lever arm",
            "reported as is; kinverify.strategies draws each axis component as 0 or at least 1e-6 of its length",
        ),
        (
            "Drake 1.51.1 makes every body without an inboard joint a free body: a URDF root link not "
            "welded to a link named world floats (7 more positions), and a URDF floating joint is "
            "ignored with a warning (the child left a free body)",
            "the adapter welds each root body to the world at the identity unless the configuration has a "
            "floating base, which is then Drake's free body, converted to the base coordinates",
        ),
    ],
    "drake-mjcf": [
        (
            "Drake 1.51.1's MJCF parser reads a subset of MJCF: it ignores <site> and warns about each "
            "element and attribute it does not support (e.g. frictionloss, <sensor>, <light>)",
            "each site becomes a frame on its body at the offset MuJoCo's compiler gives it; file mode "
            "names the ignored elements in a parser_refused warning",
        ),
        (
            "Drake 1.51.1's MJCF parser does not take a joint attribute from a default class two levels up: "
            "in the go2 of MuJoCo Menagerie the thigh joints (class front_hip in hip in go2, axis set in go2) "
            "turn about z instead of y",
            "file mode names the library that stands apart from the two that agree (parser_disagreement) and "
            "leaves it out of the comparison between the files",
        ),
        (
            "Drake 1.51.1 puts an MJCF joint's armature on the actuator of that joint (reflected inertia), "
            "so a joint without an actuator loses its armature",
            "reported as is (the dynamics comparison reads Drake's SDFormat, which carries it)",
        ),
    ],
    "drake-sdf": [
        (
            "Drake 1.51.1 reads joint armature only from its own SDFormat extension (drake:rotor_inertia "
            "times drake:gear_ratio squared), on the joint's actuator, which exists only for a joint "
            "whose <effort> limit is not zero",
            "generated SDFormat writes drake:rotor_inertia = armature with drake:gear_ratio 1",
        ),
        (
            "the SDFormat parser in Drake 1.51.1 refuses a subnormal number (below 2.2e-308 in size) with "
            "'Error reading element'",
            "generated SDFormat writes subnormal numbers as 0 (every other number exactly)",
        ),
    ],
    "newton-urdf": [
        (
            "Newton computes in float32 (Warp kernels): its FK, Jacobians and mass matrix agree with the "
            "double-precision libraries to about 1e-7 relative, not to 1e-9",
            "its backends carry an agreement floor of their own (newton_.FLOOR, measured on the shipped specs and "
            "the shared real robots; docs/performance.md); finite-difference checks of its Jacobian use a step of 1e-2",
        ),
        (
            "eval_jacobian gives each link's twist at its centre of mass (v_com, ω), not at the link origin",
            "the adapter moves the linear rows to the frame origin: v_o = v_com + ω × (p_o − p_com)",
        ),
        (
            'ModelBuilder.finalize() changes inertias it finds invalid, with a NewtonWarning ("Inertia validation '
            "corrected 5 bodies\" on ANYmal C's URDF, none on the Panda's files): Newton's mass matrix is of the corrected bodies",
            "the warnings are kept on the backend (parser_warnings), not printed; kinematics does not depend on them",
        ),
    ],
    "newton-mjcf": [
        (
            "Newton 1.8.0 keeps quaternions unnormalised: its MJCF importer leaves each joint's parent-frame "
            "quaternion (joint_X_p) off unit length by float32 round-off that grows along the chain (6.6e-7 on the "
            "Panda of models/panda.toml, 3.6e-7 on Menagerie's ANYmal C), and eval_fk composes them without "
            "renormalising, so body quaternions end up to 2.0e-6 off unit (1.4e-6 on Menagerie's Panda); "
            "eval_jacobian rotates joint axes with them, so its angular columns are longer than 1 by twice that "
            "(up to 1.1e-5 on the Panda of models/panda.toml, against 2.2e-6 from its URDF)",
            "the adapter normalises each body quaternion (in double) before making its rotation matrix; the "
            "Jacobian is Newton's own, held to Newton's agreement floor",
        ),
        (
            "Newton 1.8.0's MJCF importer makes one joint of several joints in one body, named by joining their "
            "names (hinges extra and panda_joint4 become one joint extra_panda_joint4), as Pinocchio's makes a "
            "composite joint",
            "such a file's joints are unknown to newton-mjcf: a parser_refused warning names it, as for pinocchio-mjcf",
        ),
        (
            "add_mjcf(floating=True) gives every top-level body a free joint, a static one too (Apollo's world_link in "
            "Menagerie's apptronik_apollo.xml: two free root joints), and a static top-level body is an articulation "
            "of its own",
            "the adapter reads with floating=None (the file's own free joint makes the floating base, as in MuJoCo) "
            "and reads the Jacobian of the articulation holding the compared joints; a static body does not move",
        ),
    ],
    "newton-usd": [
        (
            "ModelBuilder.add_usd reads lengths as metres whatever the stage's metersPerUnit (result['linear_unit'] "
            "reports it; nothing is scaled): a stage in centimetres (metersPerUnit 0.01, also USD's fallback when "
            "unauthored) is read 100 times too large (a joint frame at 0.1 units: 0.1 m, where the stage means 0.001 m); "
            "Newton warns 'USD stages with non-unit linear units are not supported' of an authored one only",
            "newton-usd refuses a stage whose metersPerUnit is not 1, naming it (file mode: a parser_refused warning); "
            "the shared USDs and every generated one state metersPerUnit 1",
        ),
        (
            "ModelBuilder.add_usd refuses a stage with composition errors (RuntimeError), and a robot whose mesh "
            "layers are absent has them (the shared ANYmal C Isaac Lab asset: ./Props/instanceable_meshes.usd; Apollo: "
            "Payload/GeometryLibrary.usdc)",
            "the adapter gives Newton kinverify's stage flattened (Usd.Stage.Flatten: the same composed prims, the "
            "absent layers contributing nothing); measured on the ten shared USDs: Newton agrees with kinverify's "
            "own reading to 1.2e-6 m, 4.2e-7 rad and 2.4e-6 in either Jacobian block (float32)",
        ),
        (
            "a plain Xform under a rigid body (a spec's tool, a URDF link the converter keeps as an Xform) is no "
            "Newton entity; sites are prims with MjcSiteAPI or NewtonSiteAPI",
            "such a frame's pose in its body is the stage's own transform (pxr), carried on Newton's body",
        ),
    ],
}
