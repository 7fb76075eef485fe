"""What file mode hands the suites that compare the two files (``VerifyOptions.extra["filemode"]``):
both descriptions, the matching, the alignment, the tolerance floors from the written precision,
and the body frames' poses at the aligned zero. Plain data (numpy arrays and dataclasses), so it
travels with the options to worker processes. In spec mode the suites build the same view of the
generated files with :meth:`FileModeInfo.from_sources`: same names, no alignment, no floors."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from kinverify.filemode.align.match import Matching
from kinverify.filemode.align.result import Alignment, JointMap
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.filemode.read.model import ModelDesc
from kinverify.filemode.read.precision import Floors, Precision
from kinverify.model.transforms import invert_transform


@dataclass
class FileModeInfo:
    u: ModelDesc
    m: ModelDesc
    matching: Matching
    alignment: Alignment
    floors: Floors = field(default_factory=Floors)
    precision: tuple[Precision, Precision] = (Precision("URDF"), Precision("MJCF"))
    floating: bool = False  # a free base (its body's inertia is compared, not welded to the world)
    poses_u: dict[str, np.ndarray] = field(default_factory=dict)  # URDF frames at the aligned zero
    poses_m: dict[str, np.ndarray] = field(default_factory=dict)  # MJCF frames there, in the URDF's world
    user_tolerances: frozenset = frozenset()  # properties set with --tolerance: no floor applies
    file_mode: bool = True
    notes: list[str] = field(default_factory=list)
    inertials_explained_by: str = ""  # a finding that explains every inertial difference (a length unit)
    inertial_results: list = field(default_factory=list)  # the rigid bodies compared (set by the inertia suite)
    mjcf_angle: str = "radian"  # the MJCF's <compiler angle>
    base_coordinates: bool = False  # both files float: the base pose leads the compared coordinates

    @property
    def joint_pairs(self) -> list[tuple[str, str]]:
        return [(a, b) for a, b, _ in self.matching.joints]

    @property
    def frame_pairs(self) -> list[tuple[str, str]]:
        return [(a, b) for a, b, _ in self.matching.frames]

    def tol(self, frame: str) -> tuple[float, float]:
        """(position m, rotation rad) two readings of ``frame`` may differ by: double precision
        at its distance from the origin, plus twice the floor of the written precision."""
        pos, rot = self.floors.frame(frame)
        pose = self.poses_u.get(frame)
        scale = max(1.0, float(np.abs(pose[:3, 3]).max())) if pose is not None else 1.0
        return 1e-9 * scale + 2 * pos, 1e-9 + 2 * rot

    def floor(self, prop: str, value: float) -> float:
        """``value`` (a floor) unless the user set this property's tolerance."""
        return 0.0 if prop in self.user_tolerances else value

    @classmethod
    def from_sources(cls, sources) -> "FileModeInfo":
        """Spec mode: the generated URDF and MJCF, same joint and frame names, no alignment."""
        u, m = describe_urdf(sources.urdf), describe_mjcf(sources.mjcf)
        names = [n for n in sources.joint_names if u.has_joint(n) and m.has_joint(n)]
        joints = [(n, n, "name") for n in names]
        frames = [(f, f, "name") for f in u.frames if f in m.frames]
        matching = Matching(joints, [], [], frames)
        alignment = Alignment(np.eye(4), [JointMap(n, n, u.joint(n).type) for n in names], {}, names)
        return cls(u, m, matching, alignment, poses_u=dict(u.frames), poses_m=dict(m.frames), file_mode=False)


def file_view(ctx) -> "FileModeInfo | None":
    """File mode's view for a suite: the one file mode passed, or the generated files' in spec
    mode; None when the sources lack a URDF or an MJCF."""
    info = ctx.options.extra.get("filemode")
    if info is None and ctx.sources.urdf and ctx.sources.mjcf:
        info = FileModeInfo.from_sources(ctx.sources)
    return info


def aligned_poses(alignment: Alignment, poses_m: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """MJCF frame poses brought into the URDF's world."""
    tinv = invert_transform(alignment.T)
    return {name: tinv @ pose for name, pose in poses_m.items()}
