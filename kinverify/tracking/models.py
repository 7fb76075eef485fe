"""The two dynamics models compared and used by the controllers, in kinverify's joint order.

- :class:`PinocchioDynamics`: Pinocchio on the generated **URDF**. URDF cannot express joint
  armature (rotor inertia), so it is set on ``model.armature`` from the spec (or, without a spec,
  from the MJCF) and reported as such. Pinocchio 4's ``crba``/``rnea``/``aba`` include
  ``model.armature``; none of them applies ``model.damping`` (read from the URDF's
  ``<dynamics damping>``), which is added here as the passive force ``-D·q̇``.
- :class:`MujocoDynamics`: MuJoCo on the generated **MJCF**. With ``rigid=True`` (what the
  dynamics comparison uses) MuJoCo computes rigid-body dynamics plus joint damping only: its
  constraints (contacts, joint limits, ``frictionloss``, equalities), springs and actuators are
  disabled, because Pinocchio models none of them and ``mj_inverse``/``mj_forward`` would
  otherwise include their forces. Coulomb friction is then compared as a parameter.

Native conventions: Pinocchio's ``q``/``v`` follow ``joint.idx_q``/``idx_v``; MuJoCo's follow
``jnt_qposadr``/``jnt_dofadr``. Both are permuted to the spec's joint order here. With a
floating base (``joint_names`` starting with the six base coordinates of
:mod:`kinverify.model.floating`), the mass matrix and gravity are given in those coordinates:
``Sᵀ·M·S`` and ``Sᵀ·g`` with ``S`` the map from the base coordinates' rates to the library's
base velocity (Pinocchio's free-flyer body twist; MuJoCo's free joint world linear and body
angular velocity). The velocity-dependent terms (bias, inverse and forward dynamics) would need
``Ṡ`` and are only defined for fixed bases here.
"""

from __future__ import annotations

import copy

import mujoco
import numpy as np
import pinocchio as pin

from kinverify.backends.pinocchio_ import build_urdf_model
from kinverify.errors import BackendError, UnknownNameError, library_reason
from kinverify.model.floating import base_transforms, has_base, velocity_map
from kinverify.model.transforms import matrix_to_quat


