"""One frame of one backend as IK sees it: batched ``q (B, n) -> (T (B, 4, 4), J (B, 6, n))``.

The generic path goes through the Backend Protocol (``backend.evaluate``) and keeps the
requested frame. Two fast paths compute only what IK needs, in the same convention: the
analytic backend through the spec's :class:`~kinverify.ik.chain.SerialChain` to the frame
(batched numpy, many targets and restarts per call) and Pinocchio's per-configuration
``computeFrameJacobian`` (:meth:`PinocchioBackend.frame_kinematics`).
"""

from __future__ import annotations

import numpy as np

from kinverify.errors import InputError, UnknownNameError
from kinverify.model.transforms import rotation_angle, rotation_log


class FrameModel:
    """FK and world-aligned Jacobian ``[linear; angular]`` of ``frame`` on ``backend``, in the
    forms the solvers call: batched (:meth:`__call__`, :meth:`soa`) and per configuration
    (:meth:`point`). ``revolute`` ``(n,)``: joints a whole turn may shift (default from the spec)."""

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
        self.chain = None
        if (
            type(backend) is AnalyticBackend and not backend.spec.floating
        ):  # the spec's chain to the frame: FK + J of that frame only
            from kinverify.ik.chain import SerialChain

            self.chain = SerialChain.from_spec(backend.spec, frame)
        self._tables: dict = {}
        self.seed_model = self  # whose FK builds the seed table: another model of the same frame may lend its own

    @classmethod
    def from_chain(cls, chain, name: str = "chain", frame: str = "tip") -> "FrameModel":
        """A batched model of a :class:`SerialChain` alone (e.g. from a URDF): no backend."""
        model = cls.__new__(cls)
        model.backend, model.frame, model.name, model.index = None, frame, name, 0
        model.dof, model.batched, model.chain, model._tables, model.seed_model = chain.width, True, chain, {}, model
        model.revolute = np.zeros(chain.width, bool)
        model.revolute[chain.columns] = chain.revolute
        return model

    def __call__(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``q`` ``(B, n)`` -> poses ``(B, 4, 4)``, Jacobians ``(B, 6, n)``."""
        q = np.atleast_2d(np.asarray(q, dtype=float))
        if self.chain is not None:
            rot, p, jac = self.chain.fk_jac(q)
            return _poses(rot, p), np.ascontiguousarray(jac)
        ev = self.backend.evaluate(q)
        return ev.poses[:, self.index], ev.jacobians[:, self.index]

    def soa(self, qT: np.ndarray):
        """The batched solver's form: ``qT`` ``(n, B)`` -> rotation columns ``(3, 3, B)``,
        positions ``(3, B)``, Jacobians ``(6, n, B)`` (see :meth:`SerialChain.fk_jac_soa`)."""
        if self.chain is not None:
            return self.chain.fk_jac_soa(qT)
        poses, jac = self(qT.T)
        return poses[:, :3, :3].transpose(2, 1, 0), poses[:, :3, 3].T, jac.transpose(1, 2, 0)

    def point(self):
        """The per-target solver's form: ``(fk, log3)`` with ``fk(q (n,)) -> (R (3, 3), p (3,),
        J (6, n))`` (possibly views valid until the next call) and the matching ``log3``."""
        lean = getattr(self.backend, "frame_kinematics", None)
        if lean is not None:
            return lean(self.index)
        from kinverify.ik.single import log3

        def fk(q):
            pose, jac = self(q[None])
            return pose[0, :3, :3], pose[0, :3, 3], jac[0]

        return fk, log3

    def single(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """One configuration ``(n,)`` -> ``T (4, 4)``, ``J (6, n)``."""
        poses, jac = self(q[None])
        return poses[0], jac[0]

    def poses(self, q: np.ndarray) -> np.ndarray:
        if self.chain is not None:
            return self.chain.poses(q)
        q = np.atleast_2d(np.asarray(q, dtype=float))
        return self.backend.evaluate(q, with_jacobians=False).poses[:, self.index]

    def seed_table(self, lower, upper, position_only: bool, samples: int):
        """``(SeedTable or None, build time s)`` for these finite sampling bounds, built once by
        ``seed_model`` (seeds are only starting points: any FK of the same frame gives usable ones,
        so a slow backend can borrow the analytic chain's table)."""
        owner = self.seed_model
        if samples <= 0:
            return None, 0.0
        key = (lower.tobytes(), upper.tobytes(), position_only, samples)
        if key not in owner._tables:
            import time

            from kinverify.ik.seeds import SeedTable

            t0 = time.perf_counter()
            table = SeedTable(owner.soa, lower, upper, samples=samples, w_rot=0.0 if position_only else 0.2)
            owner._tables[key] = (table, time.perf_counter() - t0)
            return owner._tables[key]
        return owner._tables[key][0], 0.0


def _poses(rot: np.ndarray, p: np.ndarray) -> np.ndarray:
    out = np.zeros(rot.shape[:-2] + (4, 4))
    out[..., :3, :3] = rot
    out[..., :3, 3] = p
    out[..., 3, 3] = 1.0
    return out


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
