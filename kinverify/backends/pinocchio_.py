"""Pinocchio (PyPI ``pin``) on the generated URDF or, through its MJCF parser, on the MJCF."""

from __future__ import annotations

import os
import sys
import tempfile

import numpy as np
import pinocchio as pin

from kinverify.errors import BackendError, UnknownNameError, library_reason
from kinverify.model.floating import base_transforms, has_base, velocity_map
from kinverify.model.transforms import matrix_to_quat
from kinverify.backends.base import EvaluatingBackend, Evaluation


# A URDF may name a joint and a link alike: a frame name is looked up with its type, links first.
FRAME_TYPES = (pin.FrameType.BODY, pin.FrameType.OP_FRAME, pin.FrameType.FIXED_JOINT, pin.FrameType.JOINT, pin.FrameType.SENSOR)


def frame_id(model: "pin.Model", name: str) -> int:
    """Id of the frame ``name``: the link (BODY frame) of that name if there is one, else the
    operational frame, fixed joint, joint or sensor; :class:`UnknownNameError` when none."""
    for kind in FRAME_TYPES:
        if model.existFrame(name, kind):
            return model.getFrameId(name, kind)
    raise UnknownNameError("frame", name, list(dict.fromkeys(f.name for f in model.frames)))


def build_urdf_model(urdf_text: str) -> "pin.Model":
    """``pin.buildModelFromXML`` that keeps the reason of a refusal: urdfdom, Pinocchio's URDF
    parser, prints why on the process's stderr and raises only "The XML stream does not contain a
    valid URDF model". What it prints during the call is read back and joined into the
    ``ValueError`` (:func:`~kinverify.errors.library_reason`); on success it is passed on to descriptor 2."""
    sys.stderr.flush()
    saved, failure = os.dup(2), None
    with tempfile.TemporaryFile() as printed:
        os.dup2(printed.fileno(), 2)
        try:
            model = pin.buildModelFromXML(urdf_text)
        except (ValueError, RuntimeError) as err:
            failure = err
        finally:
            os.dup2(saved, 2)
            os.close(saved)
        printed.seek(0)
        said = printed.read().decode("utf-8", "replace")
    if failure is None:
        if said:  # passed on to descriptor 2, where it was going (kept off the terminal during a command)
            os.write(2, said.encode())
        return model
    raise ValueError("; ".join(r for r in (library_reason(said), library_reason(failure)) if r))


