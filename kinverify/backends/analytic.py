"""The reference backends: kinverify's own numpy FK straight from the spec (no library).

``analytic`` chains the spec's joint origins and motions; ``analytic-dh`` (DH specs only) uses the
DH matrices of :mod:`kinverify.dh`. Both are batched and compute geometric Jacobians from their FK.
"""

from __future__ import annotations

import numpy as np

from kinverify.model import dh as dhmod
from kinverify.model.kinematics import frame_poses, geometric_jacobians, tool_poses
from kinverify.model.spec import ArmSpec
from kinverify.backends.base import BackendBase, Evaluation


class AnalyticBackend(BackendBase):
    """FK and geometric Jacobians from the spec (:mod:`kinverify.model.kinematics`), already in
    kinverify's convention."""

    name = "analytic"

    def __init__(self, spec: ArmSpec) -> None:
        self.spec = spec
        self.joint_names = spec.coordinate_names  # the base's six first when floating
        self.frames = spec.frame_names

    def poses(self, q: np.ndarray) -> np.ndarray:
        return frame_poses(self.spec, self._check(q))

    def jacobians(self, q: np.ndarray) -> np.ndarray:
        q = self._check(q)
        return geometric_jacobians(self.spec, self.poses(q), q)

    def evaluate(self, q: np.ndarray, with_jacobians: bool = True) -> Evaluation:
        poses = self.poses(q)
        return Evaluation(self.name, self.frames, poses, geometric_jacobians(self.spec, poses, q) if with_jacobians else None)


class AnalyticDHBackend(AnalyticBackend):
    name = "analytic-dh"

    def __init__(self, spec: ArmSpec) -> None:
        if spec.dh is None:
            raise ValueError(f"{spec.name} has no DH table")
        super().__init__(spec)
        self._prismatic = [j.type == "prismatic" for j in spec.joints]

    def poses(self, q: np.ndarray) -> np.ndarray:
        q = self._check(q)
        links = np.empty((q.shape[0], self.spec.dof + 1, 4, 4))
        links[:, 0] = self.spec.base_origin.transform
        assert self.spec.dh is not None  # checked on construction
        links[:, 1:] = dhmod.dh_link_poses(self.spec.dh.convention, self.spec.dh.rows, self._prismatic, links[0, 0], q)
        return np.concatenate([links, tool_poses(self.spec, links)], axis=1)
