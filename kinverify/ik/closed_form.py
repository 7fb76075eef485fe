"""Closed-form IK of ``arm3``-shaped arms: base yaw (z) + shoulder and elbow pitch (y), tool on link3.

Geometry read from the spec (arm3: joint1 at z 0.42 + 0.1, shoulder 0.3 above it, link2 0.25,
tool 0.05 along link3's z). With ``r`` the signed horizontal reach along the yaw direction and
``h`` the height above the shoulder::

    r = l2·sin q2 + l3·sin(q2 + q3),   h = l2·cos q2 + l3·cos(q2 + q3)

Every branch is returned: shoulder front (``r = +ρ``, q1 = atan2(y, x)) or back (``r = −ρ``,
q1 + π), elbow ``q3 = ±acos(D)``; only those inside the joint limits are kept. On the yaw axis
(ρ = 0) q1 is free: q1 = 0 is returned for it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from kinverify.errors import InputError


@dataclass(frozen=True)
class ClosedFormResult:
    reachable: bool
    solutions: np.ndarray  # (k, 3), every branch inside the limits
    closest_distance: float  # m: 0 when reachable, else the closest approach over the limits


class Arm3ClosedForm:
    def __init__(self, shoulder: np.ndarray, l2: float, l3: float, lower, upper) -> None:
        self.shoulder, self.l2, self.l3 = np.asarray(shoulder, float), float(l2), float(l3)
        self.lower, self.upper = np.asarray(lower, float), np.asarray(upper, float)

    @classmethod
    def from_spec(cls, spec, tool: str | None = None) -> "Arm3ClosedForm":
        """Check the spec has the arm3 shape (identity rotations, offsets along z) and read its lengths."""
        if spec.dof != 3 or any(j.type != "revolute" for j in spec.joints) or not spec.is_serial:
            raise InputError(f"{spec.name}: closed-form IK needs 3 revolute joints (arm3 shape)")
        axes = [tuple(np.round(j.axis, 12)) for j in spec.joints]
        frame = spec.tools[-1] if tool is None else next(t for t in spec.tools if t.name == tool)
        origins = [j.origin for j in spec.joints[1:]] + [frame.origin]
        straight = all(np.allclose(o.transform[:3, :3], np.eye(3)) and np.allclose(o.transform[:2, 3], 0) for o in origins)
        if (
            axes != [(0, 0, 1), (0, 1, 0), (0, 1, 0)]
            or not straight
            or frame.parent != spec.joints[2].link.name
            or not np.allclose(spec.base_origin.transform[:3, :3], np.eye(3))
            or not np.allclose(spec.joints[0].origin.transform[:3, :3], np.eye(3))
        ):
            raise InputError(f"{spec.name}: closed-form IK needs the arm3 shape (yaw z, pitch y, pitch y, offsets along z)")
        base = spec.base_origin.transform @ spec.joints[0].origin.transform
        shoulder = base[:3, 3] + np.array([0.0, 0.0, spec.joints[1].origin.transform[2, 3]])
        return cls(shoulder, spec.joints[2].origin.transform[2, 3], frame.origin.transform[2, 3], spec.lower, spec.upper)

    def position(self, q) -> np.ndarray:
        """Tool position ``(..., 3)`` of configurations ``(..., 3)``."""
        q = np.asarray(q, float)
        r = self.l2 * np.sin(q[..., 1]) + self.l3 * np.sin(q[..., 1] + q[..., 2])
        h = self.l2 * np.cos(q[..., 1]) + self.l3 * np.cos(q[..., 1] + q[..., 2])
        return self.shoulder + np.stack([r * np.cos(q[..., 0]), r * np.sin(q[..., 0]), h], axis=-1)

    def all_branches(self, target) -> np.ndarray:
        """Every branch ``(k, 3)`` reaching ``target`` ignoring the limits (q1 wrapped to (−π, π])."""
        d = np.asarray(target, float) - self.shoulder
        rho, h = math.hypot(d[0], d[1]), d[2]
        yaw = math.atan2(d[1], d[0]) if rho > 0 else 0.0
        cos3 = (rho * rho + h * h - self.l2**2 - self.l3**2) / (2 * self.l2 * self.l3)
        if abs(cos3) > 1.0 + 1e-12:
            return np.empty((0, 3))
        q3s = sorted({math.acos(max(-1.0, min(1.0, cos3))), -math.acos(max(-1.0, min(1.0, cos3)))})
        out = []
        for sign, q1 in ((1.0, yaw), (-1.0, yaw + math.pi)):
            for q3 in q3s:
                q2 = math.atan2(sign * rho, h) - math.atan2(self.l3 * math.sin(q3), self.l2 + self.l3 * math.cos(q3))
                out.append([_wrap(q1), _wrap(q2), q3])
        return np.unique(np.round(np.array(out), 15), axis=0)

    def solve(self, target) -> ClosedFormResult:
        branches = self.all_branches(target)
        # A branch that lies on a limit can come out beyond it by the precision the target's
        # floats determine it to (see pitch_precision): accept that much, clip into the limits, then
        # solve the other pitch joint exactly for the clipped value (clipping alone would move the
        # tool by reach × the clipped amount).
        slack = np.array([LIMIT_SLACK, *[LIMIT_SLACK + self.pitch_precision(target)] * 2])
        inside = np.all((branches >= self.lower - slack) & (branches <= self.upper + slack), axis=1)
        if inside.any():
            return ClosedFormResult(True, np.array([self._onto_limits(b, target) for b in branches[inside]]), 0.0)
        return ClosedFormResult(False, np.empty((0, 3)), self.closest_distance(target))

    def pitch_precision(self, target) -> float:
        """How precisely [rad] the pitch angles are determined by ``target`` given as floats.

        The elbow angle follows from the shoulder-target distance ``s``; near the straight elbow
        ``(l2 + l3) − s ≈ l2·l3·q3² / (2(l2 + l3))``, so a rounding ``δs`` of ``s`` moves q3 by up to
        ``√(2(l2 + l3)·δs / (l2·l3))`` (about 3e-7 rad for arm3: the singularity, not the code)."""
        d = np.asarray(target, float) - self.shoulder
        scale = max(float(np.abs(target).max()), float(np.abs(self.shoulder).max()), self.l2 + self.l3)
        ds = 8 * np.finfo(float).eps * scale  # rounding of target − shoulder and of the hypotenuse
        return math.sqrt(2 * (self.l2 + self.l3) * ds / (self.l2 * self.l3)) if np.linalg.norm(d) > 0 else 0.0

    def _onto_limits(self, branch: np.ndarray, target) -> np.ndarray:
        q = np.clip(branch, self.lower, self.upper)
        r, h = self._planar(q[0], target)
        if q[1] != branch[1]:  # shoulder on its limit: aim the forearm from the elbow at the target
            q[2] = _wrap(math.atan2(r - self.l2 * math.sin(q[1]), h - self.l2 * math.cos(q[1])) - q[1])
        elif q[2] != branch[2]:  # elbow on its limit: aim the shoulder for that elbow angle
            q[1] = _wrap(math.atan2(r, h) - math.atan2(self.l3 * math.sin(q[2]), self.l2 + self.l3 * math.cos(q[2])))
        return np.clip(q, self.lower, self.upper)

    def _planar(self, q1: float, target) -> tuple[float, float]:
        """The target in the arm's plane at yaw ``q1``: signed reach along the yaw direction, height."""
        d = np.asarray(target, float) - self.shoulder
        return float(d[0] * math.cos(q1) + d[1] * math.sin(q1)), float(d[2])

    def closest_distance(self, target, grid: int = 361) -> float:
        """Closest approach [m] to ``target`` over the limits: a (q2, q3) grid with q1 aimed at the
        target (front or back), refined by the grid's spacing. Resolution ≈ (l2 + l3) · Δq."""
        d = np.asarray(target, float) - self.shoulder
        rho, h = math.hypot(d[0], d[1]), d[2]
        q2 = np.linspace(self.lower[1], self.upper[1], grid)
        q3 = np.linspace(self.lower[2], self.upper[2], grid)
        for _ in range(3):  # zoom on the best cell twice
            a, b = np.meshgrid(q2, q3, indexing="ij")
            r = self.l2 * np.sin(a) + self.l3 * np.sin(a + b)
            z = self.l2 * np.cos(a) + self.l3 * np.cos(a + b)
            # yaw can point the arm's plane at the target (front, r>=0) or away (back, r<=0);
            # if q1's limits forbid both, the planar distance below is a lower bound.
            dist = np.hypot(np.abs(r) - rho, z - h)
            i, k = np.unravel_index(np.argmin(dist), dist.shape)
            best = float(dist[i, k])
            s2, s3 = q2[1] - q2[0], q3[1] - q3[0]
            q2 = np.linspace(max(self.lower[1], q2[i] - s2), min(self.upper[1], q2[i] + s2), 41)
            q3 = np.linspace(max(self.lower[2], q3[k] - s3), min(self.upper[2], q3[k] + s3), 41)
        return best


LIMIT_SLACK = 1e-9  # rad


def _wrap(a: float) -> float:
    """Angle in (−π, π]."""
    a = math.remainder(a, 2 * math.pi)
    return math.pi if a == -math.pi else a
