"""The model texts every backend is built from."""

from __future__ import annotations

from dataclasses import dataclass

from kinverify.generate import generate_mjcf, generate_sdf, generate_urdf
from kinverify.model.spec import ArmSpec


@dataclass(frozen=True)
class ModelSources:
    """A model as the backends read it: optional spec, URDF, MJCF and SDFormat texts, the coordinates and
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
    usd: str | None = None  # a USD file's path (its layers resolve from there) or usda text
    # File mode: the USD file's own names (None: same as the URDF's).
    usd_joint_names: tuple[str, ...] | None = None
    usd_frames: tuple[str, ...] | None = None

    @classmethod
    def from_spec(cls, spec: ArmSpec) -> "ModelSources":
        lower, upper = spec.coordinate_limits
        return cls(spec.name, spec.coordinate_names, spec.frame_names, tuple(lower), tuple(upper),
                   spec.coordinate_revolute, spec, generate_urdf(spec), generate_mjcf(spec), sdf=generate_sdf(spec))
