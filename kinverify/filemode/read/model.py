"""The neutral description of a loaded model, the same for both files (read by
:mod:`~kinverify.filemode.read.describe_urdf` and :mod:`~kinverify.filemode.read.describe_mjcf`;
``q = 0`` is every joint's zero, MuJoCo ``qpos = 0``, not ``qpos0``: a ``ref`` is a zero offset): movable joints in chain order with their world axis lines at
q = 0, limits, joint dynamics, couplings and actuator force bounds; frames with their world poses
at q = 0; each body's inertial in its own frame and in the world at q = 0."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

INF = math.inf


@dataclass
class JointDesc:
    name: str
    type: str  # "revolute" or "prismatic"
    parent: str | None  # nearest movable ancestor joint (None: on the fixed base)
    child: str  # frame that moves with the joint (URDF child link / MJCF body)
    parent_frame: str  # frame the joint hangs from (URDF parent link / MJCF parent body)
    axis: np.ndarray  # unit direction, world, q = 0
    anchor: np.ndarray  # a point on the axis, world, q = 0
    lower: float  # -inf / inf: unlimited
    upper: float
    damping: float | None = None
    friction: float | None = None
    armature: float | None = None  # None: the format cannot express it
    stiffness: float | None = None  # a joint spring [N·m/rad or N/m] (MJCF stiffness); None: the format cannot express it
    effort: float | None = None  # None: not stated; inf: actuators without a force bound
    velocity: float | None = None  # None: the format cannot express it
    effort_how: str = ""  # where the effort comes from (URDF <limit>, MJCF actuators)
    effort_each: tuple[tuple[float, str], ...] = ()  # several actuators on the joint (MJCF): each one's (bound, how)
    stated: frozenset[str] | None = None  # which of read.stated.JOINT_VALUES the file states (None: all)


@dataclass
class BodyInertial:
    owner: str | None  # movable joint the body moves with (None: fixed base)
    mass: float
    com: np.ndarray  # world, q = 0
    inertia: np.ndarray  # 3x3 about the CoM, world axes, q = 0
    name: str = ""  # URDF link / MJCF body; also the name of its frame
    com_local: np.ndarray = field(default_factory=lambda: np.zeros(3))  # in the body's frame
    inertia_local: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))  # about the CoM, body axes
    snapped: float = 0.0  # MuJoCo: angle [rad] of principal axes it aligned with the body frame (body_sameframe)
    mass_known: bool = True  # False: part of its mass came from a mesh file that is absent
    com_known: bool = True  # False: a mesh that is absent stated its mass; where it sits is not known
    snapped_com: float = 0.0  # MuJoCo: distance [m] of the stated centre of mass its run time puts at the body origin


@dataclass(frozen=True)
class Coupling:
    """``follower = multiplier * leader + offset`` (radians or metres)."""

    follower: str
    leader: str
    multiplier: float
    offset: float
    source: str  # "<mimic>" or "<equality joint>"
    nonlinear: bool = False  # MJCF polycoef terms beyond the linear one (not compared)


@dataclass
class ModelDesc:
    kind: str  # "urdf", "mjcf", "sdf" or "usd"
    library: str
    joints: list[JointDesc]
    frames: dict[str, np.ndarray]  # name -> world pose at q = 0
    frame_owner: dict[str, str | None]  # name -> movable joint it moves with
    frame_depth: dict[str, int]
    bodies: list[BodyInertial]
    skipped: list[str] = field(default_factory=list)  # joints not compared, with the reason
    frame_kind: dict[str, str] = field(default_factory=dict)  # "link" (URDF link, MJCF body) or "site"
    couplings: list[Coupling] = field(default_factory=list)
    gravity: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -9.81]))
    extensions: dict[str, dict] = field(default_factory=dict)  # joint -> non-standard tags (drake rotor inertia)
    held: list[str] = field(default_factory=list)  # joints with several coordinates, held at neutral (not compared)
    no_inertial: set[str] = field(default_factory=set)  # links/bodies that state no inertial (massless by default)
    gravcomp: dict[str, float] = field(default_factory=dict)  # MJCF body -> share of its weight compensated (gravcomp)
    free_joint: dict[str, float] = field(default_factory=dict)  # MJCF free joints' armature, damping (read.files)
    native: object = None  # the reader's own model, where file mode needs more of it (USD: the articulation, for its precision)

    def joint(self, name: str) -> JointDesc:
        return next(j for j in self.joints if j.name == name)

    def has_joint(self, name: str) -> bool:
        return any(j.name == name for j in self.joints)

    @property
    def total_mass(self) -> float:
        return float(sum(b.mass for b in self.bodies))

    def body(self, name: str) -> BodyInertial | None:
        return next((b for b in self.bodies if b.name == name), None)


def inertial_world(pose: np.ndarray, com_local, inertia_local) -> tuple[np.ndarray, np.ndarray]:
    rot = pose[:3, :3]
    return rot @ np.asarray(com_local) + pose[:3, 3], rot @ inertia_local @ rot.T
