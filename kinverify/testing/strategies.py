"""Public hypothesis strategies: random valid arm specs and configurations inside their limits.

    from hypothesis import given
    from kinverify.testing import strategies as kst

    @given(kst.arm_specs(max_joints=6), kst.data())
    def test_something(spec, data):
        q = data.draw(kst.configurations(spec))

Specs are built through :func:`kinverify.spec_from_dict`, so every drawn spec is one a user could
write as TOML (see :func:`spec_dicts`).

Planted changes (:mod:`kinverify.testing.planted`, :mod:`~kinverify.testing.rewrites` and
:mod:`~kinverify.testing.mjcf_pair`, re-exported here) property-test a pair of files:
:func:`planted_changes` draws an MJCF with one or two changes and what was planted,
:func:`equivalent_rewrites` one rewritten without changing the robot; :func:`mesh_free_urdf` and
:func:`mujoco_mjcf` make the pair to plant them in from a URDF.
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import strategies as st

from kinverify.model.specfile import spec_from_dict
from kinverify.model.spec import ArmSpec
from kinverify.testing.planted import KINDS as PLANTED_KINDS  # noqa: F401 (public, re-exported)
from kinverify.testing.mjcf_pair import mesh_free_urdf, mujoco_mjcf  # noqa: F401 (public, re-exported)
from kinverify.testing.planted import Planted, plantable_kinds, planted_changes  # noqa: F401
from kinverify.testing.rewrites import equivalent_rewrites  # noqa: F401

data = st.data

_AXES = [(1, 0, 0), (0, 1, 0), (0, 0, 1), (-1, 0, 0), (0, -1, 0), (0, 0, -1)]


def _floats(lo: float, hi: float) -> st.SearchStrategy[float]:
    return st.floats(lo, hi, allow_nan=False, allow_infinity=False, allow_subnormal=False)


def vectors(lo: float, hi: float) -> st.SearchStrategy[list[float]]:
    return st.lists(_floats(lo, hi), min_size=3, max_size=3)


TINY_AXIS = 1e-6  # Drake snaps an axis within ~1.8e-8 of a coordinate axis onto it (backends/quirks.py)


@st.composite
def axes(draw) -> list[float]:
    """Axis-aligned (either sign) or arbitrary non-zero directions; a component is 0 or at least
    1e-6 of the direction's length."""
    if draw(st.booleans()):
        return list(draw(st.sampled_from(_AXES)))
    v = draw(vectors(-1.0, 1.0).filter(lambda v: math.hypot(*v) > 0.1))
    norm = math.hypot(*v)
    return [0.0 if abs(c) < TINY_AXIS * norm else c for c in v]


TINY_ROTATION = 1e-6  # rad: yourdfpy can lose origin rotations of ~1e-8 (backends/quirks.py)


@st.composite
def angles_rpy(draw) -> list[float]:
    """Roll, pitch, yaw with special values (0, ±π/2, π); each angle is 0 or at least 1e-6 rad,
    and so is the rotation they make together (π, π, π − 5e-9 is a turn of 5e-9 rad)."""
    special = st.sampled_from([0.0, math.pi / 2, -math.pi / 2, math.pi])
    angles = [draw(st.one_of(special, _floats(-math.pi, math.pi))) for _ in range(3)]
    angles = [0.0 if abs(a) < TINY_ROTATION else a for a in angles]
    return [0.0, 0.0, 0.0] if _turn(angles) < TINY_ROTATION else angles


def _turn(rpy) -> float:
    """The angle [rad] of the rotation roll, pitch, yaw make together."""
    from kinverify.model.transforms import rotation_log, rpy_to_matrix

    return float(np.linalg.norm(rotation_log(rpy_to_matrix(rpy))))


# MuJoCo places a site within ~1e-6 m / 1e-6 rad of its body exactly at the body frame
# (backends/quirks.py); tool frames are sites, so tool offsets are zero or clear of that band.
SITE_SNAP = 1e-5


def tool_offsets() -> st.SearchStrategy[list[float]]:
    return vectors(-0.2, 0.2).map(lambda v: [0.0, 0.0, 0.0] if math.hypot(*v) < SITE_SNAP else v)


def tool_rotations() -> st.SearchStrategy[list[float]]:
    return angles_rpy().map(lambda v: [0.0, 0.0, 0.0] if max(abs(x) for x in v) < SITE_SNAP or _turn(v) < SITE_SNAP else v)


@st.composite
def _limits(draw, joint_type: str) -> dict:
    if joint_type == "prismatic":
        lower, upper = -draw(_floats(0.0, 0.3)), draw(_floats(0.01, 0.3))
        return {"lower": lower, "upper": upper, "unit": "m"}
    lower = -draw(_floats(0.0, 3.5))
    upper = draw(_floats(0.05, 3.5))
    return {"lower": lower, "upper": upper, "unit": "rad"}


