"""Baseline quantities beyond kinematics: IK results for fixed targets, and dynamics.

``ik``: at save time a few of the baseline's uniform configurations are turned into *fixed*
world targets (the end frame's pose there, position only for arms with fewer than 6 joints) and
a start configuration (5 % of the way from that configuration to the middle of the limits); both are stored in the baseline (``fixed.ik``), so a later model is asked to reach the
same points in the world from the same starts. Records: ``ik.q`` (the solution, rad or m) and
``ik.error`` (``[position m, rotation rad]`` left over), one per target, ``sample`` = the
configuration the target came from. Solved with the batched Levenberg-Marquardt solver on the
analytic kinematics from the stored starts, without random restarts (a restart may land on
another branch, and a 1 mm change would then "move" the solution by radians) and with a time
budget far beyond what the solves need (never cut short), so an unchanged model gives the same
numbers and a changed one the nearby solution. A target the solver does not reach is kept:
``ik.error`` says by how much.

``dynamics``: Pinocchio on the generated URDF (armature from the spec) at every stored
configuration: ``dynamics.mass_matrix`` (row of M for each joint, kg·m²) and
``dynamics.gravity`` (generalized gravity torque, N·m or N) with ``frame`` = the joint name.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from kinverify.errors import InputError
from kinverify.model.spec import ArmSpec

IK_TARGETS = 5  # fixed targets per baseline (fewer when there are fewer configurations)
IK_START_BLEND = 0.05  # start = q + 0.05 (middle of the limits - q): near the solution, not on it
IK_ITERATIONS = 200
IK_RESTARTS = 0  # a restart may land on another branch: a changed model would "move" by radians


def ik_frame(spec: ArmSpec) -> str:
    """The frame IK targets are for: the last tool, else the last link."""
    return (spec.tool_names or spec.link_names)[-1]


def ik_fixed(spec: ArmSpec, q: np.ndarray) -> dict[str, Any]:
    """The fixed targets of a new baseline (stored in the file): the end frame's pose at the
    last ``IK_TARGETS`` configurations (uniform draws when there are enough) and the starts."""
    from kinverify.model.kinematics import frame_poses

    frame = ik_frame(spec)
    samples = list(range(max(0, len(q) - IK_TARGETS), len(q)))
    if not samples or spec.floating:  # a floating base reaches any target: no IK records (as in verify)
        return {"frame": frame, "position_only": spec.dof < 6, "targets": []}
    poses = frame_poses(spec, q[samples])[:, spec.frame_names.index(frame)]
    middle = (np.asarray(spec.lower) + np.asarray(spec.upper)) / 2
    targets = [
        {"sample": s, "pose": poses[k].tolist(), "start": (q[s] + IK_START_BLEND * (middle - q[s])).tolist()}
        for k, s in enumerate(samples)
    ]
    return {"frame": frame, "position_only": spec.dof < 6, "targets": targets}


def ik_parse(fixed, n_samples: int | None = None):
    """``(frame, targets, poses (K, 4, 4), starts (K, n), samples)`` of stored ``fixed.ik`` data;
    :class:`InputError` when it is malformed (or, given ``n_samples``, names a missing sample)."""
    try:
        frame, targets = fixed.get("frame"), list(fixed.get("targets") or [])
        poses = np.array([t["pose"] for t in targets], dtype=float).reshape(len(targets), 4, 4)
        starts = np.array([t["start"] for t in targets], dtype=float).reshape(len(targets), -1) if targets else np.zeros((0, 0))
        samples = [t["sample"] for t in targets]
    except (AttributeError, KeyError, TypeError, ValueError):
        raise InputError("malformed baseline: fixed.ik must hold targets with a 4x4 pose, a start and a sample") from None
    if not all(isinstance(s, int) and (n_samples is None or 0 <= s < n_samples) for s in samples):
        raise InputError("malformed baseline: fixed.ik targets must name stored samples")
    return frame, targets, poses, starts, samples


def ik_records(spec: ArmSpec, q: np.ndarray, fixed: dict[str, Any]) -> list[dict]:
    """Solve the stored targets with ``spec``; nothing when the frame or the joint count changed
    (the kinematics records and the frame lists already report that)."""
    from kinverify.backends.analytic import AnalyticBackend
    from kinverify.ik import FrameModel, IKOptions, solve_lm

    frame, targets, poses, starts, samples = ik_parse(fixed)
    if frame not in spec.frame_names or not targets or starts.shape[1] != spec.dof:
        return []
    model = FrameModel(AnalyticBackend(spec), frame)
    opts = IKOptions(
        tol_pos=1e-12,
        tol_rot=1e-12,
        max_restarts=IK_RESTARTS,
        first_attempt_iter=IK_ITERATIONS,
        stall_window=IK_ITERATIONS,
        max_evaluations=IK_ITERATIONS,
        time_budget=60.0,
        seed=0,
    )
    sol = solve_lm(
        model, poses, spec.lower, spec.upper, position_only=bool(fixed.get("position_only")), options=opts, q0=starts, batch=True
    )
    out = []
    for k, sample in enumerate(samples):
        out.append({"property": "ik.q", "frame": frame, "sample": sample, "value": sol.q[k].tolist()})
        out.append(
            {
                "property": "ik.error",
                "frame": frame,
                "sample": sample,
                "value": [float(sol.pos_error[k]), float(sol.rot_error[k])],
            }
        )
    return out


def dynamics_records(spec: ArmSpec, q: np.ndarray) -> list[dict]:
    """Mass-matrix rows and gravity torques per coordinate (Pinocchio on the generated URDF)."""
    from kinverify.generate import generate_urdf
    from kinverify.tracking.models import PinocchioDynamics

    if spec.dof == 0 or len(q) == 0:
        return []
    dyn = PinocchioDynamics(generate_urdf(spec), spec.coordinate_names, [j.armature for j in spec.joints])
    out = []
    for s, qs in enumerate(q):
        mass, gravity = dyn.mass(qs), dyn.gravity(qs)
        for i, joint in enumerate(spec.coordinate_names):  # a floating base's six first
            out.append({"property": "dynamics.mass_matrix", "frame": joint, "sample": s, "value": mass[i].tolist()})
            out.append({"property": "dynamics.gravity", "frame": joint, "sample": s, "value": float(gravity[i])})
    return out
