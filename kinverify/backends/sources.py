"""The model texts every backend is built from."""

from __future__ import annotations

from dataclasses import dataclass

from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.spec import ArmSpec


@dataclass(frozen=True)
class ModelSources:
    """A model as the backends read it: optional spec, URDF text, MJCF text, the joints and frames
    to compare (kinverify's joint order), and the joint limits [rad, m] samples are drawn in."""

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

    @classmethod
    def from_spec(cls, spec: ArmSpec) -> "ModelSources":
        return cls(spec.name, spec.joint_names, spec.frame_names, tuple(spec.lower), tuple(spec.upper),
                   tuple(j.type == "revolute" for j in spec.joints), spec, generate_urdf(spec), generate_mjcf(spec))
