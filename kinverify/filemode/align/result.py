"""What the alignment found (see :mod:`kinverify.filemode.align.fit`): the world transform, the
joint map (``q_mjcf = s · q_urdf + o``), couplings, and how each matched frame fits after it; and
:class:`PairPoses`, both files' FK at the matched joints' values."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from kinverify.backends import ModelSources, build_backend
from kinverify.backends.mujoco_ import MujocoBackend
from kinverify.backends.pinocchio_ import PinocchioBackend
from kinverify.filemode.align.match import Matching
from kinverify.filemode.read.model import Coupling, ModelDesc


@dataclass
class JointMap:
    urdf: str
    mjcf: str
    type: str
    sign: int = 1
    offset: float = 0.0


@dataclass
class FrameFit:
    """One matched frame after alignment: max over the fit's configurations of the position and
    rotation error with ``T`` and the joint map applied, and after removing a constant offset ``C``
    (``pose_urdf = T⁻¹ · pose_mjcf · C``)."""

    urdf: str
    mjcf: str
    why: str
    position: float
    rotation: float
    constant: np.ndarray
    residual_position: float
    residual_rotation: float
    in_fit: bool


@dataclass
class Alignment:
    T: np.ndarray  # T_mjcf_from_urdf (4x4)
    joints: list[JointMap]  # URDF chain order
    couplings: dict[str, Coupling]  # URDF follower -> coupling (URDF names)
    independent: list[str]
    frames: list[FrameFit] = field(default_factory=list)
    axis_errors: dict[str, tuple[float, float]] = field(default_factory=dict)  # joint -> (angle rad, line distance m)
    residual: tuple[float, float] = (0.0, 0.0)  # fit residual (m, rad) over the features kept
    candidate: str = ""
    unexplained: int = 0
    attribution: dict = field(default_factory=dict)  # URDF joint -> align.attribution.Attribution (after the fit)

    def joint(self, urdf: str) -> JointMap:
        return next(j for j in self.joints if j.urdf == urdf)

    @property
    def signs(self) -> np.ndarray:
        return np.array([j.sign for j in self.joints], dtype=float)

    @property
    def offsets(self) -> np.ndarray:
        return np.array([j.offset for j in self.joints], dtype=float)

    def expand(self, q: np.ndarray) -> np.ndarray:
        """Independent joint values (N, n_independent) -> every matched joint (N, n), URDF order."""
        q = np.atleast_2d(np.asarray(q, dtype=float))
        names = [j.urdf for j in self.joints]
        full = np.zeros((q.shape[0], len(names)))
        col = {n: i for i, n in enumerate(names)}
        for k, name in enumerate(self.independent):
            full[:, col[name]] = q[:, k]
        for follower, c in self.couplings.items():
            full[:, col[follower]] = c.multiplier * full[:, col[c.leader]] + c.offset
        return full

    def expansion(self) -> np.ndarray:
        """d(every matched joint)/d(independent joints): (n, n_independent)."""
        names = [j.urdf for j in self.joints]
        e = np.zeros((len(names), len(self.independent)))
        for k, name in enumerate(self.independent):
            e[names.index(name), k] = 1.0
        for follower, c in self.couplings.items():
            e[names.index(follower)] = c.multiplier * e[names.index(c.leader)]
        return e

    def to_mjcf(self, q_full: np.ndarray) -> np.ndarray:
        return q_full * self.signs + self.offsets

    def frame_constant(self, urdf_frame: str) -> np.ndarray:
        return next((f.constant for f in self.frames if f.urdf == urdf_frame), np.eye(4))


class PairPoses:
    """FK of both files' frames at configurations of the matched joints (each file's own names):
    Pinocchio on the URDF, MuJoCo on the MJCF, Drake on an SDFormat side (joints in one file only held at zero, MJCF ones at
    ``qpos0``, where MuJoCo places a joint with a ``ref``)."""

    def __init__(
        self, u: ModelDesc, m: ModelDesc, matching: Matching, urdf_text: str, mjcf_text: str, urdf_library: str = "pinocchio"
    ) -> None:

        self.u, self.m = u, m
        self.ujoints = [a for a, _, _ in matching.joints]
        self.mjoints = [b for _, b, _ in matching.joints]
        self.uframes, self.mframes = list(u.frames), list(m.frames)
        if u.kind == "usd":
            self.ub = build_backend("usd", ModelSources("", tuple(self.ujoints), tuple(self.uframes), (), (), (), usd=urdf_text))
        elif u.kind == "sdf" or urdf_library == "drake":  # an SDFormat side, or a URDF only Drake reads
            texts: dict = {u.kind: urdf_text}  # the text of u.kind
            self.ub = build_backend(
                f"drake-{u.kind}", ModelSources("", tuple(self.ujoints), tuple(self.uframes), (), (), (), **texts)
            )
        else:
            reader = PinocchioBackend if urdf_library == "pinocchio" else MujocoBackend
            self.ub = reader.from_urdf(urdf_text, self.ujoints, self.uframes)
        if m.kind == "usd":
            self.mb = build_backend("usd", ModelSources("", tuple(self.mjoints), tuple(self.mframes), (), (), (), usd=mjcf_text))
        elif m.kind == "sdf":
            self.mb = build_backend(
                "drake-sdf", ModelSources("", tuple(self.mjoints), tuple(self.mframes), (), (), (), sdf=mjcf_text)
            )
        else:
            self.mb = MujocoBackend.from_mjcf(mjcf_text, self.mjoints, self.mframes)
        self.ui = {f: i for i, f in enumerate(self.uframes)}
        self.mi = {f: i for i, f in enumerate(self.mframes)}

    def urdf(self, q_full: np.ndarray) -> np.ndarray:
        return self.ub.poses(np.atleast_2d(q_full))

    def mjcf(self, q_mjcf: np.ndarray) -> np.ndarray:
        return self.mb.poses(np.atleast_2d(q_mjcf))
