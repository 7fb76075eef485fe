"""Frozen dataclasses describing a serial arm, validated on construction.

Units: metres, radians, kilograms, kg·m². Every joint's child link frame sits at the joint
origin (URDF convention): ``T_parent_from_child(q) = T_origin · motion(axis, q)``.
Validation errors are :class:`~kinverify.errors.SpecError` carrying a field path
(``joints[2].axis``); :mod:`kinverify.specfile` adds the file name.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from kinverify.errors import SpecError
from kinverify.model.floating import BASE_COORDINATES, BASE_REVOLUTE, base_limits
from kinverify.model.transforms import xyz_rpy_to_transform

JOINT_TYPES = ("revolute", "prismatic")
SHAPES = ("capsule", "cylinder", "sphere", "box")
NAME_PATTERN = re.compile(r"^[A-Za-z_][A-Za-z0-9_.\-]{0,63}$")
RESERVED_NAMES = ("world", "universe", "world_mount", "floating_base")  # used by the generated URDF/MJCF
MAX_ABS = 1e6  # bound on any number in a spec: larger values are typos or fuzz, not arms


def _vector(value, n: int, field_name: str) -> tuple[float, ...]:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise SpecError(field_name, f"expected {n} numbers, got {value!r}") from None
    if arr.shape != (n,):
        raise SpecError(field_name, f"expected {n} numbers, got {value!r}")
    if not np.all(np.isfinite(arr)) or np.any(np.abs(arr) > MAX_ABS):
        raise SpecError(field_name, f"numbers must be finite and within ±{MAX_ABS:g}, got {value!r}")
    return tuple(float(x) for x in arr)


def check_scalar(value, field_name: str, *, positive: bool = False, nonnegative: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
        raise SpecError(field_name, f"expected a number, got {value!r}")
    x = float(value)
    if not math.isfinite(x) or abs(x) > MAX_ABS:
        raise SpecError(field_name, f"must be finite and within ±{MAX_ABS:g}, got {value!r}")
    if positive and x <= 0:
        raise SpecError(field_name, f"must be positive, got {x:g}")
    if nonnegative and x < 0:
        raise SpecError(field_name, f"must not be negative, got {x:g}")
    return x


def _name(value, field_name: str) -> str:
    if not isinstance(value, str) or not NAME_PATTERN.match(value):
        raise SpecError(field_name, f"must be a name of letters, digits, '_', '-', '.' (got {value!r})")
    return value


@dataclass(frozen=True)
class Origin:
    """Placement of a child frame in its parent: translation ``xyz`` [m], fixed-axis ``rpy`` [rad]."""

    xyz: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "xyz", _vector(self.xyz, 3, "xyz"))
        object.__setattr__(self, "rpy", _vector(self.rpy, 3, "rpy"))

    @property
    def transform(self) -> np.ndarray:
        """``T_parent_from_child`` (4, 4)."""
        return xyz_rpy_to_transform(self.xyz, self.rpy)


@dataclass(frozen=True)
class Geometry:
    """Visual/collision shape in its link frame.

    capsule/cylinder: ``radius`` and segment ``fromto`` (x1 y1 z1 x2 y2 z2) [m];
    sphere: ``radius`` at ``pos``; box: full edge lengths ``size`` centred at ``pos``.
    """

    shape: str
    radius: float = 0.0
    fromto: tuple[float, ...] | None = None
    size: tuple[float, float, float] | None = None
    pos: tuple[float, float, float] = (0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        if self.shape not in SHAPES:
            raise SpecError("shape", f"unknown shape {self.shape!r}; expected one of {', '.join(SHAPES)}")
        object.__setattr__(self, "pos", _vector(self.pos, 3, "pos"))
        if self.shape == "box":
            size = _vector(self.size, 3, "size")
            if min(size) <= 0:
                raise SpecError("size", f"box edges must be positive, got {size}")
            object.__setattr__(self, "size", size)
            return
        object.__setattr__(self, "radius", check_scalar(self.radius, "radius", positive=True))
        if self.shape in ("capsule", "cylinder"):
            fromto = _vector(self.fromto, 6, "fromto")
            if np.linalg.norm(np.subtract(fromto[3:], fromto[:3])) < 1e-9:
                raise SpecError("fromto", f"{self.shape} needs two distinct end points")
            object.__setattr__(self, "fromto", fromto)

    @property
    def length(self) -> float:
        """Segment length [m] of a capsule/cylinder (0 for other shapes)."""
        if self.fromto is None:
            return 0.0
        return float(np.linalg.norm(np.subtract(self.fromto[3:], self.fromto[:3])))


@dataclass(frozen=True)
class Inertial:
    """Mass [kg], centre of mass ``com`` [m] in the link frame, and the inertia tensor about the
    centre of mass in link-frame axes, ``inertia = (ixx, iyy, izz, ixy, ixz, iyz)`` [kg·m²]."""

    mass: float
    com: tuple[float, float, float] = (0.0, 0.0, 0.0)
    inertia: tuple[float, float, float, float, float, float] = (1e-4, 1e-4, 1e-4, 0.0, 0.0, 0.0)

    def __post_init__(self) -> None:
        object.__setattr__(self, "mass", check_scalar(self.mass, "mass", positive=True))
        object.__setattr__(self, "com", _vector(self.com, 3, "com"))
        inertia = _vector(self.inertia, 6, "inertia")
        object.__setattr__(self, "inertia", inertia)
        eig = np.linalg.eigvalsh(self.matrix)
        if eig[0] <= 0:
            raise SpecError("inertia", f"must be positive definite (eigenvalues {np.round(eig, 12).tolist()})")
        if eig[0] + eig[1] < eig[2] * (1 - 1e-9):
            raise SpecError("inertia", "principal moments violate the triangle inequality A + B >= C")

    @property
    def matrix(self) -> np.ndarray:
        ixx, iyy, izz, ixy, ixz, iyz = self.inertia
        return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])


@dataclass(frozen=True)
class Link:
    name: str
    inertial: Inertial
    geometry: Geometry | None = None

    def __post_init__(self) -> None:
        _name(self.name, "name")


@dataclass(frozen=True)
class Limits:
    """Joint range [rad or m], speed [rad/s or m/s] and effort [N·m or N] limits."""

    lower: float
    upper: float
    velocity: float = 3.0
    effort: float = 100.0

    def __post_init__(self) -> None:
        lower, upper = check_scalar(self.lower, "lower"), check_scalar(self.upper, "upper")
        if lower >= upper:
            raise SpecError("lower", f"lower limit {lower:g} must be below upper limit {upper:g}")
        object.__setattr__(self, "lower", lower)
        object.__setattr__(self, "upper", upper)
        object.__setattr__(self, "velocity", check_scalar(self.velocity, "velocity", positive=True))
        object.__setattr__(self, "effort", check_scalar(self.effort, "effort", positive=True))


@dataclass(frozen=True)
class Joint:
    """A 1-DOF joint and the link it moves. ``axis`` is in the joint (= child link) frame and is
    normalised on construction. ``damping`` [N·m·s/rad], ``friction`` (Coulomb, N·m) and
    ``armature`` (rotor inertia, kg·m²) are joint-space parameters. ``parent``: the link the
    joint hangs from (``None``: the previous joint's link, or the base for the first joint), so
    joints can form a tree (two fingers on one hand, two arms on one torso)."""

    name: str
    type: str
    origin: Origin
    axis: tuple[float, float, float]
    limits: Limits
    link: Link
    damping: float = 0.0
    friction: float = 0.0
    armature: float = 0.0
    parent: str | None = None

    def __post_init__(self) -> None:
        _name(self.name, "name")
        if self.parent is not None:
            _name(self.parent, "parent")
        if self.type not in JOINT_TYPES:
            raise SpecError("type", f"unknown joint type {self.type!r}; expected one of {', '.join(JOINT_TYPES)}")
        axis = np.asarray(_vector(self.axis, 3, "axis"))
        norm = float(np.linalg.norm(axis))
        if norm < 1e-9:
            raise SpecError("axis", "axis must be non-zero")
        object.__setattr__(self, "axis", tuple(float(x) for x in axis / norm))
        for attr in ("damping", "friction", "armature"):
            object.__setattr__(self, attr, check_scalar(getattr(self, attr), attr, nonnegative=True))


@dataclass(frozen=True)
class Tool:
    """A named frame rigidly attached to link ``parent`` (the end effector, a flange, ...)."""

    name: str
    parent: str
    origin: Origin = field(default_factory=Origin)

    def __post_init__(self) -> None:
        _name(self.name, "name")


@dataclass(frozen=True)
class DHRow:
    """One Denavit-Hartenberg row: ``a`` [m], ``alpha`` [rad], ``d`` [m], ``theta`` [rad]
    (``theta`` is the revolute joint's zero offset; ``d`` the prismatic one's)."""

    a: float
    alpha: float
    d: float
    theta: float


@dataclass(frozen=True)
class DHTable:
    """``convention`` is ``standard`` (Rz θ·Tz d·Tx a·Rx α) or ``modified`` (Rx α·Tx a·Rz θ·Tz d,
    Craig). ``rows[i]`` belongs to ``joints[i]``."""

    convention: str
    rows: tuple[DHRow, ...]


@dataclass(frozen=True)
class ArmSpec:
    """An arm: a fixed base link placed in the world, then joints in order (each hanging from the
    base or from an earlier joint's link: a serial chain or a tree), then tools.

    Frame names (``frame_names``): the base link, every joint's link, every tool.
    """

    name: str
    base_origin: Origin
    base_link: Link
    joints: tuple[Joint, ...]
    tools: tuple[Tool, ...] = ()
    dh: DHTable | None = None
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)
    floating: bool = False  # the base moves freely: its pose is part of the configuration

    def __post_init__(self) -> None:
        _name(self.name, "name")
        if not isinstance(self.floating, bool):
            raise SpecError("base.floating", f"expected true or false, got {self.floating!r}")
        object.__setattr__(self, "joints", tuple(self.joints))
        object.__setattr__(self, "tools", tuple(self.tools))
        object.__setattr__(self, "gravity", _vector(self.gravity, 3, "gravity"))
        if not self.joints:
            raise SpecError("joints", "an arm needs at least one joint")
        seen: dict[str, str] = {}
        names = [("base.link.name", self.base_link.name)]
        names += [(f"joints[{i}].name", j.name) for i, j in enumerate(self.joints)]
        names += [(f"joints[{i}].link.name", j.link.name) for i, j in enumerate(self.joints)]
        names += [(f"tools[{i}].name", t.name) for i, t in enumerate(self.tools)]
        names += [(f"tools[{i}].name", f"{t.name}_mount") for i, t in enumerate(self.tools)]
        for path, name in names:
            if name in RESERVED_NAMES:
                raise SpecError(path, f"name {name!r} is reserved ({', '.join(RESERVED_NAMES)})")
        for path, name in names:
            if name in seen:
                raise SpecError(path, f"duplicate name {name!r} (also used by {seen[name]})")
            seen[name] = path
        links = self.link_names
        for i, joint in enumerate(self.joints):
            if joint.parent is not None and joint.parent not in links[: i + 1]:
                where = "a later joint's link" if joint.parent in links else "unknown link"
                raise SpecError(
                    f"joints[{i}].parent",
                    f"{where} {joint.parent!r}: a joint hangs from the base or an "
                    f"earlier joint's link ({', '.join(links[: i + 1])})",
                )
        if self.dh is not None and not self.is_serial:
            raise SpecError("dh", "a DH table describes a serial chain: joints with a parent are not allowed")
        for i, tool in enumerate(self.tools):
            if tool.parent not in links:
                raise SpecError(f"tools[{i}].parent", f"unknown link {tool.parent!r}; available links: {', '.join(links)}")
        if self.dh is not None and len(self.dh.rows) != len(self.joints):
            raise SpecError("dh", "the DH table needs one row per joint")

    @property
    def dof(self) -> int:
        return len(self.joints)

    @property
    def joint_names(self) -> tuple[str, ...]:
        return tuple(j.name for j in self.joints)

    @property
    def link_names(self) -> tuple[str, ...]:
        return (self.base_link.name,) + tuple(j.link.name for j in self.joints)

    @property
    def tool_names(self) -> tuple[str, ...]:
        return tuple(t.name for t in self.tools)

    @property
    def frame_names(self) -> tuple[str, ...]:
        """Frames compared by kinverify, in chain order: links, then tools."""
        return self.link_names + self.tool_names

    @property
    def lower(self) -> np.ndarray:
        """Lower joint limits (n,) [rad or m], read-only."""
        return _readonly([j.limits.lower for j in self.joints])

    @property
    def upper(self) -> np.ndarray:
        return _readonly([j.limits.upper for j in self.joints])

    def link_index(self, name: str) -> int:
        """0 for the base link, i + 1 for ``joints[i].link``."""
        return self.link_names.index(name)

    @property
    def coordinate_names(self) -> tuple[str, ...]:
        """The configuration's coordinates: the joints, after the six base coordinates when floating
        (:mod:`kinverify.model.floating`)."""
        return (BASE_COORDINATES if self.floating else ()) + self.joint_names

    @property
    def nq(self) -> int:
        """Number of configuration coordinates (``dof``, plus 6 with a floating base)."""
        return len(self.coordinate_names)

    @property
    def coordinate_limits(self) -> tuple[np.ndarray, np.ndarray]:
        """Sampling ranges of every coordinate: the joint limits, after the base's (home ± 1 m,
        every orientation) when floating."""
        if not self.floating:
            return self.lower, self.upper
        lo, up = base_limits(self.base_origin.xyz)
        return _readonly(np.concatenate([lo, self.lower])), _readonly(np.concatenate([up, self.upper]))

    @property
    def coordinate_revolute(self) -> tuple[bool, ...]:
        return (BASE_REVOLUTE if self.floating else ()) + tuple(j.type == "revolute" for j in self.joints)

    def home(self) -> np.ndarray:
        """The home configuration ``(nq,)``: every joint at 0, a floating base at its origin."""
        joints = np.zeros(self.dof)
        if not self.floating:
            return joints
        return np.concatenate([self.base_origin.xyz, self.base_origin.rpy, joints])

    @property
    def parent_indices(self) -> tuple[int, ...]:
        """For each joint, the index of the link it hangs from (0 = base, i + 1 = ``joints[i].link``)."""
        names = self.link_names
        return tuple(i if j.parent is None else names.index(j.parent) for i, j in enumerate(self.joints))

    @property
    def is_serial(self) -> bool:
        return all(p == i for i, p in enumerate(self.parent_indices))

    def ancestors(self) -> np.ndarray:
        """``(n + 1, n)`` bool: ``[k, i]`` is True when joint ``i`` moves link ``k`` (is on the path
        from the base to it)."""
        parents = self.parent_indices
        out = np.zeros((self.dof + 1, self.dof), dtype=bool)
        for i, p in enumerate(parents):
            out[i + 1] = out[p]
            out[i + 1, i] = True
        return out


def _readonly(values) -> np.ndarray:
    arr = np.array(values, dtype=float)
    arr.setflags(write=False)
    return arr
