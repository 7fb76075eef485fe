"""The backend Protocol and the shared logic every backend gets for free.

A backend evaluates a batch of configurations ``q`` ``(N, n)`` (radians / metres, in the order of
``joint_names``) and returns, in kinverify's convention:

- poses ``T_world_from_frame`` ``(N, F, 4, 4)`` for ``frames``;
- Jacobians ``(N, F, 6, n)``: world-aligned, at the frame origin, rows ``[linear; angular]``.

Subclasses implement :meth:`BackendBase.poses` and, when the library offers one,
:meth:`BackendBase.jacobians`; the rest (finite differences, combined evaluation) lives here.
A backend whose library computes in lower precision declares ``agreement_floor`` (see
:func:`pair_floor`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np

from kinverify.model.transforms import rotation_log

FD_STEP = 1e-6  # rad or m; central differences: truncation ~h², round-off ~1e-16/h


@runtime_checkable
class Backend(Protocol):
    name: str
    joint_names: tuple[str, ...]
    frames: tuple[str, ...]
    has_rotation: bool
    jacobian_method: str | None  # "analytic", "finite-difference" or None
    slow: bool  # costly per configuration: compared on a capped number of configurations

    def poses(self, q: np.ndarray) -> np.ndarray: ...

    def jacobians(self, q: np.ndarray) -> np.ndarray: ...

    def evaluate(self, q: np.ndarray, with_jacobians: bool = True) -> "Evaluation": ...


@dataclass(frozen=True)
class Evaluation:
    """What one backend computed for one batch (arrays in kinverify's convention)."""

    backend: str
    frames: tuple[str, ...]
    poses: np.ndarray
    jacobians: np.ndarray | None


def finite_difference_jacobians(poses_fn, q: np.ndarray, step: float = FD_STEP) -> np.ndarray:
    """Central-difference Jacobians ``(N, F, 6, n)`` of any batched pose function.

    Linear rows: (p(q + h e_j) − p(q − h e_j)) / 2h. Angular rows: log(R₊ R₋ᵀ) / 2h, the world
    angular velocity that carries R₋ to R₊.
    """
    q = np.asarray(q, dtype=float)
    n_cfg, n = q.shape
    shifted = np.concatenate([q + step * e for e in np.eye(n)] + [q - step * e for e in np.eye(n)])
    poses = poses_fn(shifted).reshape(2, n, n_cfg, -1, 4, 4)
    plus, minus = poses[0], poses[1]  # (n, N, F, 4, 4)
    linear = (plus[..., :3, 3] - minus[..., :3, 3]) / (2 * step)
    angular = rotation_log(plus[..., :3, :3] @ np.swapaxes(minus[..., :3, :3], -1, -2)) / (2 * step)
    jac = np.concatenate([linear, angular], axis=-1)  # (n, N, F, 6)
    return np.moveaxis(jac, 0, -1)


class BackendBase:
    """Shared behaviour; subclasses set the attributes and implement :meth:`poses`.

    Capabilities are declared here, once per class: ``jacobian_method``, ``has_rotation`` and
    ``slow``; the library each registered backend runs (the distribution whose version every report
    records) is its line of the registry (:mod:`kinverify.backends`)."""

    name: str = "backend"
    joint_names: tuple[str, ...] = ()
    frames: tuple[str, ...] = ()
    has_rotation: bool = True
    jacobian_method: str | None = "analytic"
    slow: bool = False
    fd_step: float = FD_STEP  # step of its finite-difference Jacobians (a float32 library needs a larger one)
    # Per kinematics property, the least error this backend's comparisons are held to (a library
    # computing in float32, like Newton, cannot agree to the double-precision 1e-9): a check of a
    # pair holding it gets max(the property's tolerance, this floor). Empty: no floor.
    agreement_floor: dict[str, float] = {}

    def poses(self, q: np.ndarray) -> np.ndarray:
        raise NotImplementedError

    def jacobians(self, q: np.ndarray) -> np.ndarray:
        """Finite-difference Jacobians unless the subclass has analytic ones."""
        return finite_difference_jacobians(self.poses, self._check(q), self.fd_step)

    def evaluate(self, q: np.ndarray, with_jacobians: bool = True) -> Evaluation:
        q = self._check(q)
        jac = self.jacobians(q) if with_jacobians and self.jacobian_method else None
        return Evaluation(self.name, self.frames, self.poses(q), jac)

    def _check(self, q) -> np.ndarray:
        q = np.atleast_2d(np.asarray(q, dtype=float))
        if q.shape[1] != len(self.joint_names):
            raise ValueError(f"{self.name}: expected q of shape (N, {len(self.joint_names)}), got {q.shape}")
        return q

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name!r}: {len(self.joint_names)} joints, {len(self.frames)} frames>"


class EvaluatingBackend(BackendBase):
    """A backend whose library computes FK and Jacobians in one pass: :meth:`evaluate` is the
    primitive, and poses/Jacobians alone are read from it."""

    def poses(self, q: np.ndarray) -> np.ndarray:
        return self.evaluate(q, with_jacobians=False).poses

    def jacobians(self, q: np.ndarray) -> np.ndarray:
        jac = self.evaluate(q).jacobians
        assert jac is not None  # evaluated with Jacobians
        return jac


def pair_floor(prop: str, *backends) -> float:
    """The largest floor any of ``backends`` declares for kinematics property ``prop`` (0: none)."""
    return max([float(getattr(b, "agreement_floor", {}).get(prop, 0.0)) for b in backends if b is not None] or [0.0])
