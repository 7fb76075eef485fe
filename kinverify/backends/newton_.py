"""Newton (PyPI ``newton`` with ``warp-lang``, the optional extra ``kinverify[newton]``) on the
URDF or the MJCF, through its own importers (``ModelBuilder.add_urdf`` / ``add_mjcf``): the reader
Isaac Lab 3 loads MJCF into, on the CPU here. ``newton-usd`` (``add_usd``,
:mod:`kinverify.backends.newton_usd`) adds its importer to :attr:`NewtonBackend.readers`.

Native conventions: Newton computes in **float32** (Warp kernels); a pose is a ``transformf``
``(p, q)``, seven floats ``[px py pz, qx qy qz qw]``, the quaternion **xyzw**; ``joint_q`` holds
each joint's coordinates in joint order at ``model.joint_q_start[j]`` (a revolute or prismatic
joint one, a free joint seven: its child's world position then quaternion xyzw, a fixed joint
none), ``joint_qd`` its DOFs at ``joint_qd_start[j]``; ``state.body_q`` the world pose of each body
origin. ``eval_jacobian`` gives, per articulation, ``(links·6, dofs)`` rows of each link's twist in
Newton's body-twist convention ``(v_com_world, ω_world)``: the linear rows are the velocity of the
link's **centre of mass**, moved here to the frame origin (``v_o = v_com + ω × (p_o − p_com)``).
``eval_mass_matrix`` gives the joint-space inertia with armature on its diagonal.

Every URDF link and MJCF body is a Newton body (``collapse_fixed_joints`` is left off: with it on,
Newton merges the child of each fixed joint into its parent and the link disappears as a frame);
labels are paths (URDF ``<robot>/<link>``, MJCF ``<model>/worldbody/<body>/.../<name>``), matched
here by their last part. An
MJCF ``<site>`` is a shape flagged ``ShapeFlags.SITE`` on its body, at ``shape_transform``.

Configurations are evaluated in batches: the robot is replicated :data:`COPIES` times in one model
(one world each), so one ``eval_fk`` / ``eval_jacobian`` launch evaluates that many configurations.
A floating base (kinverify's six base coordinates) is the root's free joint; its Jacobian columns
are the rigid motion of the whole robot, formed from the frame positions (Newton's free-joint DOF
convention is not needed).
"""

from __future__ import annotations

import contextlib
import gc
import warnings
from typing import Callable

import numpy as np

from kinverify.backends.base import BackendBase, Evaluation
from kinverify.errors import BackendError, UnknownNameError
from kinverify.model.floating import base_transforms, has_base, rate_matrices
from kinverify.model.transforms import matrix_to_quat, quat_to_matrix


