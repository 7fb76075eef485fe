"""Findings: what differs between the two files, named once, with its size.

Severity (``SEVERITY``): an **error** is a difference in what the robot is, and fails the verdict
unless accepted: kinematics (world transform, zero offsets, axis signs, directions and positions,
joint types, a joint or a mass in one file only, a named frame placed elsewhere), limits, masses,
centres of mass, inertias, joint damping and friction, dynamics. A **warning** is worth knowing
and changes nothing the files can agree on: a library that refuses or misreads a file, a value
one format cannot express, a difference that cannot move a fixed-base robot. An **info** is a
choice or an artefact: rounding at the written precision, frame conventions, name prefixes, links
merged differently, known library quirks.

This module holds the table, :func:`finding` and the names of unit mistakes.
"""

from __future__ import annotations

import numpy as np

from kinverify.suites.base import Finding, Severity

SEVERITY: dict[str, Severity] = {
    # kinematics
    "base_transform": "error",
    "zero_offset": "error",
    "axis_sign_flip": "error",
    "axis_direction": "error",
    "axis_position": "error",
    "joint_origin_moved": "error",
    "joint_origin_turned": "error",
    "type_difference": "error",
    "frame_offset": "error",
    "disagreement_starts": "error",
    "coupling_difference": "error",
    "extra_parts": "error",
    "length_units": "error",
    "mass_units": "error",
    "floating_one_file": "error",
    # limits, inertials, joint dynamics
    "limit_difference": "error",
    "limit_units": "error",
    "effort_difference": "error",
    "mass_difference": "error",
    "com_difference": "error",
    "inertia_difference": "error",
    "inertia_rotated": "error",
    "damping_difference": "error",
    "friction_difference": "error",
    "dynamics_difference": "error",
    "armature_difference": "error",
    "velocity_difference": "error",
    # worth knowing
    "parser_refused": "warning",
    "parser_disagreement": "warning",
    "inexpressible": "warning",
    "stiffness_inexpressible": "warning",
    "coupling_one_file": "warning",
    "base_inertial_difference": "warning",
    "base_frame_offset": "warning",
    "actuator_alternatives": "warning",
    "usd_pose_mismatch": "warning",
    # one file leaves a value unset (the format's default), the other states one
    "damping_unset": "warning",
    "friction_unset": "warning",
    "limit_unset": "warning",
    "effort_unset": "warning",
    "inertial_unset": "warning",
    "mass_unknown": "warning",
    "armature_unset": "warning",
    # choices and artefacts
    "frame_convention": "info",
    "rounding": "info",
    "parser_quirk": "info",
    "joint_names": "info",
    "lumped_links": "info",
    "frame_twin": "info",
    "total_mass": "info",
    "floating_base": "info",
    "format_extension": "info",
    "several_actuators": "info",
    "parser_ignores": "info",
    "world_parts": "info",
    "one_file_only": "info",
}
SUBJECTS = ("joint", "link", "frame")


def finding(
    kind: str,
    message: str,
    values: dict | None = None,
    *,
    magnitude: float | None = None,
    unit: str = "",
    prop: str = "",
    severity: Severity | None = None,
    **names,
) -> Finding:
    """A :class:`Finding` of ``kind`` (severity from ``SEVERITY`` unless given); ``names``:
    ``joint``/``link``/``frame`` (URDF name) and ``mjcf_joint``/``mjcf_link``/``mjcf_frame`` (its
    MJCF name); several subjects are joined with ", "."""
    values = dict(values or {})
    subject_type = next((k for k in SUBJECTS if names.get(k) is not None), "file" if "file" in values else "model")
    subject = names.get(subject_type) or str(values.get("file", ""))
    other = names.get(f"mjcf_{subject_type}") or ""
    subject, other = (", ".join(x) if isinstance(x, (list, tuple)) else x for x in (subject, other))
    return Finding(
        kind,
        severity or SEVERITY.get(kind, "warning"),
        message,
        subject,
        subject_type,
        other,
        prop,
        values,
        None if magnitude is None else float(magnitude),
        unit,
    )


def fmt(v) -> str:
    v = np.atleast_1d(np.asarray(v, dtype=float))
    v = np.where(np.abs(v) < 5e-13, 0.0, v)
    return "[" + ", ".join(f"{x:.6g}" for x in v + 0.0) + "]"


UNIT_FACTORS = {
    "length": {
        1000.0: "millimetres as metres",
        100.0: "centimetres as metres",
        0.0254: "inches as metres",
        25.4: "inches as millimetres",
    },
    "mass": {1000.0: "grams as kilograms", 0.45359237: "pounds as kilograms"},
}


def unit_factor(ratio: float, quantity: str) -> str | None:
    """A name for ``ratio`` (the MJCF's value over the URDF's) when it is a units mistake."""
    for factor, name in UNIT_FACTORS[quantity].items():
        if abs(ratio / factor - 1) < 1e-3:
            return f"×{ratio:.6g} ({name} in the MJCF?)"
        if abs(ratio * factor - 1) < 1e-3:
            return f"×{ratio:.6g} ({name} in the URDF?)"
    return None
