"""Drake's reading of a model file: a finalized ``MultibodyPlant`` (see :mod:`kinverify.backends.drake_`
for the conventions), its parser's warnings, and the frames, joints and free base kinverify
compares. Shared by the backend and by Drake's dynamics model."""

from __future__ import annotations

import logging
import re
from contextlib import contextmanager

import mujoco
import numpy as np
from pydrake.common.eigen_geometry import Quaternion
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import BodyIndex, FixedOffsetFrame, FrameIndex

from kinverify.errors import BackendError, UnknownNameError
from kinverify.io.isolate import LibraryDied, survives, usable_cwd
from kinverify.model.floating import base_transforms, rate_matrices
from kinverify.model.transforms import matrix_to_quat

FORMATS = {"urdf": "urdf", "sdf": "sdf", "mjcf": "xml"}  # kinverify's source -> Drake's file type
UNSUPPORTED = re.compile(r"[Tt]he (tag|attribute) '([^']+)' found (?:in an? |as a child of )'([^']+)'")


@contextmanager
def captured_warnings(out: list[str]):
    """Drake's parser warnings (through Python's ``drake`` logger) collected in ``out``, not printed."""
    logger = logging.getLogger("drake")

    class Keep(logging.Handler):
        def emit(self, record):
            out.append(record.getMessage())

    handler, propagate = Keep(logging.WARNING), logger.propagate
    logger.addHandler(handler)
    logger.propagate = False
    try:
        yield out
    finally:
        logger.removeHandler(handler)
        logger.propagate = propagate


def refused_elements(warnings) -> list[str]:
    """``<tag>`` / ``tag@attribute`` names of what Drake's parser said it ignores, once each."""
    found = []
    for text in warnings:
        m = UNSUPPORTED.search(text)
        if m:
            item = f"<{m.group(2)}> in <{m.group(3)}>" if m.group(1) == "tag" else f"{m.group(3)}@{m.group(2)}"
            found.append(item)
    return list(dict.fromkeys(found))


def load_plant(text: str, source: str, floating: bool = False, name: str = "drake") -> tuple:
    """``(plant, model instances, parser warnings)``: Drake's reading of ``text`` (``source`` "urdf",
    "sdf" or "mjcf"), finalized. Root bodies are welded to the world unless ``floating``."""
    try:  # Drake can end the process (e.g. on an MJCF's <inertial mass="0">): each file is tried in a child first
        survives(("drake", source, floating, text), lambda: _build(text, source, floating, name) and None)
    except LibraryDied as err:
        raise BackendError(name, f"Drake's {source.upper()} parser {err.reason}: the file is not read by Drake") from None
    return _build(text, source, floating, name)


def _build(text: str, source: str, floating: bool, name: str) -> tuple:
    plant, instances, warnings = _parse(text, source, name)
    children = {plant.get_joint(j).child_body().index() for j in plant.GetJointIndices()}
    roots = [
        plant.get_body(b)
        for m in instances
        for b in plant.GetBodyIndices(m)
        if b not in children and b != plant.world_body().index()
    ]
    if not floating:
        for body in roots:
            plant.WeldFrames(plant.world_frame(), body.body_frame(), RigidTransform())
    if source == "mjcf":
        _add_sites(plant, text, name)
    plant.Finalize()
    return plant, instances, warnings


def _parse(text: str, source: str, name: str = "drake") -> tuple:
    """``(plant, model instances, parser warnings)``: the plant Drake's parser makes of ``text``, not finalized."""
    plant = MultibodyPlant(0.0)
    warnings: list[str] = []
    try:
        with captured_warnings(warnings), usable_cwd():
            instances = Parser(plant).AddModelsFromString(text, FORMATS[source])
    except (RuntimeError, ValueError) as err:
        raise BackendError(name, f"cannot load the {source.upper()}: {first_line(err)}") from None
    return plant, instances, warnings