class PinocchioBackend(EvaluatingBackend):
    """Frame FK and Jacobians from a ``pin.Model``.

    Native convention: ``data.oMf[i]`` is ``T_world_from_frame``; ``getFrameJacobian`` with
    ``LOCAL_WORLD_ALIGNED`` is ``[linear; angular]``, world axes, at the frame origin — already ours.
    A floating root is a ``JointModelFreeFlyer``: ``q = [xyz, quat xyzw]`` placed at its joint
    placement, ``v`` the base's body-frame twist, converted to the base coordinates of
    :mod:`kinverify.model.floating`. Joints of the model not in ``joint_names`` are held at their
    neutral value.
    """

    def __init__(self, model: "pin.Model", name: str, joint_names, frames) -> None:
        self.model, self.data, self.name = model, model.createData(), name
        self.joint_names, self.frames = tuple(joint_names), tuple(frames)
        available = [model.names[i] for i in range(1, model.njoints)]
        self._idx_q, self._idx_v = [], []
        self.floating = has_base(self.joint_names)
        if self.floating:
            root = next((i for i in range(1, model.njoints) if model.parents[i] == 0), None)
            if root is None or model.joints[root].shortname() != "JointModelFreeFlyer":
                raise BackendError(name, "the configuration has a floating base but the model's root joint is not floating")
            self._ff = (model.joints[root].idx_q, model.joints[root].idx_v, model.jointPlacements[root].inverse().homogeneous)
        for joint in self.joint_names[6 if self.floating else 0 :]:
            if not model.existJointName(joint):
                raise UnknownNameError("joint", joint, available)
            jmodel = model.joints[model.getJointId(joint)]
            if jmodel.nq != 1:
                raise BackendError(name, f"joint {joint!r} has {jmodel.nq} coordinates; only 1-DOF joints are compared")
            self._idx_q.append(jmodel.idx_q)
            self._idx_v.append(jmodel.idx_v)
        self._frame_ids = [frame_id(model, f) for f in self.frames]
        self._neutral = pin.neutral(model)

    @classmethod
    def from_urdf(cls, urdf_text: str, joint_names, frames, name: str = "pinocchio-urdf") -> "PinocchioBackend":
        try:
            model = build_urdf_model(urdf_text)
        except ValueError as err:
            raise BackendError(name, f"cannot load URDF: {library_reason(err)}") from None
        return cls(model, name, joint_names, frames)

    @classmethod
    def from_mjcf(cls, mjcf_text: str, joint_names, frames, name: str = "pinocchio-mjcf") -> "PinocchioBackend":
        # buildModelFromMJCF reads only from a file path.
        fd, path = tempfile.mkstemp(suffix=".xml", prefix="kinverify-")
        try:
            with os.fdopen(fd, "w") as handle:
                handle.write(mjcf_text)
            model = pin.buildModelFromMJCF(path)
        except (ValueError, RuntimeError) as err:
            raise BackendError(name, f"cannot load MJCF: {library_reason(err)}") from None
        finally:
            os.unlink(path)
        return cls(model, name, joint_names, frames)

    def _full_q(self, q: np.ndarray) -> np.ndarray:
        full = np.tile(self._neutral, (q.shape[0], 1))
        if self.floating:
            iq, _, placement_inv = self._ff
            t = placement_inv @ base_transforms(q[:, :6])  # the free-flyer's own motion
            full[:, iq : iq + 3] = t[:, :3, 3]
            full[:, iq + 3 : iq + 7] = np.roll(matrix_to_quat(t[:, :3, :3]), -1, axis=-1)  # wxyz -> xyzw
            q = q[:, 6:]
        full[:, self._idx_q] = q
        return full

    def _columns(self, full: np.ndarray, q: np.ndarray) -> np.ndarray:
        """Our Jacobian columns from the model's ``(N, F, 6, nv)``: the joints', after the base's
        converted from the free-flyer's body twist."""
        joints = full[..., self._idx_v]
        if not self.floating:
            return joints
        iv = self._ff[1]
        base = full[..., iv : iv + 6] @ velocity_map(q[:, :6], linear_in_body=True)[:, None]
        return np.concatenate([base, joints], axis=-1)

    def frame_kinematics(self, frame_index: int):
        """Per-configuration IK path for ``frames[frame_index]``: ``(fk, log3)`` with ``fk(q (n,)) ->
        (R (3, 3), p (3,), J (6, n))`` from one ``computeFrameJacobian`` (which also places the
        frame). R and p are live views of ``data.oMf`` (pinocchio returns it by reference): valid
        until the next call. Joints outside ``joint_names`` (e.g. a gripper) are locked at neutral
        in a reduced model, so each call computes only the compared joints."""
        if self.floating:
            raise BackendError(self.name, "IK's one-frame path does not take a floating base (IK is not run for one)")
        model, fid = self.model, self._frame_ids[frame_index]
        if self._idx_q != list(range(model.nq)) or self._idx_v != list(range(model.nv)):
            keep = {model.getJointId(j) for j in self.joint_names}
            model = pin.buildReducedModel(model, [i for i in range(1, model.njoints) if i not in keep], self._neutral)
            fid = frame_id(model, self.frames[frame_index])
            if [model.names[i] for i in range(1, model.njoints)] != list(self.joint_names) or model.nq != model.nv:
                raise BackendError(self.name, "IK needs the compared joints in the model's order, one coordinate each")
        data = model.createData()
        cfj, lwa = pin.computeFrameJacobian, pin.LOCAL_WORLD_ALIGNED
        placement = data.oMf[fid]
        rot, pos = placement.rotation, placement.translation

        def fk(q, inner=None):  # the wrappers' signature (inner unused)
            return rot, pos, cfj(model, data, q, fid, lwa)

        if model.nv == 1:  # computeFrameJacobian returns a (6,) vector then

            def fk(q, inner=fk):
                r, p, jac = inner(q)
                return r, p, jac.reshape(6, 1)

        fk(pin.neutral(model))
        if not np.array_equal(pos, data.oMf[fid].translation):  # not by reference in this pin: fetch it

            def fk(q, inner=fk):
                jac = inner(q)[2]
                return data.oMf[fid].rotation, data.oMf[fid].translation, jac

        return fk, pin.log3

    def evaluate(self, q: np.ndarray, with_jacobians: bool = True) -> Evaluation:
        # Lean loop: bound functions, results written straight into preallocated
        # arrays, joint columns selected once per batch rather than per frame.
        q = self._check(q)
        model, data, oMf = self.model, self.data, self.data.oMf
        frames = list(enumerate(self._frame_ids))
        n_cfg = q.shape[0]
        poses = np.empty((n_cfg, len(frames), 4, 4))
        if with_jacobians:
            full = np.empty((n_cfg, len(frames), 6, model.nv))
            # with nv == 1 getFrameJacobian returns a (6,) vector: write through a (..., 6) view
            target = full[..., 0] if model.nv == 1 else full
            cjj, ufp, gfj, lwa = (
                pin.computeJointJacobians,
                pin.updateFramePlacements,
                pin.getFrameJacobian,
                pin.LOCAL_WORLD_ALIGNED,
            )
            for k, qk in enumerate(self._full_q(q)):
                cjj(model, data, qk)  # also runs forward kinematics
                ufp(model, data)
                pk, jk = poses[k], target[k]
                for f, fid in frames:
                    pk[f] = oMf[fid].homogeneous
                    jk[f] = gfj(model, data, fid, lwa)
            jac = full if self._idx_v == list(range(model.nv)) and not self.floating else self._columns(full, q)
        else:
            jac, ffk = None, pin.framesForwardKinematics
            for k, qk in enumerate(self._full_q(q)):
                ffk(model, data, qk)
                pk = poses[k]
                for f, fid in frames:
                    pk[f] = oMf[fid].homogeneous
        return Evaluation(self.name, self.frames, poses, jac)