class PinocchioDynamics:
    library, reads = "pinocchio-urdf", "URDF"  # the backend named in its errors, and the format it reads

    def __init__(self, urdf: str, joint_names, armature) -> None:
        self.model = self.build_model(urdf)
        m = self.model
        self.floating = has_base(joint_names)
        self._ff: tuple[int, int, np.ndarray] | None = None
        if self.floating:
            root = next((i for i in range(1, m.njoints) if m.parents[i] == 0), None)
            if root is None or m.joints[root].shortname() != "JointModelFreeFlyer":
                raise BackendError(
                    self.library, f"the configuration has a floating base but the {self.reads}'s root joint is not floating"
                )
            self._ff = (m.joints[root].idx_q, m.joints[root].idx_v, m.jointPlacements[root].inverse().homogeneous)
            joint_names = joint_names[6:]
        missing = [j for j in joint_names if not m.existJointName(j)]
        if missing:
            raise UnknownNameError("joint", missing[0], [m.names[i] for i in range(1, m.njoints)])
        compared = len(joint_names) + 6 * self.floating
        if m.nv != compared:
            raise BackendError(
                self.library,
                f"dynamics needs the model to move by the compared joints only ({compared} degree{'s' * (compared != 1)} "
                f"of freedom), the {self.reads} has {m.nv}",
            )
        self.idx_v = np.array([m.joints[m.getJointId(j)].idx_v for j in joint_names])
        self.idx_q = np.array([m.joints[m.getJointId(j)].idx_q for j in joint_names])
        self.urdf_armature = np.array(m.armature)[self.idx_v].copy()  # always 0: URDF has no field for it
        m.armature[self.idx_v] = np.asarray(armature, dtype=float)
        self.damping = np.array(m.damping)[self.idx_v].copy()
        self.friction = np.array(m.friction)[self.idx_v].copy()
        self.data = m.createData()
        self._perm = np.argsort(self.idx_v)  # model order -> ours

    def with_inertials(self, changes: dict[str, tuple[tuple, tuple]]) -> PinocchioDynamics:
        """A copy in which each named body (link) carries another inertial: ``changes`` maps the
        name to (inertial it has, inertial it gets), each ``(mass, com, 3×3 inertia about the com)``
        in the body frame (:meth:`MujocoDynamics.run_inertials`)."""
        other = copy.copy(self)
        m = other.model = self.model.copy()
        for name, (old, new) in changes.items():
            if not m.existFrame(name, pin.FrameType.BODY):  # a body the URDF does not have: left as it is
                continue
            frame = m.frames[m.getFrameId(name, pin.FrameType.BODY)]
            if frame.parentJoint == 0:  # fixed to the world: in no dynamics
                continue
            # dynamic parameters (mass, first and second moments) are linear in the bodies summed
            params = [frame.placement.act(pin.Inertia(*i)).toDynamicParameters() for i in (old, new)]
            total = m.inertias[frame.parentJoint].toDynamicParameters() - params[0] + params[1]
            m.inertias[frame.parentJoint] = pin.Inertia.FromDynamicParameters(total)
        other.data = m.createData()
        return other

    @classmethod
    def build_model(cls, urdf: str):
        """Pinocchio's model of the text (a subclass may read another format)."""
        try:
            return build_urdf_model(urdf)
        except ValueError as err:
            raise BackendError(cls.library, f"cannot load URDF: {library_reason(err)}") from None

    def _in(self, x) -> np.ndarray:
        out = np.empty(len(self.idx_v))
        out[self.idx_v] = x
        return out

    def _q(self, q) -> np.ndarray:
        """The model's configuration for ours (joints, after the base coordinates when floating)."""
        q = np.asarray(q, dtype=float)
        if not self.floating:
            return self._in(q)
        assert self._ff is not None  # set whenever the base floats
        iq, _, placement_inv = self._ff
        full = pin.neutral(self.model)
        t = placement_inv @ base_transforms(q[:6])
        full[iq : iq + 3] = t[:3, 3]
        full[iq + 3 : iq + 7] = np.roll(matrix_to_quat(t[:3, :3]), -1)  # wxyz -> xyzw
        full[self.idx_q] = q[6:]
        return full

    def _columns(self, q) -> tuple[np.ndarray, np.ndarray | None]:
        """Our columns among the model's velocities, and ``S`` for the base block (None if fixed)."""
        return base_columns(self.idx_v, self._ff[1] if self._ff is not None else None, q, linear_in_body=True)

    def mass(self, q) -> np.ndarray:
        M = pin.crba(self.model, self.data, self._q(q))
        M = np.triu(M) + np.triu(M, 1).T  # crba fills the upper triangle
        cols, s = self._columns(q)
        M = M[np.ix_(cols, cols)]
        return M if s is None else s.T @ M @ s

    def bias(self, q, v) -> np.ndarray:
        """Coriolis, centrifugal and gravity forces ``h(q, q̇)`` (MuJoCo's ``qfrc_bias``)."""
        return np.asarray(pin.nonLinearEffects(self.model, self.data, self._in(q), self._in(v)))[self.idx_v]

    def gravity(self, q) -> np.ndarray:
        g = np.asarray(pin.computeGeneralizedGravity(self.model, self.data, self._q(q)))
        cols, s = self._columns(q)
        return g[cols] if s is None else s.T @ g[cols]

    def inverse(self, q, v, a) -> np.ndarray:
        """Joint forces giving acceleration ``a``: RNEA plus the damping force ``D·q̇`` to overcome."""
        tau = np.asarray(pin.rnea(self.model, self.data, self._in(q), self._in(v), self._in(a)))[self.idx_v]
        return tau + self.damping * np.asarray(v)

    def forward(self, q, v, tau) -> np.ndarray:
        """ABA: acceleration under ``tau`` and the damping force ``-D·q̇``."""
        tau = np.asarray(tau) - self.damping * np.asarray(v)
        return np.asarray(pin.aba(self.model, self.data, self._in(q), self._in(v), self._in(tau)))[self.idx_v]

    def step_euler(self, q, v, tau, dt: float) -> tuple[np.ndarray, np.ndarray]:
        """One step of MuJoCo's ``Euler`` integrator, computed with ABA: damping is implicit,
        ``(M + dt·D) a = τ − h − D·q̇``, i.e. ABA with armature raised by ``dt·D``; then
        semi-implicit Euler ``q̇' = q̇ + dt·a``, ``q' = q + dt·q̇'``."""
        m = self.model
        saved = m.armature.copy()
        m.armature[self.idx_v] += dt * self.damping
        try:
            a = self.forward(q, v, tau)
        finally:
            m.armature[:] = saved
        v1 = np.asarray(v) + dt * a
        return np.asarray(q) + dt * v1, v1


