"""The model texts every backend is built from."""

from __future__ import annotations

from dataclasses import dataclass

from kinverify.generate import generate_mjcf, generate_sdf, generate_urdf, generate_usd_if_available
from kinverify.generate.usd_names import prim_names
from kinverify.model.spec import ArmSpec


@dataclass(frozen=True)
class ModelSources:
    """A model as the backends read it: optional spec, URDF, MJCF, SDFormat and OpenUSD texts, the coordinates and
    frames to compare (kinverify's order) and the ranges [rad, m] samples are drawn in.

    ``joint_names`` are the configuration's coordinates: the joints, after the six base
    coordinates of :mod:`kinverify.model.floating` (``base:x`` ...) when the base floats."""

    name: str
    joint_names: tuple[str, ...]
    frames: tuple[str, ...]
    lower: tuple[float, ...]
    upper: tuple[float, ...]
    revolute: tuple[bool, ...]
    spec: ArmSpec | None = None
    urdf: str | None = None
    mjcf: str | None = None
    # File mode: the MJCF's own names for the same joints and frames (None: same as the URDF's).
    mjcf_joint_names: tuple[str, ...] | None = None
    mjcf_frames: tuple[str, ...] | None = None
    sdf: str | None = None
    # File mode: the SDFormat file's own names (None: same as the URDF's).
    sdf_joint_names: tuple[str, ...] | None = None
    sdf_frames: tuple[str, ...] | None = None
    usd: str | None = None  # usda text (from a spec, only when usd-core, the ``usd`` extra, imports) or a USD file's path
    # The USD's own prim names for the same joints and frames (None: same as the URDF's).
    usd_joint_names: tuple[str, ...] | None = None
    usd_frames: tuple[str, ...] | None = None

    @classmethod
    def from_spec(cls, spec: ArmSpec) -> "ModelSources":
        lower, upper = spec.coordinate_limits
        usd = generate_usd_if_available(spec)
        names = prim_names(spec) if usd is not None else {}
        joints = tuple(names.get(n, n) for n in spec.coordinate_names)  # the base's coordinates keep theirs
        frames = tuple(names.get(n, n) for n in spec.frame_names)
        return cls(
            spec.name,
            spec.coordinate_names,
            spec.frame_names,
            tuple(lower),
            tuple(upper),
            spec.coordinate_revolute,
            spec,
            generate_urdf(spec),
            generate_mjcf(spec),
            sdf=generate_sdf(spec),
            usd=usd,
            usd_joint_names=joints if joints != spec.coordinate_names else None,
            usd_frames=frames if frames != spec.frame_names else None,
        )
