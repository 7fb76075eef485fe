"""USD (OpenUSD, read with ``usd-core``): FK of a USD articulation by composing its joint frames.

Native convention of the library (``pxr``): joint frames are ``physics:localPos0/localRot0`` in
body0 and ``localPos1/localRot1`` in body1; rotations are ``GfQuat`` written (real, imaginary) =
(w, x, y, z); ``Gf`` matrices act on row vectors (transposed here); angular values (limits, drive
gains, velocities) are in degrees; lengths in stage units (``metersPerUnit``). A body's world
pose is ``T_body1 = T_body0 · localPose0 · motion(q about/along the joint axis) · localPose1⁻¹``
from the articulation's root (:func:`kinverify.backends.usd_stage.forward`). Jacobians: each
joint's column from its world axis line (``[a × (p − o); a]`` for a revolute joint, ``[a; 0]`` for a
prismatic one); with a floating base, finite differences of the FK.
"""

from __future__ import annotations

import os
import tempfile
from functools import lru_cache

import numpy as np
import pxr  # noqa: F401  (the backend is unavailable without the extra "usd")

from kinverify.backends.base import BackendBase, finite_difference_jacobians
from kinverify.backends.usd_stage import UsdRobot, forward, read_robot
from kinverify.errors import UnknownNameError
from kinverify.model.floating import BASE_COORDINATES, base_transforms


@lru_cache(maxsize=8)
def _robot_of_file(path: str, stamp: tuple) -> UsdRobot:
    return read_robot(path)


def load_robot(usd_text_or_path: str) -> UsdRobot:
    """The articulation of a USD file (a path), or of USD text (``#usda`` ...; written to a
    scratch file first so pxr reads it like any layer)."""
    if usd_text_or_path.lstrip().startswith("#usda") or "\n" in usd_text_or_path:
        with tempfile.TemporaryDirectory() as folder:
            path = os.path.join(folder, "model.usda")
            with open(path, "w", encoding="utf-8") as f:
                f.write(usd_text_or_path)
            return read_robot(path)
    st = os.stat(usd_text_or_path)
    return _robot_of_file(os.path.abspath(usd_text_or_path), (st.st_mtime_ns, st.st_size))


class UsdBackend(BackendBase):
    """FK of a USD articulation (pxr reads it; the joint frames composed in numpy)."""

    jacobian_method = "analytic"
    # UsdPhysics stores joint frames in single precision (point3f localPos, quatf localRot): each value
    # is off by up to 2^-24 of itself (6e-8), and a chain of 30 joints over 2 m adds up to about
    # 2e-6 m and 2e-6 rad (measured on the shipped specs: 2.4e-8 m). Below that a USD cannot state a
    # difference, so its comparisons are held to no less.
    agreement_floor = {"fk.position": 2e-6, "fk.rotation": 2e-6, "jacobian.linear": 2e-6, "jacobian.angular": 2e-6}

    def __init__(self, robot: UsdRobot, joint_names, frames, name: str = "usd") -> None:
        self.robot, self.name = robot, name
        self.joint_names, self.frames = tuple(joint_names), tuple(frames)
        self.floating = self.joint_names[:6] == BASE_COORDINATES  # the six base coordinates first: the root body moves
        movable = {j.name for j in robot.joints if j.kind in ("revolute", "prismatic")}
        unknown = [j for j in self.joint_names if j not in movable and not j.startswith("base:")]
        if unknown:
            raise UnknownNameError("USD joint", unknown[0], sorted(movable))
        if self.floating:
            self.jacobian_method = "finite-difference"
        by_name = {n: b for b, n in robot.names.items()}
        self._where = []
        for f in self.frames:
            if f in by_name:
                self._where.append((by_name[f], np.eye(4)))
            elif f in robot.sites:
                self._where.append(robot.sites[f][:2])
            else:
                raise UnknownNameError("USD frame", f, sorted(by_name) + sorted(robot.sites))

    @classmethod
    def from_usd(cls, usd_text_or_path: str, joint_names, frames, name: str = "usd") -> "UsdBackend":
        return cls(load_robot(usd_text_or_path), joint_names, frames, name=name)

    def jacobians(self, q: np.ndarray) -> np.ndarray:
        """World-aligned Jacobians at each frame's origin, rows [linear; angular]."""
        if self.floating:
            return finite_difference_jacobians(self.poses, self._check(q))
        q = self._check(q)
        n, robot = len(q), self.robot
        world = forward(robot, {name: q[:, i] for i, name in enumerate(self.joint_names)}, n)
        column = {name: i for i, name in enumerate(self.joint_names)}
        out = np.zeros((n, len(self.frames), 6, len(self.joint_names)))
        for k, (body, local) in enumerate(self._where):
            point = (world[body] @ local)[:, :3, 3]
            b = body
            while b != robot.root:
                j = robot.parent_joint[b]
                if j.name in column:
                    flipped = j.path in robot.flipped
                    frame = world[j.body1] @ j.x1 if flipped else world[j.body0] @ j.x0
                    axis = frame[:, :3, j.axis] * (-1.0 if flipped else 1.0)
                    i = column[j.name]
                    if j.kind == "revolute":
                        out[:, k, :3, i] = np.cross(axis, point - frame[:, :3, 3])
                        out[:, k, 3:, i] = axis
                    else:
                        out[:, k, :3, i] = axis
                b = j.body0 if b == j.body1 else j.body1
        return out

    def poses(self, q: np.ndarray) -> np.ndarray:
        q = self._check(q)
        n = len(q)
        values = {name: q[:, i] for i, name in enumerate(self.joint_names)}
        base = np.tile(np.eye(4), (n, 1, 1))
        if self.floating:  # the six base coordinates (x y z roll pitch yaw) of a floating base
            base = base_transforms(q[:, :6])
        world = forward(self.robot, values, n)
        out = np.empty((n, len(self.frames), 4, 4))
        for k, (body, local) in enumerate(self._where):
            out[:, k] = base @ world[body] @ local
        return out
