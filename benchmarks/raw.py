"""The "raw" loops the overhead is measured against: the simplest loop a user would write with
each library (its FK and Jacobian calls, copying every frame's pose and Jacobian into a
preallocated numpy array), on the backends' own loaded models so the work is the same."""

from __future__ import annotations

import mujoco
import numpy as np
import pinocchio as pin


def raw_pinocchio(backend, q: np.ndarray) -> None:
    model, data, fids = backend.model, backend.data, backend._frame_ids
    full_q = backend._full_q(q)
    poses = np.empty((len(q), len(fids), 4, 4))
    jac = np.empty((len(q), len(fids), 6, model.nv))
    for k in range(len(q)):
        pin.computeJointJacobians(model, data, full_q[k])
        pin.updateFramePlacements(model, data)
        for f, fid in enumerate(fids):
            poses[k, f] = data.oMf[fid].homogeneous
            jac[k, f] = pin.getFrameJacobian(model, data, fid, pin.LOCAL_WORLD_ALIGNED)


def raw_mujoco(backend, q: np.ndarray) -> None:
    m, d = backend.model, backend.data
    poses = np.zeros((len(q), len(backend.frames), 4, 4))
    jac = np.empty((len(q), len(backend.frames), 6, m.nv))
    jacp, jacr = np.zeros((3, m.nv)), np.zeros((3, m.nv))
    for k in range(len(q)):
        d.qpos[backend._qadr] = q[k]
        mujoco.mj_kinematics(m, d)
        mujoco.mj_comPos(m, d)
        for f, (is_site, oid) in enumerate(backend._targets):
            if is_site:
                poses[k, f, :3, :3] = d.site_xmat[oid].reshape(3, 3)
                poses[k, f, :3, 3] = d.site_xpos[oid]
                mujoco.mj_jacSite(m, d, jacp, jacr, oid)
            else:
                poses[k, f, :3, :3] = d.xmat[oid].reshape(3, 3)
                poses[k, f, :3, 3] = d.xpos[oid]
                mujoco.mj_jacBody(m, d, jacp, jacr, oid)
            jac[k, f, :3] = jacp
            jac[k, f, 3:] = jacr


def raw_yourdfpy(backend, q: np.ndarray) -> None:
    robot, root = backend.robot, backend._root
    poses = np.empty((len(q), len(backend.frames), 4, 4))
    cfg = np.zeros(len(robot.actuated_joint_names))
    for k in range(len(q)):
        cfg[backend._order] = q[k]
        robot.update_cfg(cfg)
        for f, frame in enumerate(backend.frames):
            poses[k, f] = robot.get_transform(frame, root)


def raw_analytic(backend, q: np.ndarray) -> None:
    """kinverify's own batched numpy FK + Jacobian is the "library" here: the raw call is itself."""
    backend.evaluate(q)


def raw_for(backend):
    name = backend.name
    if name.startswith("pinocchio"):
        return raw_pinocchio
    if name == "mujoco":
        return raw_mujoco
    if name == "yourdfpy":
        return raw_yourdfpy
    return raw_analytic
