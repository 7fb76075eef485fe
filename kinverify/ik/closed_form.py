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
        if spec.dof != 3 or any(j.type != "revolute" for j in spec.joints):
            raise InputError(f"{spec.name}: closed-form IK needs 3 revolute joints (arm3 shape)")
        axes = [tuple(np.round(j.axis, 12)) for j in spec.joints]
        tool = spec.tools[-1] if tool is None else next(t for t in spec.tools if t.name == tool)
        origins = [j.origin for j in spec.joints[1:]] + [tool.origin]
        straight = all(np.allclose(o.transform[:3, :3], np.eye(3)) and np.allclose(o.transform[:2, 3], 0) for o in origins)
        if axes != [(0, 0, 1), (0, 1, 0), (0, 1, 0)] or not straight or tool.parent != spec.joints[2].link.name \
                or not np.allclose(spec.base_origin.transform[:3, :3], np.eye(3)) \
                or not np.allclose(spec.joints[0].origin.transform[:3, :3], np.eye(3)):
            raise InputError(f"{spec.name}: closed-form IK needs the arm3 shape (yaw z, pitch y, pitch y, offsets along z)")
        base = spec.base_origin.transform @ spec.joints[0].origin.transform
        shoulder = base[:3, 3] + np.array([0.0, 0.0, spec.joints[1].origin.transform[2, 3]])
        return cls(shoulder, spec.joints[2].origin.transform[2, 3], tool.origin.transform[2, 3], spec.lower, spec.upper)

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
        cos3 = (rho * rho + h * h - self.l2 ** 2 - self.l3 ** 2) / (2 * self.l2 * self.l3)
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
        # Near the straight elbow acos loses precision (~1e-16/|q3| rad), so a branch that lies on
        # a limit can come out ~1e-11 beyond it: accept 1e-9 rad, then clip into the limits.
        inside = np.all((branches >= self.lower - LIMIT_SLACK) & (branches <= self.upper + LIMIT_SLACK), axis=1)
        if inside.any():
            return ClosedFormResult(True, np.clip(branches[inside], self.lower, self.upper), 0.0)
        return ClosedFormResult(False, np.empty((0, 3)), self.closest_distance(target))

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
