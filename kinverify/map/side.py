"""What one file (or an actuator table) says about the contract a policy depends on: the order
its simulator gives the joints and the actuators, and per joint the values a policy is trained
with, every one in SI units per radian (N·m/rad, N·m·s/rad, rad/s, rad; metres for a prismatic
joint).

A :class:`Side` is what every reader (:mod:`kinverify.map.readers`) returns; the comparison, the
maps and the report read sides only, never a library's model."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from kinverify.filemode.read.model import ModelDesc


@dataclass(frozen=True)
class Value:
    """One compared quantity: ``name`` (a :class:`MapJoint` field), how the report names it, its
    unit for a revolute joint and for a prismatic one, and ``scale``: how it converts from per
    degree to per radian (stiffness k/deg = k·180/π per rad: ``+1``; a velocity in deg/s is
    ×π/180: ``-1``; a torque or an inertia does not convert: ``0``)."""

    name: str
    label: str
    unit_revolute: str
    unit_prismatic: str
    scale: int
    absolute: bool = False  # compared by absolute difference (positions), else relative

    def unit(self, joint_type: str) -> str:
        return self.unit_prismatic if joint_type == "prismatic" else self.unit_revolute


VALUES = (
    Value("default", "default position", "rad", "m", -1, absolute=True),
    Value("stiffness", "PD stiffness (kp)", "N·m/rad", "N/m", 1),
    Value("damping", "PD damping (kd)", "N·m·s/rad", "N·s/m", 1),
    Value("effort", "effort limit", "N·m", "N", 0),
    Value("velocity", "velocity limit", "rad/s", "m/s", -1),
    Value("armature", "armature", "kg·m²", "kg", 0),
    Value("friction", "friction (frictionloss)", "N·m", "N", 0),
    Value("joint_damping", "joint damping (passive)", "N·m·s/rad", "N·s/m", 1),
)
VALUE_NAMES = tuple(v.name for v in VALUES)


def value(name: str) -> Value:
    return next(v for v in VALUES if v.name == name)


def to_radian(amount: float, name: str, joint_type: str) -> float:
    """``amount`` stated per degree (a position in degrees, a stiffness per degree...) in
    radians; a prismatic joint's values and unit-free quantities unchanged."""
    scale = value(name).scale
    if joint_type == "prismatic" or scale == 0:
        return amount
    return amount * (180.0 / math.pi) ** scale


@dataclass(frozen=True)
class Follows:
    """``joint = multiplier · leader + offset`` (URDF ``<mimic>``, an active MJCF ``<equality joint>``)."""

    leader: str
    multiplier: float
    offset: float
    source: str


@dataclass
class MapJoint:
    """A 1-DOF joint as its simulator sees it. ``qpos``/``dof``: its index in the simulator's
    position and velocity vectors (MuJoCo ``qpos``/``qvel``, Drake's positions/velocities), None
    where the format has no state vector. A value left None is not stated (see
    :attr:`Side.expresses`); ``how`` says where a stated value comes from."""

    name: str
    type: str  # "revolute" or "prismatic"
    qpos: int | None = None
    dof: int | None = None
    default: float | None = None
    stiffness: float | None = None
    damping: float | None = None
    effort: float | None = None
    velocity: float | None = None
    armature: float | None = None
    friction: float | None = None
    joint_damping: float | None = None
    driven: bool | None = None  # None: the format does not say (a URDF without transmissions)
    follows: Follows | None = None
    mode: str = ""  # how it is driven: "position", "velocity", "motor (torque)", "tendon <name>", ...
    how: dict[str, str] = field(default_factory=dict)
    apart: dict[str, str] = field(default_factory=dict)  # value -> why it is not compared (a motor's gains)


@dataclass(frozen=True)
class Actuator:
    """One actuator, in the simulator's actuator (control) order: the joints it acts on (one for
    a joint transmission, several through a tendon) and how (``kind``)."""

    name: str
    joints: tuple[str, ...]
    kind: str
    direct: bool = True  # acts on one joint through a joint transmission (not a tendon)


@dataclass
class Side:
    """One input: ``label`` (the file as given), its ``format``, the simulator whose order
    ``joints`` are in (``order``), its actuators in control order, the quantities its format can
    state (``expresses``; None elsewhere is *unset*), its joint couplings' own reading for
    matching (``desc``) and notes. An actuator table has no order of its own (``ordered`` False)."""

    label: str
    path: str
    format: str
    order: str
    joints: list[MapJoint]
    actuators: list[Actuator] | None  # None: the format states no actuators (URDF without transmissions)
    expresses: frozenset[str]
    desc: ModelDesc | None = None
    notes: list[str] = field(default_factory=list)
    ordered: bool = True
    silence: str = "unset"  # what a value it can state and does not means ("inherited": taken from the asset)

    def joint(self, name: str) -> MapJoint | None:
        return next((j for j in self.joints if j.name == name), None)

    @property
    def names(self) -> list[str]:
        return [j.name for j in self.joints]

    def state(self, name: str) -> str:
        """Why a value is absent: "unset" (the file could state it), "inherited" (an actuator table
        leaves it to the asset, as Isaac Lab does with a None) or "inexpressible"."""
        return self.silence if name in self.expresses else "inexpressible"
