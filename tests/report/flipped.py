"""A model that disagrees for a known reason: the generated URDF with one joint's axis negated,
loaded by the real Pinocchio as one more backend."""

from __future__ import annotations

import re

from kinverify.backends import ModelSources
from kinverify.backends.pinocchio_ import PinocchioBackend

FLIPPED = "flipped-urdf"


def flipped_backend(sources: ModelSources, joint: str) -> PinocchioBackend:
    """The generated URDF with ``joint``'s axis negated, loaded by the real Pinocchio."""
    pattern = re.compile(rf'(<joint name="{joint}".*?<axis xyz=")([^"]*)(")', re.S)
    axis = [float(v) for v in pattern.search(sources.urdf).group(2).split()]
    urdf = pattern.sub(lambda m: m.group(1) + " ".join(str(-v + 0.0) for v in axis) + m.group(3), sources.urdf, count=1)
    assert urdf != sources.urdf
    return PinocchioBackend.from_urdf(urdf, sources.joint_names, sources.frames, name=FLIPPED)