@contextlib.contextmanager
def long_lived():
    """Python's cyclic garbage collector paused while Newton defines its Warp kernels, and what they
    made frozen after (``gc.freeze``): Warp parses every kernel's source when it is defined, so
    ``import newton`` leaves about a thousand parsed functions alive for the life of the process, and
    each full collection (dozens during the import, one more at exit) walked them all again: 2.5 s
    of the import's 4 s of CPU (docs/performance.md). The kernels live as long as the process
    either way; only their repeated traversal is saved. Everything else alive at that moment is
    frozen too: should it later become cyclic garbage, it is not collected (a long process that
    builds many Newton backends, a test session, keeps a little more memory)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        gc.freeze()
        if enabled:
            gc.enable()


with long_lived():
    import warp as wp

    wp.config.log_level = wp.LOG_WARNING  # set before Newton loads kernels: no "Module ... load" line per module
    import newton

COPIES = 64  # configurations per kernel launch (copies of the robot in one model)
# About twice the largest difference measured (Newton 1.8.0, Warp 1.19.0) between Newton's float32
# readings and Pinocchio's (same URDF) or MuJoCo's (same MJCF), over the shipped specs (200 samples
# each) and the eight shared real-robot pairs (200 in-range samples, every body, link and site):
# position 1.9e-6 m (models/panda.toml's MJCF), rotation 9.2e-7 rad (ur5e's URDF), Jacobian linear
# rows 6.9e-6 and angular rows 1.1e-5 (Frobenius; the Panda MJCFs, see quirks.py), Jacobian against
# finite differences of its own FK 5.1e-5. docs/performance.md lists them per robot.
# A world turned 45° about z and moved 0.37 m (tests/filemode/test_audit.py) took the Panda MJCF's
# position to 4.9e-6 m: hence 1e-5.
FLOOR = {"fk.position": 1e-5, "fk.rotation": 5e-6, "jacobian.linear": 3e-5, "jacobian.angular": 3e-5, "jacobian.fd": 1.5e-4}
FLOOR["ik.cross_fk"] = 1e-6 + max(FLOOR["fk.position"], FLOOR["fk.rotation"])  # IK's own tolerance + Newton's FK error
# Finite differences of float32 FK: round-off ~1e-7 m / h, truncation ~h²/6; measured on the Panda: h = 1e-3
# gives 4.6e-4 (Frobenius, 7 joints), 3e-3 1.6e-4, 1e-2 5.2e-5, 2e-2 9.8e-5.
FD_STEP32 = 1e-2


def _import_urdf(builder, text: str, floating: bool) -> None:
    builder.add_urdf(text, floating=floating, hide_visuals=True, ignore_inertial_definitions=False)


def _import_mjcf(builder, text: str, floating: bool) -> None:
    # floating=None: the file's own free joint makes the floating base, as in MuJoCo (floating=True would give
    # every top-level body one, a static one too: Apollo's world_link)
    builder.add_mjcf(text, floating=None, parse_visuals=False, parse_meshes=False, ignore_inertial_definitions=False)


# One importer per source kind (a subclass's ``readers`` adds "usd": kinverify.backends.newton_usd).
READERS = {"urdf": _import_urdf, "mjcf": _import_mjcf}


class NewtonBackend(BackendBase):
    """Frame FK, Jacobians and the mass matrix from a finalized ``newton.Model`` on the CPU
    (conventions: module docstring). Joints not in ``joint_names`` stay at Newton's ``joint_q``
    defaults."""

    agreement_floor = FLOOR
    fd_step = FD_STEP32
    readers: dict[str, Callable[..., None]] = READERS  # source kind -> importer (a subclass adds its own: newton_usd)

    def __init__(self, text: str, source: str, name: str, joint_names, frames) -> None:
        self.name, self.joint_names, self.frames = name, tuple(joint_names), tuple(frames)
        self.floating = has_base(self.joint_names)
        robot = newton.ModelBuilder()
        with warnings.catch_warnings(record=True) as caught:  # e.g. "Inertia validation corrected 5 bodies"
            warnings.simplefilter("always")
            try:
                with long_lived():  # add_mjcf imports Newton's MuJoCo solver (its kernels) the first time
                    self.readers[source](robot, text, self.floating)
            except Exception as err:
                raise BackendError(name, f"cannot load the {source.upper()}: {type(err).__name__}: {err}") from None
            self.one = robot.finalize(device="cpu", requires_grad=False)
        self.parser_warnings = [str(w.message) for w in caught]  # kept, not printed
        m = self.one
        self.n_q, self.n_qd, self.n_body = m.joint_coord_count, m.joint_dof_count, m.body_count
        labels = list(m.joint_label)
        types, q_start, qd_start = m.joint_type.numpy(), m.joint_q_start.numpy(), m.joint_qd_start.numpy()
        self._free = None
        free = [j for j in range(m.joint_count) if types[j] == int(newton.JointType.FREE) and m.joint_parent.numpy()[j] < 0]
        if self.floating:
            if len(free) != 1:
                raise BackendError(name, f"the configuration has a floating base but the model has {len(free)} free root joints")
            self._free = (int(q_start[free[0]]), int(qd_start[free[0]]), int(m.joint_child.numpy()[free[0]]))
        self._iq, self._iv, held = [], [], free[:1] if self.floating else []
        for joint in self.joint_names[6 if self.floating else 0 :]:
            j = _find(labels, joint)
            if j is None:
                raise UnknownNameError("joint", joint, [_short(x) for x in labels])
            if types[j] not in (int(newton.JointType.REVOLUTE), int(newton.JointType.PRISMATIC)):
                raise BackendError(name, f"joint {joint!r} is not a revolute or prismatic joint in Newton's reading")
            self._iq.append(int(q_start[j]))
            self._iv.append(int(qd_start[j]))
            held.append(j)
        self._targets = self._frame_targets(m)  # (body index, 4×4 offset) per frame
        self._articulation(m, held)
        self._q0 = m.joint_q.numpy().astype(np.float64)
        self._com = np.vstack([m.body_com.numpy().astype(np.float64), np.zeros(3)])  # body frame; the world's last
        builder = newton.ModelBuilder()
        builder.replicate(robot, COPIES)
        with warnings.catch_warnings():  # the same warnings again, once per copy
            warnings.simplefilter("ignore")
            self.model = builder.finalize(device="cpu", requires_grad=False)
        self.state = self.model.state()

    def _articulation(self, m, held: list[int]) -> None:
        """The articulation moved by the compared coordinates (joints ``held``), as eval_jacobian lays it out:
        a row block per joint of it (its child body's twist), a column per DOF from its first. Bodies of
        other articulations (a static body of its own, like Apollo's world_link in its MJCF) do not move."""
        arts = m.joint_articulation.numpy()
        self._art, self._n_art = int(arts[held[0]]) if held else 0, m.articulation_count
        if self._art < 0 or any(arts[j] != self._art for j in held):
            raise BackendError(self.name, "the compared joints are not all in one articulation in Newton's reading")
        joints = np.flatnonzero(arts == self._art)
        self._rows, self._col0 = m.joint_child.numpy()[joints], int(m.joint_qd_start.numpy()[joints[0]])

    @classmethod
    def from_urdf(cls, urdf_text: str, joint_names, frames, name: str = "newton-urdf") -> "NewtonBackend":
        return cls(urdf_text, "urdf", name, joint_names, frames)

    @classmethod
    def from_mjcf(cls, mjcf_text: str, joint_names, frames, name: str = "newton-mjcf") -> "NewtonBackend":
        return cls(mjcf_text, "mjcf", name, joint_names, frames)

    def _frame_targets(self, m) -> list[tuple[int, np.ndarray]]:
        bodies = list(m.body_label)
        shapes, flags = list(m.shape_label), m.shape_flags.numpy()
        sites = {i for i in range(len(shapes)) if flags[i] & int(newton.ShapeFlags.SITE)}
        out = []
        for frame in self.frames:
            b = _find(bodies, frame)
            s = None if b is not None else _find(shapes, frame, sites)
            if b is not None:
                out.append((b, np.eye(4)))
            elif s is not None:
                body = int(m.shape_body.numpy()[s])  # -1: a site of the world (MJCF <worldbody>), index n_body here
                out.append((self.n_body if body < 0 else body, _matrices(m.shape_transform.numpy()[s : s + 1])[0]))
            else:
                out.append(self._other_frame(m, frame, [_short(x) for x in bodies] + [_short(shapes[i]) for i in sorted(sites)]))
        return out

    def _other_frame(self, m, frame: str, known: list[str]) -> tuple[int, np.ndarray]:
        """A frame that is neither a Newton body nor a site: unknown here (a reader may know more)."""
        raise UnknownNameError("frame", frame, known)

    def _joint_q(self, q: np.ndarray) -> np.ndarray:
        """Newton's ``joint_q`` rows ``(N, n_q)`` for our configurations ``(N, n)``."""
        full = np.tile(self._q0, (len(q), 1))
        if self.floating:
            assert self._free is not None  # a floating base has its free joint
            t = base_transforms(q[:, :6])
            wxyz = matrix_to_quat(t[:, :3, :3])
            iq = self._free[0]
            full[:, iq : iq + 3], full[:, iq + 3 : iq + 6], full[:, iq + 6] = t[:, :3, 3], wxyz[:, 1:], wxyz[:, 0]
            q = q[:, 6:]
        full[:, self._iq] = q
        return full

    def _run(self, q: np.ndarray, with_jacobians: bool):
        """Body poses ``(N, B + 1, 4, 4)`` and, when asked, link Jacobians ``(N, B + 1, 6, n_qd)`` (COM
        twist); the last is the world (identity, no motion), which holds the MJCF's world sites."""
        full = self._joint_q(q)
        n = len(q)
        poses = np.tile(np.eye(4), (n, self.n_body + 1, 1, 1))  # the last: the world, for its sites
        jac = np.zeros((n, self.n_body + 1, 6, self.n_qd)) if with_jacobians else None
        buf = np.zeros((COPIES, self.n_q), dtype=np.float32)
        m, st = self.model, self.state
        for start in range(0, n, COPIES):
            rows = full[start : start + COPIES]
            k = len(rows)
            buf[:k] = rows
            m.joint_q.assign(buf.reshape(-1))
            newton.eval_fk(m, m.joint_q, m.joint_qd, st)
            body_q = st.body_q.numpy().astype(np.float64).reshape(COPIES, self.n_body, 7)[:k]
            poses[start : start + k, : self.n_body] = _matrices(body_q)
            if jac is not None:
                J = newton.eval_jacobian(m, st).numpy().astype(np.float64)[self._art :: self._n_art][:k]  # (k, links·6, dofs)
                cols = slice(self._col0, self._col0 + J.shape[2])
                jac[start : start + k, self._rows, :, cols] = J[:, : len(self._rows) * 6].reshape(k, len(self._rows), 6, -1)
        return poses, jac

    def poses(self, q: np.ndarray) -> np.ndarray:
        return self.evaluate(q, with_jacobians=False).poses

    def jacobians(self, q: np.ndarray) -> np.ndarray:
        jac = self.evaluate(q).jacobians
        assert jac is not None  # evaluated with Jacobians
        return jac

    def evaluate(self, q: np.ndarray, with_jacobians: bool = True) -> Evaluation:
        q = self._check(q)
        body_poses, body_jac = self._run(q, with_jacobians)
        bodies = [b for b, _ in self._targets]
        poses = body_poses[:, bodies] @ np.stack([t for _, t in self._targets])
        jac = None
        if with_jacobians:
            held = body_poses[:, bodies]
            com = held[..., :3, 3] + (held[..., :3, :3] @ self._com[bodies][..., None])[..., 0]
            r = poses[..., :3, 3] - com  # from the centre of mass to the frame origin
            full = body_jac[:, bodies]
            lin = full[..., :3, :] + np.cross(full[..., 3:, :], r[..., :, None], axis=-2)  # v_o = v_com + ω × r
            jac = np.concatenate([lin, full[..., 3:, :]], axis=-2)[..., self._iv]
            if self.floating:
                jac = np.concatenate([self._base_columns(q, body_poses, poses), jac], axis=-1)
        return Evaluation(self.name, self.frames, poses, jac)

    def _base_columns(self, q: np.ndarray, body_poses: np.ndarray, poses: np.ndarray) -> np.ndarray:
        """``(N, F, 6, 6)``: each frame's twist per base coordinate rate (the robot's articulation moved rigidly)."""
        assert self._free is not None  # asked of a floating base only
        p_base = body_poses[:, self._free[2], :3, 3]
        r = poses[..., :3, 3] - p_base[:, None]  # (N, F, 3)
        e = rate_matrices(q[:, :6])[:, None]  # world angular velocity per [roll, pitch, yaw] rate
        out = np.zeros(poses.shape[:2] + (6, 6))
        out[..., :3, :3] = np.eye(3)
        out[..., :3, 3:] = -np.cross(r[..., :, None], e, axis=-2)  # ω × r = −r × ω
        out[..., 3:, 3:] = e
        moved = np.isin([b for b, _ in self._targets], self._rows)  # a frame on the world or a static body: still
        return out * moved[:, None, None]

    def mass_matrix(self, q: np.ndarray) -> np.ndarray:
        """Joint-space inertia ``(N, n, n)`` (armature included) on the joints in ``joint_names``;
        fixed base only (Newton's free-joint DOFs are not kinverify's base coordinates)."""
        q = self._check(q)
        if self.floating:
            raise BackendError(self.name, "the mass matrix is compared for a fixed base only")
        full, n = self._joint_q(q), len(q)
        out = np.empty((n, len(self._iv), len(self._iv)))
        buf = np.zeros((COPIES, self.n_q), dtype=np.float32)
        m, st = self.model, self.state
        for start in range(0, n, COPIES):
            k = len(full[start : start + COPIES])
            buf[:k] = full[start : start + COPIES]
            m.joint_q.assign(buf.reshape(-1))
            newton.eval_fk(m, m.joint_q, m.joint_qd, st)
            H = newton.eval_mass_matrix(m, st).numpy().astype(np.float64)[self._art :: self._n_art][:k]
            iv = np.array(self._iv) - self._col0  # the articulation's own DOF indices
            out[start : start + k] = H[:, iv][:, :, iv]
        return out


def _short(label: str) -> str:
    """A Newton label's last part: the file's own name of the element."""
    return label.rsplit("/", 1)[-1]


def _find(labels, name: str, among=None) -> int | None:
    """Index of the label naming ``name`` (``name`` itself or a path ending ``/name``), None if none."""
    hits = [i for i, x in enumerate(labels) if (among is None or i in among) and (x == name or x.endswith("/" + name))]
    return hits[0] if hits else None


def _matrices(tf: np.ndarray) -> np.ndarray:
    """4×4 matrices ``(..., 4, 4)`` of Newton transforms ``(..., 7)`` ``[p, q xyzw]``."""
    out = np.zeros(tf.shape[:-1] + (4, 4))
    wxyz = np.concatenate([tf[..., 6:7], tf[..., 3:6]], axis=-1)
    wxyz = wxyz / np.linalg.norm(wxyz, axis=-1, keepdims=True)  # float32 quaternions: renormalised in double
    out[..., :3, :3] = quat_to_matrix(wxyz)
    out[..., :3, 3] = tf[..., :3]
    out[..., 3, 3] = 1.0
    return out
