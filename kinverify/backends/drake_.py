"""Drake (PyPI ``drake``, the optional extra ``kinverify[drake]``) on the URDF, the SDFormat file
or, through its own MJCF parser, the MJCF: a third independent implementation of parsing,
kinematics and rigid-body dynamics (``MultibodyPlant``).

Native conventions: ``CalcRelativeTransform(world, F)`` is ``T_world_from_frame``;
``CalcJacobianSpatialVelocity`` (with respect to ``v``, at the frame origin, measured and
expressed in the world) stacks a spatial velocity as **[angular; linear]**, swapped here to
[linear; angular]; quaternions are **wxyz** (``RotationMatrix``/``Quaternion``); a free body's
``QuaternionFloatingJoint`` has ``q = [qw qx qy qz, x y z]`` (world pose of the body) and ``v =
[ω, v]`` both in the world; ``CalcGravityGeneralizedForces`` is the force gravity *applies*
(``−g(q)`` in Pinocchio's sign) and ``CalcBiasTerm`` is ``C(q, v)·v`` without gravity.

Drake makes every body without an inboard joint a free body (an unwelded URDF root floats):
unless the configuration has a floating base, each such root body is welded to the world at
the identity, as Pinocchio and MuJoCo hold a root link. Drake's MJCF parser ignores ``<site>``
(quirks.py): each site becomes a frame on its body at the offset MuJoCo's compiler gives it.
Parser warnings (unsupported elements) are kept in ``parser_warnings``, not printed.
"""

from __future__ import annotations

import numpy as np
from pydrake.multibody.tree import JacobianWrtVariable

from kinverify.backends.base import EvaluatingBackend, Evaluation
from kinverify.backends.drake_dynamics import DrakeDynamics
from kinverify.backends.drake_plant import (
    base_positions,
    base_velocity_map,
    floating_joint,
    frame_named,
    load_plant,
    one_dof_joint,
    refused_elements,
)
from kinverify.model.floating import has_base


class DrakeBackend(EvaluatingBackend):
    """Frame FK and Jacobians from a finalized ``MultibodyPlant`` (conventions: module docstring).
    Joints of the model not in ``joint_names`` stay at Drake's default positions (0 for 1-DOF joints)."""

    dynamics = DrakeDynamics  # Drake's dynamics model of a file (the dynamics suite's third library)
    load_plant = staticmethod(load_plant)  # Drake's reading of a file (file mode describes an SDFormat file with it)
    refused_elements = staticmethod(refused_elements)  # what its parser said it ignores, by element

    def __init__(self, plant, name: str, joint_names, frames, warnings=()) -> None:
        self.plant, self.name = plant, name
        self.context = plant.CreateDefaultContext()
        self.joint_names, self.frames = tuple(joint_names), tuple(frames)
        self.parser_warnings = list(warnings)
        self.floating = has_base(self.joint_names)
        self._q0 = plant.GetPositions(self.context).copy()
        self._free: tuple[int, int] | None = None
        if self.floating:
            joint = floating_joint(plant, name)
            self._free = (joint.position_start(), joint.velocity_start())
        joints = [one_dof_joint(plant, j, name) for j in self.joint_names[6 if self.floating else 0 :]]
        self._idx_q = [j.position_start() for j in joints]
        self._idx_v = [j.velocity_start() for j in joints]
        self._frames = [frame_named(plant, f) for f in self.frames]

    @classmethod
    def from_source(cls, text: str, source: str, joint_names, frames, name: str) -> "DrakeBackend":
        plant, _, warnings = load_plant(text, source, floating=has_base(joint_names), name=name)
        return cls(plant, name, joint_names, frames, warnings)

    @classmethod
    def from_urdf(cls, urdf_text: str, joint_names, frames, name: str = "drake-urdf") -> "DrakeBackend":
        return cls.from_source(urdf_text, "urdf", joint_names, frames, name)

    @classmethod
    def from_sdf(cls, sdf_text: str, joint_names, frames, name: str = "drake-sdf") -> "DrakeBackend":
        return cls.from_source(sdf_text, "sdf", joint_names, frames, name)

    @classmethod
    def from_mjcf(cls, mjcf_text: str, joint_names, frames, name: str = "drake-mjcf") -> "DrakeBackend":
        return cls.from_source(mjcf_text, "mjcf", joint_names, frames, name)

    def full_positions(self, q: np.ndarray) -> np.ndarray:
        """Drake's position vectors ``(N, nq)`` for our configurations ``(N, n)``."""
        full = np.tile(self._q0, (q.shape[0], 1))
        if self.floating:
            assert self._free is not None  # set whenever the base floats
            iq = self._free[0]
            full[:, iq : iq + 7] = base_positions(q[:, :6])
            q = q[:, 6:]
        full[:, self._idx_q] = q
        return full

    def evaluate(self, q: np.ndarray, with_jacobians: bool = True) -> Evaluation:
        q = self._check(q)
        plant, ctx, world = self.plant, self.context, self.plant.world_frame()
        n_cfg, n_frames = q.shape[0], len(self.frames)
        poses = np.empty((n_cfg, n_frames, 4, 4))
        full = np.empty((n_cfg, n_frames, 6, plant.num_velocities())) if with_jacobians else None
        origin, kv = np.zeros(3), JacobianWrtVariable.kV
        relative, jacobian, set_positions = plant.CalcRelativeTransform, plant.CalcJacobianSpatialVelocity, plant.SetPositions
        for k, qk in enumerate(self.full_positions(q)):
            set_positions(ctx, qk)
            for f, frame in enumerate(self._frames):
                poses[k, f] = relative(ctx, world, frame).GetAsMatrix4()
                if with_jacobians:
                    jac = jacobian(ctx, kv, frame, origin, world, world)
                    assert full is not None  # made whenever with_jacobians
                    full[k, f, :3], full[k, f, 3:] = jac[3:], jac[:3]  # [angular; linear] -> [linear; angular]
        jac = None
        if with_jacobians:
            assert full is not None
            jac = full[..., self._idx_v]
            if self.floating:
                assert self._free is not None  # set whenever the base floats
                iv = self._free[1]
                base = full[..., iv : iv + 6] @ base_velocity_map(q[:, :6])[:, None]
                jac = np.concatenate([base, jac], axis=-1)
        return Evaluation(self.name, self.frames, poses, jac)