@st.composite
def spec_dicts(
    draw, min_joints: int = 1, max_joints: int = 8, prismatic: bool = True, trees: bool = False, floating: bool = False
) -> dict:
    """The TOML structure of a random valid arm (1-8 joints by default): a serial chain, or with
    ``trees`` a tree in which each joint may hang from the base or any earlier joint's link; with
    ``floating``, the base floats in some of them (its pose then leads the configuration)."""
    n = draw(st.integers(min_joints, max_joints))
    joints = []
    for i in range(n):
        jtype = draw(st.sampled_from(["revolute", "revolute", "revolute", "prismatic"] if prismatic else ["revolute"]))
        joint = {
            "name": f"j{i + 1}",
            "type": jtype,
            "xyz": draw(st.one_of(st.just([0.0, 0.0, 0.0]), vectors(-0.3, 0.3))),
            "rpy": draw(angles_rpy()),
            "axis": draw(axes()),
            "limits": draw(_limits(jtype)),
            "link": {"name": f"l{i + 1}", "mass": draw(_floats(0.1, 5.0))},
        }
        if trees and i > 0 and draw(st.booleans()):
            joint["parent"] = draw(st.sampled_from(["base"] + [f"l{k}" for k in range(1, i + 1)]))
        joints.append(joint)
    tools = [{"name": "tool", "parent": f"l{n}", "xyz": draw(tool_offsets()), "rpy": draw(tool_rotations())}]
    if draw(st.booleans()):
        parent = draw(st.integers(1, n))
        tools.append({"name": "aux", "parent": f"l{parent}", "xyz": draw(tool_offsets())})
    return {
        "name": "random_arm",
        "base": {
            "xyz": draw(vectors(-0.5, 0.5)),
            "rpy": draw(angles_rpy()),
            "link": {"name": "base"},
            **({"floating": True} if floating and draw(st.booleans()) else {}),
        },
        "joints": joints,
        "tools": tools,
    }


def arm_specs(
    min_joints: int = 1, max_joints: int = 8, prismatic: bool = True, trees: bool = False, floating: bool = False
) -> st.SearchStrategy[ArmSpec]:
    """Random valid :class:`ArmSpec` (random joint types, axes, origins, limits, tools; with
    ``trees``, branching chains; with ``floating``, some with a floating base)."""
    return spec_dicts(min_joints, max_joints, prismatic, trees, floating).map(spec_from_dict)


def _edges(lo: float, hi: float, revolute: bool) -> list[float]:
    values = [lo, hi, 0.0] + ([math.pi / 2, -math.pi / 2] if revolute else [])
    return [v for v in values if lo <= v <= hi]


@st.composite
def configurations(draw, spec: ArmSpec, edge_probability: float = 0.3) -> np.ndarray:
    """One configuration ``(nq,)`` inside the ranges (a floating base's six coordinates first);
    each coordinate is an edge value (limit, zero, ±π/2 where inside) with probability
    ``edge_probability``, else uniform."""
    q = []
    lower, upper = spec.coordinate_limits
    for lo, hi, revolute in zip(lower, upper, spec.coordinate_revolute, strict=True):
        if draw(st.floats(0, 1)) < edge_probability:
            q.append(draw(st.sampled_from(_edges(float(lo), float(hi), revolute))))
        else:
            q.append(draw(_floats(float(lo), float(hi))))
    return np.array(q)


def configuration_batches(spec: ArmSpec, min_size: int = 1, max_size: int = 20) -> st.SearchStrategy[np.ndarray]:
    """A batch ``(N, n)`` of configurations inside the limits."""
    return st.lists(configurations(spec), min_size=min_size, max_size=max_size).map(np.array)


# --- reachable targets and perturbed specs -------------------------------------------


class ReachableTarget:
    """A pose that ``spec`` reaches: ``pose`` (4×4 ``T_world_from_frame``) of ``frame`` at ``q``."""

    def __init__(self, frame: str, q: np.ndarray, pose: np.ndarray) -> None:
        self.frame, self.q, self.pose = frame, q, pose

    @property
    def position(self) -> np.ndarray:
        return self.pose[:3, 3]

    def __repr__(self) -> str:
        return f"ReachableTarget(frame={self.frame!r}, q={self.q.tolist()!r}, position={self.position.tolist()!r})"


@st.composite
def reachable_targets(draw, spec: ArmSpec, frame: str | None = None, edge_probability: float = 0.3) -> ReachableTarget:
    """A target pose of ``frame`` (default: the last frame) that the arm reaches: the analytic
    FK of a configuration drawn by :func:`configurations` (kept as ``.q``, a known solution)."""
    from kinverify.model.kinematics import frame_poses

    frame = frame or spec.frame_names[-1]
    index = list(spec.frame_names).index(frame)
    q = draw(configurations(spec, edge_probability))
    return ReachableTarget(frame, q, frame_poses(spec, q)[0, index])


@st.composite
def perturbed_specs(draw, spec: ArmSpec, scale: float = 1e-3) -> ArmSpec:
    """``spec`` with one frame origin moved: one joint's (or tool's, or the base's) ``xyz`` by
    a vector of length in [scale/2, scale] [m], or its ``rpy`` by such an angle [rad]. Names,
    limits and inertias are kept, so baselines and diffs can be checked against the known change."""
    from dataclasses import replace

    from kinverify.model.spec import Origin

    owners = ["base"] + [f"joint:{i}" for i in range(spec.dof)] + [f"tool:{i}" for i in range(len(spec.tools))]
    owner = draw(st.sampled_from(owners))
    field_name = draw(st.sampled_from(["xyz", "rpy"]))
    direction = np.array(draw(vectors(-1.0, 1.0).filter(lambda v: math.hypot(*v) > 0.1)))
    size = draw(_floats(scale / 2, scale))
    step = direction / np.linalg.norm(direction) * size

    def moved(origin: Origin) -> Origin:
        if field_name == "xyz":
            return Origin(tuple(np.add(origin.xyz, step)), origin.rpy)
        return Origin(origin.xyz, tuple(np.add(origin.rpy, step)))

    kind, _, index = owner.partition(":")
    if kind == "base":
        return replace(spec, base_origin=moved(spec.base_origin))
    i = int(index)
    if kind == "joint":
        joints = list(spec.joints)
        joints[i] = replace(joints[i], origin=moved(joints[i].origin))
        return replace(spec, joints=tuple(joints))
    tools = list(spec.tools)
    tools[i] = replace(tools[i], origin=moved(tools[i].origin))
    return replace(spec, tools=tuple(tools))
