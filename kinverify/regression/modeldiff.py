"""Behaviour-level difference between two versions of a model (``kinverify diff OLD NEW``).

Both specs are evaluated with the analytic kinematics at the same configurations (the old
spec's seeded sample set, edges included): per frame present in both, the largest change of
position, orientation and Jacobian. Workspace reach is computed for each spec over its own
sample set: the largest distance of each tool frame (or the last link) from the base link.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from kinverify.model.kinematics import frame_poses, geometric_jacobians
from kinverify.model.spec import ArmSpec
from kinverify.model.transforms import geodesic_distance
from kinverify.pipeline.sampling import spec_samples
from kinverify.regression.specdiff import ParamChange, diff_specs

DIFF_SAMPLES = 200
REACH_SAMPLES = 2000


@dataclass(frozen=True)
class FrameChange:
    """Largest change over the sample set for one frame; ``q`` is where the position moved most."""

    frame: str
    position: float  # m
    rotation: float  # rad
    jacobian_linear: float  # Frobenius norm, m/rad (m/m for prismatic columns)
    jacobian_angular: float
    q: tuple[float, ...]

    def to_dict(self) -> dict[str, Any]:
        return {**self.__dict__, "q": list(self.q)}


@dataclass(frozen=True)
class ReachChange:
    frame: str
    old: float | None  # m; None when the frame is missing from that spec
    new: float | None

    @property
    def change(self) -> float | None:
        return None if self.old is None or self.new is None else self.new - self.old


@dataclass
class ModelDiff:
    old_name: str
    new_name: str
    params: list[ParamChange]
    frames: list[FrameChange] = field(default_factory=list)
    reach: list[ReachChange] = field(default_factory=list)
    samples: int = 0
    notes: list[str] = field(default_factory=list)

    @property
    def identical(self) -> bool:
        return not self.params and all(
            max(f.position, f.rotation, f.jacobian_linear, f.jacobian_angular) == 0 for f in self.frames
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "old": self.old_name,
            "new": self.new_name,
            "samples": self.samples,
            "params": [p.to_dict() for p in self.params],
            "frames": [f.to_dict() for f in self.frames],
            "reach": [{"frame": r.frame, "old": r.old, "new": r.new, "change": r.change} for r in self.reach],
            "notes": self.notes,
        }


def reach(spec: ArmSpec, samples: int = REACH_SAMPLES, seed: int = 0) -> dict[str, float]:
    """Largest distance [m] from the base link origin of each tool (or of the last link when
    the arm has no tools) over the spec's sample set."""
    q = spec_samples(spec, samples, seed)
    poses = frame_poses(spec, q)
    names = list(spec.frame_names)
    targets = list(spec.tool_names) or [spec.link_names[-1]]
    base = poses[:, 0, :3, 3]
    return {f: float(np.max(np.linalg.norm(poses[:, names.index(f), :3, 3] - base, axis=-1))) for f in targets}


def frame_changes(old: ArmSpec, new: ArmSpec, q: np.ndarray) -> list[FrameChange]:
    """Per common frame, the largest FK and Jacobian change at configurations ``q``."""
    po, pn = frame_poses(old, q), frame_poses(new, q)
    jo, jn = geometric_jacobians(old, po, q), geometric_jacobians(new, pn, q)
    old_names = list(old.frame_names)
    out = []
    for f, frame in enumerate(new.frame_names):
        if frame not in old_names:
            continue
        g = old_names.index(frame)
        dp = np.linalg.norm(pn[:, f, :3, 3] - po[:, g, :3, 3], axis=-1)
        dr = geodesic_distance(po[:, g, :3, :3], pn[:, f, :3, :3])
        dj = jn[:, f] - jo[:, g]
        worst = int(np.argmax(dp)) if dp.max() > 0 else int(np.argmax(dr))
        out.append(
            FrameChange(
                frame,
                float(dp.max()),
                float(dr.max()),
                float(np.linalg.norm(dj[:, :3], axis=(-2, -1)).max()),
                float(np.linalg.norm(dj[:, 3:], axis=(-2, -1)).max()),
                tuple(q[worst].tolist()),
            )
        )
    return out


def diff_models(old: ArmSpec, new: ArmSpec, samples: int = DIFF_SAMPLES, seed: int = 0) -> ModelDiff:
    """Parameter-level and behaviour-level differences from ``old`` to ``new``."""
    result = ModelDiff(old.name, new.name, diff_specs(old, new))
    if old.nq != new.nq or old.floating != new.floating:
        what = (
            "the base floats in one version only"
            if old.floating != new.floating
            else f"joint count changed ({old.dof} -> {new.dof})"
        )
        result.notes.append(f"{what}: FK and Jacobians cannot be compared at the same configurations")
    else:
        q = spec_samples(old, samples, seed)
        result.samples = len(q)
        result.frames = frame_changes(old, new, q)
        if not (np.array_equal(old.lower, new.lower) and np.array_equal(old.upper, new.upper)):
            result.notes.append("joint limits changed: FK and Jacobians are compared inside the old limits")
    ro, rn = reach(old), reach(new)
    result.reach = [ReachChange(f, ro.get(f), rn.get(f)) for f in dict.fromkeys([*ro, *rn])]
    return result
