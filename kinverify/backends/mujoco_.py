"""MuJoCo on the generated MJCF: body frames and sites."""

from __future__ import annotations

import mujoco
import numpy as np

from ..errors import BackendError, UnknownNameError
from .base import BackendBase, Evaluation


class MujocoBackend(BackendBase):
    """Frame FK and Jacobians from an ``mujoco.MjModel``.

    Native convention: ``xpos``/``xmat`` (row-major 3×3) are world poses of body frames,
    ``site_xpos``/``site_xmat`` of sites; ``mj_jacBody``/``mj_jacSite`` give ``jacp``, ``jacr``
    (3×nv) centred at the frame origin and aligned with the world — stacked here as [jacp; jacr].
    Joints not in ``joint_names`` stay at ``qpos0``.
    """

    def __init__(self, model: "mujoco.MjModel", name: str, joint_names, frames) -> None:
        self.model, self.data, self.name = model, mujoco.MjData(model), name
        self.joint_names, self.frames = tuple(joint_names), tuple(frames)
        joints = [model.joint(i).name for i in range(model.njnt)]
        self._qadr, self._vadr = [], []
        for joint in self.joint_names:
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
            raise BackendError(name, f"cannot load MJCF: {str(err).strip().splitlines()[0]}") from None
        return cls(model, name, joint_names, frames)

    @classmethod
    def from_urdf(cls, urdf_text: str, joint_names, frames, name: str = "mujoco-urdf") -> "MujocoBackend":
        """MuJoCo's own URDF import (see :func:`urdf_for_mujoco`)."""
        try:
            model = mujoco.MjModel.from_xml_string(urdf_for_mujoco(urdf_text))
        except ValueError as err:
            raise BackendError(name, f"cannot load URDF: {str(err).strip().splitlines()[0]}") from None
        return cls(model, name, joint_names, frames)

    def poses(self, q: np.ndarray) -> np.ndarray:
        return self.evaluate(q, with_jacobians=False).poses

    def jacobians(self, q: np.ndarray) -> np.ndarray:
        return self.evaluate(q).jacobians

    def evaluate(self, q: np.ndarray, with_jacobians: bool = True) -> Evaluation:
        q = self._check(q)
        m, d = self.model, self.data
        n_cfg = q.shape[0]
        poses = np.zeros((n_cfg, len(self.frames), 4, 4))
        poses[..., 3, 3] = 1.0
        jac = np.empty((n_cfg, len(self.frames), 6, len(self._vadr))) if with_jacobians else None
        jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
        d.qpos[:] = m.qpos0
        for k in range(n_cfg):
            d.qpos[self._qadr] = q[k]
            mujoco.mj_kinematics(m, d)
            if with_jacobians:
                mujoco.mj_comPos(m, d)  # cdof, needed by the Jacobian functions
            for f, (is_site, oid) in enumerate(self._targets):
                if is_site:
                    poses[k, f, :3, :3] = d.site_xmat[oid].reshape(3, 3)
                    poses[k, f, :3, 3] = d.site_xpos[oid]
                else:
                    poses[k, f, :3, :3] = d.xmat[oid].reshape(3, 3)
                    poses[k, f, :3, 3] = d.xpos[oid]
                if with_jacobians:
                    (mujoco.mj_jacSite if is_site else mujoco.mj_jacBody)(m, d, jacp, jacr, oid)
                    jac[k, f, :3] = jacp[:, self._vadr]
                    jac[k, f, 3:] = jacr[:, self._vadr]
        return Evaluation(self.name, self.frames, poses, jac)


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
    ET.SubElement(ET.SubElement(root, "mujoco"), "compiler", fusestatic="false", discardvisual="true")
    return ET.tostring(root, encoding="unicode")
