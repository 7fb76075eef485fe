"""A backend of one file seen through the alignment, so the kinematics checks compare the two
files after what alignment explains: the independent joints in (followers of a coupling computed
from their leaders), the other file's joint values out (``q_mjcf = s·q + o``), poses brought into
the URDF's world (``left = T⁻¹``) and each frame's constant convention removed (``· C``), under
the URDF's frame names. With a floating base (``inner`` built on the six base coordinates first,
:mod:`kinverify.filemode.align.floating`) the base coordinates lead ``q``: the MJCF side gets the base
pose ``T·B·T⁻¹`` in its world (``T = left⁻¹``), its Jacobian's base columns chained through it."""

from __future__ import annotations

import numpy as np

from kinverify.backends.base import BackendBase, Evaluation
from kinverify.filemode.align.floating import conjugated
from kinverify.filemode.align.result import Alignment
from kinverify.model.floating import BASE_COORDINATES


class AlignedBackend(BackendBase):
    """``inner`` is built on every matched joint in the alignment's order ("urdf": URDF names and
    values; "mjcf": the MJCF's names and values), or on ``pick`` of them (URDF names): a library that
    drives some couplings itself, like yourdfpy the URDF's ``<mimic>`` followers, is given the other
    joints only, each at the value every other library gets."""

    def __init__(
        self,
        inner,
        alignment: Alignment,
        frames,
        mode: str,
        left: np.ndarray | None = None,
        constants: list[np.ndarray] | np.ndarray | None = None,
        pick: list[str] | None = None,
    ) -> None:
        self.inner, self.alignment, self.mode = inner, alignment, mode
        self.name, self.frames = inner.name, tuple(frames)
        self.floating = bool(getattr(inner, "floating", False))
        self.joint_names = BASE_COORDINATES * self.floating + tuple(alignment.independent)
        self.has_rotation, self.jacobian_method = inner.has_rotation, inner.jacobian_method
        self.slow = getattr(inner, "slow", False)
        self.fd_step = getattr(inner, "fd_step", self.fd_step)
        self.agreement_floor = getattr(inner, "agreement_floor", {})
        self.left = np.eye(4) if left is None else np.asarray(left, dtype=float)
        self.constants = None if constants is None else np.asarray(constants, dtype=float)  # (F, 4, 4)
        names = [j.urdf for j in alignment.joints]
        self.cols = None if pick is None else [names.index(n) for n in pick]
        e = alignment.expansion()
        self.chain = e * alignment.signs[:, None] if mode == "mjcf" else e  # d q_inner / d q
        if self.cols is not None:
            self.chain = self.chain[self.cols]

    def _conjugates(self) -> bool:
        return self.floating and self.mode == "mjcf" and not np.array_equal(self.left, np.eye(4))

    def _inner_q(self, q: np.ndarray) -> np.ndarray:
        if self.floating:
            base = conjugated(np.linalg.inv(self.left), q[:, :6])[0] if self._conjugates() else q[:, :6]
            return np.concatenate([base, self._joints_q(q[:, 6:])], axis=1)
        return self._joints_q(q)

    def _joints_q(self, q: np.ndarray) -> np.ndarray:
        full = self.alignment.expand(q)
        full = self.alignment.to_mjcf(full) if self.mode == "mjcf" else full
        return full if self.cols is None else full[:, self.cols]

    def _chain(self, jac: np.ndarray, q: np.ndarray) -> np.ndarray:
        """Jacobian columns of the inner coordinates (N, F, 6, n_inner) as ours."""
        if not self.floating:
            return jac @ self.chain
        base = jac[..., :6]
        if self._conjugates():
            base = base @ conjugated(np.linalg.inv(self.left), q[:, :6])[1][:, None]
        return np.concatenate([base, jac[..., 6:] @ self.chain], axis=-1)

    def _poses(self, poses: np.ndarray) -> np.ndarray:
        out = self.left @ poses
        return out if self.constants is None else out @ self.constants

    def poses(self, q: np.ndarray) -> np.ndarray:
        q = self._check(q)
        return self._poses(self.inner.poses(self._inner_q(q)))

    def evaluate(self, q: np.ndarray, with_jacobians: bool = True) -> Evaluation:
        q = self._check(q)
        if self.jacobian_method != "analytic":
            return super().evaluate(q, with_jacobians)
        ev = self.inner.evaluate(self._inner_q(q), with_jacobians)
        poses = self._poses(ev.poses)
        jac = None
        if ev.jacobians is not None:
            jac = self._chain(ev.jacobians, q)  # (N, F, 6, n)
            rot = self.left[:3, :3]
            lin, ang = rot @ jac[..., :3, :], rot @ jac[..., 3:, :]
            if self.constants is not None:  # the frame origin moved by the constant: v' = v + ω × r
                r = poses[..., :3, 3] - (self.left @ ev.poses)[..., :3, 3]  # (N, F, 3)
                lin = lin + np.cross(ang, r[..., :, None], axis=-2)
            jac = np.concatenate([lin, ang], axis=-2)
        return Evaluation(self.name, self.frames, poses, jac)

    def jacobians(self, q: np.ndarray) -> np.ndarray:
        if self.jacobian_method != "analytic":
            return super().jacobians(q)  # finite differences of the aligned poses
        jac = self.evaluate(q).jacobians
        assert jac is not None  # evaluated with Jacobians
        return jac
