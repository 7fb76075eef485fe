"""Drake's rigid-body dynamics of a model file, in kinverify's joint order and sign conventions
(those of :class:`kinverify.tracking.models.PinocchioDynamics`): ``M(q)``, gravity ``g(q)`` (the
force to hold against gravity), bias ``h(q, q̇) = C(q, q̇)·q̇ + g(q)``, inverse dynamics with the
joint damping force ``D·q̇`` to overcome, and forward dynamics under ``τ − D·q̇``.

Native conventions (see :mod:`kinverify.backends.drake_`): ``CalcGravityGeneralizedForces`` is
``−g(q)``; ``CalcBiasTerm`` is ``C·q̇`` without gravity; ``CalcInverseDynamics`` takes the applied
forces, here Drake's own force elements (gravity and joint damping) from
``CalcForceElementsContribution``, so it returns ``M·q̈ + C·q̇ + g + D·q̇``. Joint armature is
Drake's reflected inertia (``rotor_inertia · gear_ratio²`` on the joint's actuator), which
``CalcMassMatrix`` and ``CalcInverseDynamics`` include. Drake has no Coulomb joint friction.
A floating base: the mass matrix and gravity in the base coordinates (``Sᵀ·M·S``, ``Sᵀ·g``, ``S``
from our rates to Drake's ``[ω; v]`` in the world); velocity terms only for a fixed base.
"""

from __future__ import annotations

import numpy as np
from pydrake.multibody.tree import MultibodyForces

from kinverify.backends.drake_plant import base_positions, base_velocity_map, floating_joint, load_plant, one_dof_joint
from kinverify.model.floating import has_base


class DrakeDynamics:
    def __init__(self, text: str, source: str, joint_names, name: str = "drake-sdf") -> None:
        self.name = name
        self.floating = has_base(joint_names)
        self.plant, _, self.parser_warnings = load_plant(text, source, floating=self.floating, name=name)
        plant = self.plant
        self.context = plant.CreateDefaultContext()
        self._q0 = plant.GetPositions(self.context).copy()
        self._free: tuple[int, int] | None = None
        if self.floating:
            joint = floating_joint(plant, name)
            self._free = (joint.position_start(), joint.velocity_start())
        joints = [one_dof_joint(plant, j, name) for j in joint_names[6 if self.floating else 0 :]]
        self.idx_q = np.array([j.position_start() for j in joints], dtype=int)
        self.idx_v = np.array([j.velocity_start() for j in joints], dtype=int)
        self.damping = np.array([float(j.default_damping()) for j in joints])
        reflected = np.zeros(plant.num_velocities())
        for a in plant.GetJointActuatorIndices():
            actuator = plant.get_joint_actuator(a)
            reflected[actuator.joint().velocity_start()] += actuator.default_reflected_inertia()
        self.armature = reflected[self.idx_v]

    def _set(self, q, v=None) -> None:
        full = self._q0.copy()
        q = np.asarray(q, dtype=float)
        if self.floating:
            if v is not None:
                raise ValueError("velocity-dependent dynamics of a floating base are not compared")
            assert self._free is not None  # set whenever the base floats
            full[self._free[0] : self._free[0] + 7] = base_positions(q[:6])[0]
            q = q[6:]
        full[self.idx_q] = q
        self.plant.SetPositions(self.context, full)
        velocities = np.zeros(self.plant.num_velocities())
        if v is not None:
            velocities[self.idx_v] = v
        self.plant.SetVelocities(self.context, velocities)

    def _columns(self, q) -> tuple[np.ndarray, np.ndarray | None]:
        if not self.floating:
            return self.idx_v, None
        assert self._free is not None  # set whenever the base floats
        iv = self._free[1]
        cols = np.concatenate([np.arange(iv, iv + 6), self.idx_v])
        s = np.eye(len(cols))
        s[:6, :6] = base_velocity_map(np.asarray(q, dtype=float)[:6])[0]
        return cols, s

    def mass(self, q) -> np.ndarray:
        self._set(q)
        cols, s = self._columns(q)
        M = self.plant.CalcMassMatrix(self.context)[np.ix_(cols, cols)]
        return M if s is None else s.T @ M @ s

    def gravity(self, q) -> np.ndarray:
        self._set(q)
        cols, s = self._columns(q)
        g = -self.plant.CalcGravityGeneralizedForces(self.context)[cols]
        return g if s is None else s.T @ g

    def bias(self, q, v) -> np.ndarray:
        self._set(q, v)
        h = self.plant.CalcBiasTerm(self.context) - self.plant.CalcGravityGeneralizedForces(self.context)
        return h[self.idx_v]

    def _inverse_full(self, a_full: np.ndarray) -> np.ndarray:
        forces = MultibodyForces(self.plant)
        self.plant.CalcForceElementsContribution(self.context, forces)  # gravity and joint damping
        return self.plant.CalcInverseDynamics(self.context, a_full, forces)

    def inverse(self, q, v, a) -> np.ndarray:
        """Joint forces giving acceleration ``a``: ``M·a + C·q̇ + g + D·q̇``."""
        self._set(q, v)
        a_full = np.zeros(self.plant.num_velocities())
        a_full[self.idx_v] = a
        return self._inverse_full(a_full)[self.idx_v]

    def forward(self, q, v, tau) -> np.ndarray:
        """Acceleration under joint forces ``tau`` and the damping force: ``M⁻¹ (τ − C·q̇ − g − D·q̇)``."""
        self._set(q, v)
        rest = self._inverse_full(np.zeros(self.plant.num_velocities()))
        M = self.plant.CalcMassMatrix(self.context)
        force = -rest
        force[self.idx_v] += np.asarray(tau, dtype=float)
        return np.linalg.solve(M, force)[self.idx_v]
