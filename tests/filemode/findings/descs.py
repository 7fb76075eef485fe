"""Small hand-made model descriptions for the findings' unit tests: a chain of joints whose values
the test states, so each decision of a finding can be met on the smallest input that tells it."""

from __future__ import annotations

import math

import numpy as np

from kinverify.filemode.align.match import Matching
from kinverify.filemode.align.result import Alignment, JointMap
from kinverify.filemode.read.model import Coupling, JointDesc, ModelDesc


def joint(name: str, parent: str | None = None, type: str = "revolute", lower: float = -1.0, upper: float = 2.0) -> JointDesc:
    """A joint about z at the origin, moving the frame ``<name>_link``."""
    return JointDesc(name, type, parent, f"{name}_link", "base", np.array([0.0, 0.0, 1.0]), np.zeros(3), lower, upper)


def desc(kind: str, joints: list[JointDesc], couplings: list[Coupling] = (), frames: dict | None = None) -> ModelDesc:
    """A model of ``joints``; ``frames``: frame -> world position (each joint's link at the origin
    unless given), each owned by the joint of the same link name."""
    poses = {j.child: np.eye(4) for j in joints}
    for name, xyz in (frames or {}).items():
        poses[name] = np.eye(4)
        poses[name][:3, 3] = xyz
    owner = {f: next((j.name for j in joints if j.child == f), None) for f in poses}
    return ModelDesc(kind, "test", joints, poses, owner, dict.fromkeys(poses, 0), [], couplings=list(couplings))


def matching(pairs: list[tuple[str, str]], how: str = "same name", frames=()) -> Matching:
    return Matching([(a, b, how) for a, b in pairs], [], [], list(frames))


def alignment(maps: list[JointMap], **kw) -> Alignment:
    return Alignment(kw.pop("T", np.eye(4)), maps, {}, [j.urdf for j in maps], **kw)


def couple(follower: str, leader: str, k: float = 1.0, c: float = 0.0, source: str = "<mimic>") -> Coupling:
    return Coupling(follower, leader, k, c, source)


INF = math.inf
