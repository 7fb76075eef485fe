"""MuJoCo on the generated MJCF: body frames and sites."""

from __future__ import annotations

import mujoco
import numpy as np

from kinverify.errors import BackendError, UnknownNameError, library_reason
from kinverify.model.floating import base_transforms, has_base, velocity_map
from kinverify.model.transforms import matrix_to_quat
from kinverify.backends.base import EvaluatingBackend, Evaluation


class MujocoBackend(EvaluatingBackend):
    """Frame FK and Jacobians from an ``mujoco.MjModel``.

    Native convention: ``xpos``/``xmat`` (row-major 3×3) are world poses of body frames,
    ``site_xpos``/``site_xmat`` of sites; ``mj_jacBody``/``mj_jacSite`` give ``jacp``, ``jacr``
    (3×nv) centred at the frame origin and aligned with the world — stacked here as [jacp; jacr].
    A free joint on a top-level body is a floating base: ``qpos = [xyz, quat wxyz]`` (its world
    pose), ``qvel`` its world linear and body angular velocity, converted to the base
    coordinates of :mod:`kinverify.model.floating`. Joints not in ``joint_names`` stay at ``qpos0``.
    """

    def __init__(self, model: "mujoco.MjModel", name: str, joint_names, frames) -> None:
        self.model, self.data, self.name = model, mujoco.MjData(model), name
        self.joint_names, self.frames = tuple(joint_names), tuple(frames)
        joints = [model.joint(i).name for i in range(model.njnt)]
        self._qadr, self._vadr = [], []
        self.floating = has_base(self.joint_names)
        if self.floating:
            free = [
                j
                for j in range(model.njnt)
                if int(model.jnt_type[j]) == int(mujoco.mjtJoint.mjJNT_FREE) and model.body_parentid[model.jnt_bodyid[j]] == 0
            ]
            if len(free) != 1:
                raise BackendError(
                    name,
                    "the configuration has a floating base but the model has "
                    f"{len(free)} free joints on top-level bodies (expected one)",
                )
            self._free = (int(model.jnt_qposadr[free[0]]), int(model.jnt_dofadr[free[0]]))
        for joint in self.joint_names[6 if self.floating else 0 :]:
            jid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint)
            if jid < 0:
                raise UnknownNameError("joint", joint, joints)
            if int(model.jnt_type[jid]) not in (int(mujoco.mjtJoint.mjJNT_HINGE), int(mujoco.mjtJoint.mjJNT_SLIDE)):
                raise BackendError(name, f"joint {joint!r} is not a hinge or slide joint")
            self._qadr.append(model.jnt_qposadr[jid])
            self._vadr.append(model.jnt_dofadr[jid])
        self._targets = []  # (is_site, id) per frame
        for frame in self.frames:
            bid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, frame)
            sid = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, frame)
            if bid < 0 and sid < 0:
                names = [model.body(i).name for i in range(model.nbody)] + [model.site(i).name for i in range(model.nsite)]
                raise UnknownNameError("frame", frame, names)
            self._targets.append((bid < 0, sid if bid < 0 else bid))

    @classmethod
    def from_mjcf(cls, mjcf_text: str, joint_names, frames, name: str = "mujoco") -> "MujocoBackend":
        try:
            model = mujoco.MjModel.from_xml_string(mjcf_text)
        except ValueError as err:
            raise BackendError(name, f"cannot load MJCF: {library_reason(err)}") from None
        return cls(model, name, joint_names, frames)

    @classmethod
    def from_urdf(cls, urdf_text: str, joint_names, frames, name: str = "mujoco-urdf") -> "MujocoBackend":
        """MuJoCo's own URDF import (see :func:`urdf_for_mujoco`)."""
        try:
            model = mujoco.MjModel.from_xml_string(urdf_for_mujoco(urdf_text))
        except ValueError as err:
            raise BackendError(name, f"cannot load URDF: {library_reason(err)}") from None
        return cls(model, name, joint_names, frames)

    def frame_kinematics(self, frame_index: int):
        """Per-configuration IK path for ``frames[frame_index]``: ``(fk, log3)`` with ``fk(q (n,)) ->
        (R (3, 3), p (3,), J (6, n))``: ``mj_kinematics``, ``mj_comPos`` and one ``mj_jacBody`` or
        ``mj_jacSite`` (not every frame's). R and p are views of ``MjData``, valid until the next call."""
        from kinverify.ik.single import log3

        m, d = self.model, self.data
        site, oid = self._targets[frame_index]
        rot = (d.site_xmat if site else d.xmat)[oid].reshape(3, 3)
        pos = (d.site_xpos if site else d.xpos)[oid]
        jac_full = np.zeros((6, m.nv))
        jacp, jacr = jac_full[:3], jac_full[3:]
        jac_fn = mujoco.mj_jacSite if site else mujoco.mj_jacBody
        kin, com_pos = mujoco.mj_kinematics, mujoco.mj_comPos
        qpos, qadr, vadr = d.qpos, np.asarray(self._qadr, dtype=int), np.asarray(self._vadr, dtype=int)
        qpos[:] = m.qpos0
        whole = self._vadr == list(range(m.nv))

        def fk(q):
            qpos[qadr] = q
            kin(m, d)
            com_pos(m, d)
            jac_fn(m, d, jacp, jacr, oid)
            return rot, pos, jac_full if whole else jac_full[:, vadr]

        return fk, log3

    def evaluate(self, q: np.ndarray, with_jacobians: bool = True) -> Evaluation:
        # Lean loop: body and site poses copied with one fancy index each per
        # configuration (d.xpos[ids], d.xmat[ids]); Jacobians written by mj_jacBody/mj_jacSite
        # straight into contiguous rows of the output; joint columns selected once per batch.
        q = self._check(q)
        m, d = self.model, self.data
        n_cfg, n_frames = q.shape[0], len(self.frames)
        bodies = [(f, oid) for f, (site, oid) in enumerate(self._targets) if not site]
        sites = [(f, oid) for f, (site, oid) in enumerate(self._targets) if site]
        bf, bid = [f for f, _ in bodies], [o for _, o in bodies]
        sf, sid = [f for f, _ in sites], [o for _, o in sites]
        rot = np.empty((n_cfg, n_frames, 9))
        pos = np.empty((n_cfg, n_frames, 3))
        full = np.empty((n_cfg, n_frames, 6, m.nv)) if with_jacobians else None
        kin, com_pos, jac_body, jac_site = mujoco.mj_kinematics, mujoco.mj_comPos, mujoco.mj_jacBody, mujoco.mj_jacSite
        qpos, xpos, xmat, site_xpos, site_xmat = d.qpos, d.xpos, d.xmat, d.site_xpos, d.site_xmat
        qpos[:] = m.qpos0
        qadr = np.asarray(self._qadr, dtype=int)
        joints = q
        if self.floating:  # the free joint's qpos: the base's world pose, quaternion wxyz
            t = base_transforms(q[:, :6])
            free = np.concatenate([t[:, :3, 3], matrix_to_quat(t[:, :3, :3])], axis=1)
            joints = q[:, 6:]
        for k in range(n_cfg):
            if self.floating:
                qpos[self._free[0] : self._free[0] + 7] = free[k]
            qpos[qadr] = joints[k]
            kin(m, d)
            if bid:
                rot[k, bf] = xmat[bid]
                pos[k, bf] = xpos[bid]
            if sid:
                rot[k, sf] = site_xmat[sid]
                pos[k, sf] = site_xpos[sid]
            if with_jacobians:
                com_pos(m, d)  # cdof, needed by the Jacobian functions
                assert full is not None  # made whenever with_jacobians
                jk = full[k]
                for f, oid in bodies:
                    jac_body(m, d, jk[f, :3], jk[f, 3:], oid)
                for f, oid in sites:
                    jac_site(m, d, jk[f, :3], jk[f, 3:], oid)
        poses = np.zeros((n_cfg, n_frames, 4, 4))
        poses[..., :3, :3] = rot.reshape(n_cfg, n_frames, 3, 3)
        poses[..., :3, 3] = pos
        poses[..., 3, 3] = 1.0
        jac = None
        if with_jacobians:
            assert full is not None
            jac = full if self._vadr == list(range(m.nv)) else full[..., self._vadr]
            if self.floating:  # free joint: world linear, body angular velocity
                iv = self._free[1]
                base = full[..., iv : iv + 6] @ velocity_map(q[:, :6], linear_in_body=False)[:, None]
                jac = np.concatenate([base, jac], axis=-1)
        return Evaluation(self.name, self.frames, poses, jac)


MUJOCO_MESH_FORMATS = (".stl", ".obj", ".msh")


def urdf_for_mujoco(urdf_text: str) -> str:
    """The URDF with the ``<mujoco><compiler>`` extension MuJoCo's URDF import reads: keep fixed
    links as bodies (``fusestatic="false"``) so every URDF link stays a frame."""
    import xml.etree.ElementTree as ET

    try:
        root = ET.fromstring(urdf_text)
    except ET.ParseError as err:
        raise ValueError(f"not XML: {err}") from None
    for ext in root.findall("mujoco"):
        root.remove(ext)
    for link in root.iter("link"):  # MuJoCo reads STL, OBJ and MSH meshes only (not e.g. COLLADA .dae)
        for el in list(link):
            mesh = el.find("geometry/mesh")
            if mesh is not None and not mesh.get("filename", "").lower().endswith(MUJOCO_MESH_FORMATS):
                link.remove(el)
    ET.SubElement(ET.SubElement(root, "mujoco"), "compiler", fusestatic="false", discardvisual="true")
    return ET.tostring(root, encoding="unicode")
