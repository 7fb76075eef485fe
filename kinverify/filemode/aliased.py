"""A backend seen under the other file's frame names, so the kinematics checks pair frames by name."""

from __future__ import annotations

import numpy as np

from kinverify.backends.base import BackendBase, Evaluation


class AliasedBackend(BackendBase):
    """Delegates to ``inner`` (same joints, same order) and reports its frames as ``frames``."""

    def __init__(self, inner, frames) -> None:
        self.inner, self.name, self.frames = inner, inner.name, tuple(frames)
        self.joint_names = inner.joint_names
        self.has_rotation, self.jacobian_method = inner.has_rotation, inner.jacobian_method
        self.library, self.slow = inner.library, inner.slow

    def poses(self, q: np.ndarray) -> np.ndarray:
        return self.inner.poses(q)

    def jacobians(self, q: np.ndarray) -> np.ndarray:
        return self.inner.jacobians(q)

    def evaluate(self, q: np.ndarray, with_jacobians: bool = True) -> Evaluation:
        ev = self.inner.evaluate(q, with_jacobians)
        return Evaluation(self.name, self.frames, ev.poses, ev.jacobians)