def _add_sites(plant, mjcf_text: str, name: str) -> None:
    """Each MJCF site as a frame on its body, at MuJoCo's compiled offset (Drake ignores sites)."""
    try:
        m = mujoco.MjModel.from_xml_string(mjcf_text)
    except ValueError:
        return  # MuJoCo refuses the file: no sites to add; Drake's own reading stands
    for s in range(m.nsite):
        site, body = m.site(s).name, m.body(m.site_bodyid[s]).name
        if not site or plant.HasFrameNamed(site) or not body:
            continue
        parent = plant.world_frame() if m.site_bodyid[s] == 0 else _body_frame(plant, body)
        if parent is None:
            continue
        pose = RigidTransform(
            RotationMatrix(Quaternion(np.asarray(m.site_quat[s], dtype=float))), np.asarray(m.site_pos[s], dtype=float)
        )
        plant.AddFrame(FixedOffsetFrame(site, parent, pose))


def _body_frame(plant, name: str):
    bodies = [plant.get_body(BodyIndex(b)) for b in range(plant.num_bodies()) if plant.get_body(BodyIndex(b)).name() == name]
    return bodies[0].body_frame() if len(bodies) == 1 else None


def frame_named(plant, name: str):
    """The frame ``name`` (a body's own frame first); :class:`UnknownNameError` when none."""
    if name == "world":
        return plant.world_frame()
    body = _body_frame(plant, name)
    if body is not None:
        return body
    frames = [plant.get_frame(FrameIndex(f)) for f in range(plant.num_frames()) if plant.get_frame(FrameIndex(f)).name() == name]
    if frames:
        return frames[0]
    names = [plant.get_body(BodyIndex(b)).name() for b in range(plant.num_bodies())]
    names += [plant.get_frame(FrameIndex(f)).name() for f in range(plant.num_frames())]
    raise UnknownNameError("frame", name, list(dict.fromkeys(names)))


def one_dof_joint(plant, name: str, backend: str):
    joints = [plant.get_joint(j) for j in plant.GetJointIndices() if plant.get_joint(j).name() == name]
    if not joints:
        movable = [plant.get_joint(j).name() for j in plant.GetJointIndices() if plant.get_joint(j).num_positions() > 0]
        raise UnknownNameError("joint", name, movable)
    joint = joints[0]
    if joint.num_positions() != 1 or joint.num_velocities() != 1:
        raise BackendError(backend, f"joint {name!r} has {joint.num_positions()} coordinates; only 1-DOF joints are compared")
    return joint


def floating_joint(plant, backend: str):
    """The free base's ``QuaternionFloatingJoint`` (between the world and the base body's frame)."""
    free = [
        plant.get_joint(j)
        for j in plant.GetJointIndices()
        if plant.get_joint(j).type_name() == "quaternion_floating" and plant.get_joint(j).parent_body().index() == 0
    ]
    if len(free) != 1:
        raise BackendError(
            backend, f"the configuration has a floating base but Drake's model has {len(free)} free bodies (expected one)"
        )
    joint = free[0]
    if (
        joint.frame_on_parent().index() != plant.world_frame().index()
        or joint.frame_on_child().index() != joint.child_body().body_frame().index()
    ):
        raise BackendError(backend, "the free body's floating joint is not between the world and the body's own frame")
    return joint


def base_velocity_map(b) -> np.ndarray:
    """``S`` ``(N, 6, 6)``: Drake's free-body velocity ``[ω_world; v_world]`` = ``S @`` our base rates."""
    b = np.atleast_2d(np.asarray(b, dtype=float))
    out = np.zeros(b.shape[:-1] + (6, 6))
    out[..., :3, 3:] = rate_matrices(b)
    out[..., 3:, :3] = np.eye(3)
    return out


def base_positions(b) -> np.ndarray:
    """Drake's free-body positions ``(N, 7)`` ``[qw qx qy qz, x y z]`` for our base coordinates ``(N, 6)``."""
    t = base_transforms(np.atleast_2d(b))
    return np.concatenate([matrix_to_quat(t[:, :3, :3]), t[:, :3, 3]], axis=1)


def first_line(err: Exception) -> str:
    lines = [line for line in str(err).strip().splitlines() if line.strip()]
    return lines[0] if lines else type(err).__name__
