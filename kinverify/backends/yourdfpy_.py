"""yourdfpy on the generated URDF: FK only (its Jacobian here is by finite differences)."""

from __future__ import annotations

import io

import numpy as np
import yourdfpy

from kinverify.errors import BackendError, UnknownNameError, library_reason
from kinverify.model.floating import base_transforms, has_base
from kinverify.backends.base import BackendBase


STALE_BELOW = 1e-6  # rad or m: smaller joint changes may leave trimesh's transforms stale
_IDENTITY = np.eye(4)


class YourdfpyBackend(BackendBase):
    """Native convention: ``get_transform(frame_to, frame_from)`` returns the 4×4 pose of
    ``frame_to`` in ``frame_from``; with ``frame_from`` the root link (``world``) that is
    ``T_world_from_frame``, ours. yourdfpy takes a floating root joint for a 1-coordinate joint,
    so a floating base is held fixed at the identity there and its pose (the base coordinates
    of :mod:`kinverify.model.floating`) composed in front. Joints not in ``joint_names`` stay at 0.

    Poses are read one joint at a time (``get_transform(child, parent)``: the transform yourdfpy
    wrote for that joint) and chained from the root here, one product per link: asking trimesh
    for each frame from the root walks and multiplies the whole path again for every frame
    (quadratic in the chain's length, ~3× slower on a 7-joint arm)."""

    jacobian_method = "finite-difference"
    slow = True  # ~100x slower per configuration than the others: capped by VerifyOptions.slow_samples

    def __init__(self, robot: "yourdfpy.URDF", name: str, joint_names, frames) -> None:
        self.robot, self.name = robot, name
        self.joint_names, self.frames = tuple(joint_names), tuple(frames)
        self.floating = has_base(self.joint_names)
        actuated = list(robot.actuated_joint_names)
        for joint in self.joint_names[6 if self.floating else 0 :]:
            if joint not in actuated:
                raise UnknownNameError("joint", joint, actuated)
        self._order = [actuated.index(j) for j in self.joint_names[6 if self.floating else 0 :]]
        links = list(robot.link_map)
        for frame in self.frames:
            if frame not in robot.link_map:
                raise UnknownNameError("frame", frame, links)
        self._root = robot.base_link
        self._cfg = np.asarray(robot.cfg, dtype=float).copy()
        self._reseat_transforms()
        parent = {j.child: j.parent for j in robot.robot.joints}
        depth: dict[str, int] = {}
        for frame in self.frames:  # every link from the root to each frame, parents first
            link, path = frame, []
            while link != self._root and link not in depth:
                path.append(link)
                link = parent[link]
            for k, child in enumerate(reversed(path)):
                depth[child] = depth.get(link, 0) + k + 1
        self._edges = [(child, parent[child]) for child in sorted(depth, key=depth.__getitem__)]

    def _reseat_transforms(self) -> None:
        """At load time trimesh keeps a joint's first (identity) transform when the real origin is
        within 1e-8 of it (quirks.py): move every joint far away once, then back."""
        far = np.eye(4)
        far[:3, 3] = 1.0
        graph = self.robot.scene.graph
        for joint in self.robot.robot.joints:
            if joint.type == "fixed" and joint.origin is not None:
                graph.update(frame_from=joint.parent, frame_to=joint.child, matrix=far)
                graph.update(frame_from=joint.parent, frame_to=joint.child, matrix=joint.origin)
        self.robot.update_cfg(self._cfg + 1.0)
        self.robot.update_cfg(self._cfg)

    @classmethod
    def from_urdf(cls, urdf_text: str, joint_names, frames, name: str = "yourdfpy", **load_kwargs) -> "YourdfpyBackend":
        kwargs = dict(build_scene_graph=True, load_meshes=False, build_collision_scene_graph=False, load_collision_meshes=False)
        kwargs.update(load_kwargs)
        if has_base(joint_names):
            urdf_text = fixed_root(urdf_text)
        try:
            robot = yourdfpy.URDF.load(io.BytesIO(urdf_text.encode()), **kwargs)
        except Exception as err:  # yourdfpy raises bare lxml/ValueError/KeyError alike
            raise BackendError(name, f"cannot load URDF: {library_reason(err)}") from None
        return cls(robot, name, joint_names, frames)

    def poses(self, q: np.ndarray) -> np.ndarray:
        q = self._check(q)
        if self.floating:
            return base_transforms(q[:, :6])[:, None] @ self._joint_poses(q[:, 6:])
        return self._joint_poses(q)

    def _joint_poses(self, q: np.ndarray) -> np.ndarray:
        out = np.empty((q.shape[0], len(self.frames), 4, 4))
        cfg = self._cfg  # the configuration the scene graph holds now (kept across calls)
        for k, qk in enumerate(q):
            previous, cfg = cfg, cfg.copy()
            cfg[self._order] = qk
            if np.any((cfg != previous) & (np.abs(cfg - previous) < STALE_BELOW)):
                self.robot.update_cfg(cfg + 1.0)  # trimesh would skip so small a change (quirks.py)
            self.robot.update_cfg(cfg)
            world = {self._root: _IDENTITY}
            for child, par in self._edges:
                world[child] = world[par] @ self.robot.get_transform(child, par)
            for f, frame in enumerate(self.frames):
                out[k, f] = world[frame]
        self._cfg = cfg
        return out


def fixed_root(urdf_text: str) -> str:
    """The URDF with its floating root joint made fixed at the identity (the base pose is composed
    by the adapter)."""
    import xml.etree.ElementTree as ET

    root = ET.fromstring(urdf_text)
    children = {c.get("link") for j in root.iter("joint") if (c := j.find("child")) is not None}
    for joint in root.iter("joint"):
        parent = joint.find("parent")
        if joint.get("type") == "floating" and parent is not None and parent.get("link") not in children:
            joint.set("type", "fixed")
            for origin in joint.findall("origin"):
                joint.remove(origin)
    return ET.tostring(root, encoding="unicode")