RIGID_BODY_DISABLED = ("mjDSBL_CONSTRAINT", "mjDSBL_SPRING", "mjDSBL_ACTUATION")


class MujocoDynamics:
    def __init__(self, mjcf: str, joint_names, rigid: bool = False, library: str = "mujoco", reads: str = "MJCF") -> None:
        """``library``, ``reads``: the backend named in its errors and the format it read (MuJoCo's
        URDF import: ``mujoco-urdf`` and ``URDF``, ``mjcf`` then being the URDF's MJCF)."""
        try:
            self.model = mujoco.MjModel.from_xml_string(mjcf)
        except ValueError as err:
            raise BackendError(library, f"cannot load {reads}: {library_reason(err)}") from None
        m = self.model
        if rigid:  # no constraints, springs, actuators or gravity compensation (a passive force)
            for flag in RIGID_BODY_DISABLED:
                m.opt.disableflags |= int(getattr(mujoco.mjtDisableBit, flag))
            m.body_gravcomp[:] = 0.0
        self._free: tuple[int, int] | None = None
        self.floating = has_base(joint_names)
        if self.floating:
            free = [
                j
                for j in range(m.njnt)
                if int(m.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_FREE) and m.body_parentid[m.jnt_bodyid[j]] == 0
            ]
            if len(free) != 1:
                raise BackendError(
                    library,
                    f"the configuration has a floating base but the {reads} has {len(free)} free "
                    "joints on top-level bodies (expected one)",
                )
            self._free = (int(m.jnt_qposadr[free[0]]), int(m.jnt_dofadr[free[0]]))
            if rigid:  # a free joint's armature and damping (a URDF's floating base has neither)
                m.dof_armature[self._free[1] : self._free[1] + 6] = 0.0
                m.dof_damping[self._free[1] : self._free[1] + 6] = 0.0
            joint_names = joint_names[6:]
        ids = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, j) for j in joint_names]
        if min(ids) < 0:
            raise BackendError(library, f"{reads} lacks joint {joint_names[ids.index(min(ids))]!r}")
        self.qadr = np.array([m.jnt_qposadr[i] for i in ids])
        self.vadr = np.array([m.jnt_dofadr[i] for i in ids])
        self.armature = np.array(m.dof_armature)[self.vadr]
        self.damping = np.array(m.dof_damping)[self.vadr]
        self.friction = np.array(m.dof_frictionloss)[self.vadr]
        self.data = mujoco.MjData(m)
        self._full = np.zeros((m.nv, m.nv))

    def snapped_inertia_frames(self) -> list[tuple[str, float]]:
        """Bodies whose principal inertia axes MuJoCo's compiler treats as aligned with the body
        frame (``body_sameframe``) although ``body_iquat`` is not the identity: MuJoCo then drops a
        rotation of this angle [rad] at run time, changing M by up to angle·(I_max − I_min)."""
        m, out = self.model, []
        aligned = (int(mujoco.mjtSameFrame.mjSAMEFRAME_BODY), int(mujoco.mjtSameFrame.mjSAMEFRAME_BODYROT))
        for b in range(1, m.nbody):
            vec = float(np.linalg.norm(m.body_iquat[b][1:]))
            if int(m.body_sameframe[b]) in aligned and vec > 0:
                out.append((m.body(b).name, 2.0 * float(np.arcsin(min(1.0, vec)))))
        return out

    def moved_coms(self) -> list[tuple[str, float]]:
        """Bodies whose stated centre of mass (``body_ipos``, not zero) MuJoCo's run time puts at the
        body origin, with that distance [m]: the compiler's same-frame test takes an inertial frame
        whose every coordinate is within 1e-6 m of the body's, and whose quaternion is within 1e-6 of
        the identity, for the body frame itself (``body_sameframe`` = BODY), and ``mj_kinematics``
        then uses the body's origin as its centre of mass (``xipos``)."""
        m, same = self.model, int(mujoco.mjtSameFrame.mjSAMEFRAME_BODY)
        return [
            (m.body(b).name, float(np.linalg.norm(m.body_ipos[b])))
            for b in range(1, m.nbody)
            if int(m.body_sameframe[b]) == same and np.any(m.body_ipos[b])
        ]

    def run_inertials(self) -> dict[str, tuple[tuple, tuple]]:
        """For each body :meth:`snapped_inertia_frames` or :meth:`moved_coms` names: its inertial as
        the MJCF states it (compiled: ``body_ipos``, ``body_iquat``) and as MuJoCo's run time uses it
        (at the body origin, along the body's axes); each ``(mass, com, 3×3 inertia about the com)``
        in the body frame."""
        m, out = self.model, {}
        for name in dict(self.snapped_inertia_frames() + self.moved_coms()):
            b = m.body(name).id
            flat = np.zeros(9)
            mujoco.mju_quat2Mat(flat, m.body_iquat[b])
            rot, diag = flat.reshape(3, 3), np.diag(m.body_inertia[b])
            mass, com = float(m.body_mass[b]), np.array(m.body_ipos[b])
            same = int(m.body_sameframe[b]) == int(mujoco.mjtSameFrame.mjSAMEFRAME_BODY)
            out[name] = ((mass, com, rot @ diag @ rot.T), (mass, np.zeros(3) if same else com, diag))
        return out

    def _set(self, q, v=None) -> None:
        d = self.data
        d.qpos[:] = self.model.qpos0
        d.qvel[:] = 0.0
        q = np.asarray(q, dtype=float)
        if self.floating:  # the free joint's qpos: the base's world pose, quaternion wxyz
            t = base_transforms(q[:6])
            assert self._free is not None  # set whenever the base floats
            a = self._free[0]
            d.qpos[a : a + 3], d.qpos[a + 3 : a + 7] = t[:3, 3], matrix_to_quat(t[:3, :3])
            if v is not None:
                raise ValueError("velocity-dependent dynamics of a floating base are not compared")
            q = q[6:]
        d.qpos[self.qadr] = q
        if v is not None:
            d.qvel[self.vadr] = v
        mujoco.mj_forward(self.model, d)

    def _columns(self, q) -> tuple[np.ndarray, np.ndarray | None]:
        """Our columns among MuJoCo's dofs, and ``S`` for the base block (None if fixed)."""
        return base_columns(self.vadr, self._free[1] if self._free is not None else None, q, linear_in_body=False)

    def mass(self, q) -> np.ndarray:
        self._set(q)
        mujoco.mj_fullM(self.model, self.data, self._full)
        cols, s = self._columns(q)
        M = self._full[np.ix_(cols, cols)].copy()
        return M if s is None else s.T @ M @ s

    def bias(self, q, v) -> np.ndarray:
        self._set(q, v)
        return self.data.qfrc_bias[self.vadr].copy()

    def gravity(self, q) -> np.ndarray:
        self._set(q)  # at rest: qfrc_bias is gravity alone
        cols, s = self._columns(q)
        g = self.data.qfrc_bias[cols].copy()
        return g if s is None else s.T @ g

    def inverse(self, q, v, a) -> np.ndarray:
        """``mj_inverse``: joint forces giving ``a``, including the passive (damping) forces."""
        self._set(q, v)
        self.data.qacc[:] = 0.0
        self.data.qacc[self.vadr] = a
        mujoco.mj_inverse(self.model, self.data)
        return self.data.qfrc_inverse[self.vadr].copy()

    def forward(self, q, v, tau) -> np.ndarray:
        """``mj_forward``'s continuous-time acceleration under joint forces ``tau`` (as
        ``qfrc_applied``) and the passive damping force."""
        d = self.data
        d.qfrc_applied[:] = 0.0
        d.qfrc_applied[self.vadr] = tau
        try:
            self._set(q, v)
            return d.qacc[self.vadr].copy()
        finally:
            d.qfrc_applied[:] = 0.0


def base_columns(joint_cols, base_start, q, linear_in_body: bool) -> tuple[np.ndarray, np.ndarray | None]:
    """A library's velocity columns for our coordinates (the base's six first when ``base_start``
    is not None) and ``S`` mapping our rates to them (None for a fixed base); ``linear_in_body``:
    the library's free-joint linear velocity is in the base frame (Pinocchio) or the world's (MuJoCo)."""
    if base_start is None:
        return joint_cols, None
    cols = np.concatenate([np.arange(base_start, base_start + 6), joint_cols])
    s = np.eye(len(cols))
    s[:6, :6] = velocity_map(np.asarray(q, dtype=float)[:6], linear_in_body=linear_in_body)
    return cols, s
