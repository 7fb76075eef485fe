"""Newton on a USD (``newton-usd``): ``ModelBuilder.add_usd``, the importer Newton and Isaac Lab 3 load
an OpenUSD robot with, compared like Newton's URDF and MJCF readings (conventions, float32 floor:
:mod:`kinverify.backends.newton_`).

The stage is the one kinverify opens (:func:`kinverify.backends.usd_.load_robot`: every layer checked
before pxr reads it). Newton refuses a stage with composition errors, and a robot whose meshes are
absent has them (a reference to a missing mesh layer, as in the shared Isaac Lab ANYmal C and Apollo): it is then given the
stage flattened (``Usd.Stage.Flatten``: the same composed prims, the absent layers contributing
nothing, as they do in the stage itself). Newton is asked for no visual shapes and no mesh
approximation (kinematics only).

Frames: Newton's rigid bodies (labels are prim paths) and its sites (prims with ``MjcSiteAPI`` or
``NewtonSiteAPI``, loaded as shapes flagged ``SITE``). A plain ``Xform`` under a body (a spec's tool,
a URDF link the converter keeps as an Xform) is no Newton entity: its pose in its body is the
stage's own transform (pxr), carried on Newton's body. A root body no joint holds to the world gets
a free joint (``add_usd``'s default); without base coordinates it is held at the identity, as the
``usd`` backend holds it.
"""

from __future__ import annotations

import newton_usd_schemas  # noqa: F401  (Newton's USD importer needs its schemas: part of the "newton" extra)
import numpy as np
from pxr import Usd

from kinverify.backends.newton_ import READERS, NewtonBackend, newton
from kinverify.backends.usd_ import load_robot
from kinverify.backends.usd_layers import quiet_stderr
from kinverify.backends.usd_stage import UsdRobot
from kinverify.errors import BackendError, UnknownNameError

IDENTITY_FREE = np.array([0.0, 0, 0, 0, 0, 0, 1])  # a free joint's coordinates at the identity: p, quaternion xyzw


def newton_stage(robot: UsdRobot):
    """The stage Newton reads: kinverify's, flattened where it has composition errors (absent layers)."""
    if not robot.stage.GetCompositionErrors():
        return robot.stage
    with quiet_stderr():  # pxr names each custom metadata field it drops while flattening
        return Usd.Stage.Open(robot.stage.Flatten())


def _import_usd(builder, robot: UsdRobot, floating: bool) -> None:
    with quiet_stderr():
        builder.add_usd(
            newton_stage(robot),
            load_visual_shapes=False,
            load_static_visual_shapes=False,
            skip_mesh_approximation=True,
            load_sites=True,
        )


class NewtonUsdBackend(NewtonBackend):
    """Newton's reading of a USD robot (``add_usd``), frames as the module docstring says."""

    readers = {**READERS, "usd": _import_usd}

    def __init__(self, robot: UsdRobot, name: str, joint_names, frames) -> None:
        self.robot = robot
        if robot.meters != 1.0:  # quirks.py, newton-usd
            stated = "USD's fallback, not authored" if not robot.stage.HasAuthoredMetadata("metersPerUnit") else "authored"
            raise BackendError(
                name,
                f"Newton's add_usd reads lengths as metres and ignores the stage's metersPerUnit ({robot.meters:g}, {stated}): "
                f"it would place every body {1 / robot.meters:g} times as far as the stage does; not compared",
            )
        super().__init__(robot, "usd", name, joint_names, frames)  # type: ignore[arg-type]  # the importer takes the robot
        if not self.floating:  # a free root joint held at the identity, like the usd backend's floating root
            m = self.one
            types, parents, q_start = m.joint_type.numpy(), m.joint_parent.numpy(), m.joint_q_start.numpy()
            for j in range(m.joint_count):
                if types[j] == int(newton.JointType.FREE) and parents[j] < 0:
                    self._q0[q_start[j] : q_start[j] + 7] = IDENTITY_FREE

    @classmethod
    def from_usd(cls, usd_text_or_path: str, joint_names, frames, name: str = "newton-usd") -> "NewtonUsdBackend":
        return cls(load_robot(usd_text_or_path), name, joint_names, frames)

    def _other_frame(self, m, frame: str, known: list[str]) -> tuple[int, np.ndarray]:
        """A plain Xform under a body: its pose in the body from the stage, on Newton's body."""
        site = self.robot.sites.get(frame)
        bodies = list(m.body_label)
        if site is None or site[0] not in bodies:
            raise UnknownNameError("frame", frame, known + sorted(self.robot.sites))
        return bodies.index(site[0]), site[1]
