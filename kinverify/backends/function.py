"""A user's own FK function as one more backend (e.g. a hand-derived closed form)."""

from __future__ import annotations

from typing import Callable

import numpy as np

from kinverify.backends.base import BackendBase


class FunctionBackend(BackendBase):
    """Wrap ``fk(q) -> array`` where ``q`` is ``(N, n)`` [rad, m] and the result is either
    positions ``(N, F, 3)`` [m] (then only ``fk.position`` is compared) or poses ``(N, F, 4, 4)``.
    With ``batched=False``, ``fk`` takes one ``(n,)`` vector and returns ``(F, 3)`` or ``(F, 4, 4)``.
    Its Jacobians, when compared, are finite differences of ``fk``.
    """

    def __init__(self, name: str, fk: Callable, joint_names, frames, batched: bool = True, jacobians: bool = False) -> None:
        self.name, self.fk, self.batched = name, fk, batched
        self.joint_names, self.frames = tuple(joint_names), tuple(frames)
        self.jacobian_method = "finite-difference" if jacobians else None
        probe = self._call(np.zeros((1, len(self.joint_names))))
        self.has_rotation = probe.shape[-2:] == (4, 4)

    def _call(self, q: np.ndarray) -> np.ndarray:
        out = np.asarray(self.fk(q) if self.batched else [self.fk(qk) for qk in q], dtype=float)
        if out.ndim == 2:  # a single frame given as (N, 3)
            out = out[:, None, :]
        if out.shape[:2] != (q.shape[0], len(self.frames)) or out.shape[2:] not in ((3,), (4, 4)):
            raise ValueError(
                f"{self.name}: fk returned shape {out.shape}; expected (N, {len(self.frames)}, 3) or (N, {len(self.frames)}, 4, 4)"
            )
        return out

    def poses(self, q: np.ndarray) -> np.ndarray:
        out = self._call(self._check(q))
        if out.shape[-1] == 3:
            poses = np.tile(np.eye(4), out.shape[:2] + (1, 1))
            poses[..., :3, 3] = out
            return poses
        return out
