"""One frame of one backend as IK sees it: batched ``q (B, n) -> (T (B, 4, 4), J (B, 6, n))``.

The generic path goes through the Backend Protocol (``backend.evaluate``) and keeps the
requested frame. Two fast paths compute only what IK needs, in the same convention:
the analytic backend (batched numpy, many restarts/targets per call) and Pinocchio (one
``computeFrameJacobian`` per configuration instead of every frame's Jacobian).
"""

from __future__ import annotations

import math

import numpy as np

from kinverify.errors import InputError, UnknownNameError
from kinverify.model.transforms import rotation_angle, rotation_log


class FrameModel:
    """FK and world-aligned Jacobian ``[linear; angular]`` of ``frame`` on ``backend``."""

    def __init__(self, backend, frame: str | None = None, revolute=None) -> None:
        if not backend.jacobian_method:
            raise InputError(f"backend {backend.name!r} has no Jacobian; IK needs FK and Jacobians")
        frame = frame or backend.frames[-1]
        if frame not in backend.frames:
            raise UnknownNameError("frame", frame, backend.frames)
        self.backend, self.frame, self.name = backend, frame, backend.name
        self.index = backend.frames.index(frame)
        self.dof = len(backend.joint_names)
        self.revolute = _revolute(backend) if revolute is None else np.asarray(revolute, bool)
        from kinverify.backends.analytic import AnalyticBackend

        # numpy backends evaluate a whole batch per call: solve their rows in lock-step
        self.batched = type(backend).__module__.endswith("backends.analytic")
        self._eval = self._generic
        if type(backend) is AnalyticBackend:
            self._eval = self._analytic
        elif type(backend).__module__.endswith("backends.pinocchio_"):
            self._eval = self._pinocchio

    def __call__(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self._eval(np.atleast_2d(np.asarray(q, dtype=float)))

    def single(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """One configuration ``(n,)`` -> ``T (4, 4)``, ``J (6, n)`` (the per-target solve path)."""
        if self._eval == self._pinocchio:
            return self.backend.frame_pose_and_jacobian(q, self.index)
        poses, jac = self._eval(q[None])
        return poses[0], jac[0]

    def poses(self, q: np.ndarray) -> np.ndarray:
        return self(q)[0]

    def _generic(self, q):
        ev = self.backend.evaluate(q)
        return ev.poses[:, self.index], ev.jacobians[:, self.index]

    def _analytic(self, q):
        from kinverify.model.kinematics import frame_poses, geometric_jacobians

        spec = self.backend.spec
        poses = frame_poses(spec, q)
        return poses[:, self.index], geometric_jacobians(spec, poses, q)[:, self.index]

    def _pinocchio(self, q):
        poses = np.empty((len(q), 4, 4))
        jac = np.empty((len(q), 6, self.dof))
        for k, qk in enumerate(q):
            poses[k], jac[k] = self.backend.frame_pose_and_jacobian(qk, self.index)
        return poses, jac


def _revolute(backend) -> np.ndarray:
    """Which joints are revolute, from the spec when the backend has one (else none is assumed to be,
    so no joint is wrapped by 2π)."""
    spec = getattr(backend, "spec", None)
    if spec is not None:
        return np.array([j.type == "revolute" for j in spec.joints])
    return np.zeros(len(backend.joint_names), bool)


def pose_errors(poses: np.ndarray, targets: np.ndarray, position_only: bool) -> np.ndarray:
    """Error vectors ``(B, 3)`` or ``(B, 6)``: ``[p_target − p; log(R_target Rᵀ)]`` (world axes),
    so that a Gauss-Newton step solves ``J dq = e`` with the world-aligned Jacobian."""
    dp = targets[:, :3, 3] - poses[:, :3, 3]
    if position_only:
        return dp
    dr = rotation_log(targets[:, :3, :3] @ np.swapaxes(poses[:, :3, :3], -1, -2))
    return np.concatenate([dp, dr], axis=-1)


def residuals(poses: np.ndarray, targets: np.ndarray, position_only: bool) -> tuple[np.ndarray, np.ndarray]:
    """Position error [m] and rotation error [rad] (zero when position-only) of each pose."""
    pos = np.linalg.norm(targets[:, :3, 3] - poses[:, :3, 3], axis=-1)
    if position_only:
        return pos, np.zeros_like(pos)
    rot = rotation_angle(np.swapaxes(targets[:, :3, :3], -1, -2) @ poses[:, :3, :3])
    return pos, rot


def pose_error_single(pose: np.ndarray, target: np.ndarray, position_only: bool) -> tuple[np.ndarray, float, float]:
    """:func:`pose_errors` and :func:`residuals` for one pose: (error vector, position [m], angle [rad])."""
    dp = target[:3, 3] - pose[:3, 3]
    pos = math.sqrt(dp @ dp)
    if position_only:
        return dp, pos, 0.0
    m = target[:3, :3] @ pose[:3, :3].T
    v = 0.5 * np.array([m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1]])
    s = math.sqrt(v @ v)
    angle = math.atan2(s, 0.5 * (m[0, 0] + m[1, 1] + m[2, 2] - 1.0))
    dr = v * (angle / s) if s > 1e-12 else v
    return np.concatenate([dp, dr]), pos, angle
