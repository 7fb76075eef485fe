"""Drake's reading of an SDFormat file as a :class:`~kinverify.filemode.read.model.ModelDesc` (the
same description Pinocchio gives of a URDF and MuJoCo of an MJCF; Drake is the only reader of
SDFormat here): movable 1-DOF joints in chain order with their world axis lines at q = 0, limits,
damping, armature (Drake's reflected inertia) and effort; links and ``<frame>`` elements with their
world poses at q = 0; each link's inertial in its own frame and in the world. Drake models no
Coulomb joint friction (``friction`` None). Root links are welded to the world (a free body is
held at the identity, as file mode holds a floating base)."""

from __future__ import annotations

import numpy as np

from kinverify.backends import backend_info
from kinverify.filemode.read.model import INF, BodyInertial, JointDesc, ModelDesc, inertial_world


def describe_sdf(sdf_text: str, source: str = "sdf") -> ModelDesc:
    """Drake's reading of the SDFormat text (or of a URDF, ``source`` "urdf", that only Drake reads),
    every joint at 0; ``RuntimeError`` when Drake refuses it or the ``drake`` extra is not installed."""
    info = backend_info(f"drake-{source}")
    if not info.available:
        raise RuntimeError(f"Drake is not installed ({info.reason})")
    plant, _, warnings = info.backend_class.load_plant(sdf_text, source, name=f"drake-{source}")
    ctx = plant.CreateDefaultContext()
    plant.SetPositions(ctx, np.zeros(plant.num_positions()))
    world = plant.world_frame()
    joints = [plant.get_joint(j) for j in plant.GetJointIndices()]
    movable = {j.child_body().index(): j for j in joints if j.num_positions() == 1 and j.num_velocities() == 1}
    parent_of = {j.child_body().index(): j.parent_body().index() for j in joints}
    skipped = [
        f"{j.name()}: {j.type_name()} joint with {j.num_positions()} coordinates; only 1-DOF joints are compared (held at 0)"
        for j in joints
        if j.num_positions() > 1
    ]
    held = [j.name() for j in joints if j.num_positions() > 1]
    world_index = plant.world_body().index()

    def owner(body) -> str | None:
        while body != world_index:
            if body in movable:
                return movable[body].name()
            body = parent_of.get(body, world_index)
        return None

    def depth(body) -> int:
        d = 0
        while body != world_index:
            body, d = parent_of.get(body, world_index), d + 1
        return d

    effort = {}
    for a in plant.GetJointActuatorIndices():
        actuator = plant.get_joint_actuator(a)
        effort[actuator.joint().name()] = (float(actuator.effort_limit()), float(actuator.default_reflected_inertia()))
    frames, owners, depths, kinds = {}, {}, {}, {}
    bodies = []
    joint_frames = {f.index() for j in joints for f in (j.frame_on_parent(), j.frame_on_child())}
    for b in range(1, plant.num_bodies()):
        body = plant.get_body(type(world_index)(b))
        name, index = body.name(), body.index()
        pose = plant.CalcRelativeTransform(ctx, world, body.body_frame()).GetAsMatrix4()
        frames[name], owners[name], depths[name], kinds[name] = pose, owner(index), depth(index), "link"
        mass = float(body.default_mass())
        if mass > 0:
            inertia = body.default_spatial_inertia()
            com = np.array(inertia.get_com(), dtype=float)
            about_com = inertia.Shift(com).CalcRotationalInertia().CopyToFullMatrix3()
            com_w, ine_w = inertial_world(pose, com, about_com)
            bodies.append(BodyInertial(owner(index), mass, com_w, ine_w, name, com, about_com))
    for f in range(plant.num_frames()):
        frame = plant.get_frame(type(plant.world_frame().index())(f))
        if (
            frame.name() in frames
            or frame.index() in joint_frames
            or frame.is_ephemeral()
            or frame.index() == world.index()
            or frame.name() in ("", "__model__")
        ):
            continue  # a link's own frame, a joint's, one Drake made, the world, the model frame
        body = frame.body().index()
        frames[frame.name()] = plant.CalcRelativeTransform(ctx, world, frame).GetAsMatrix4()
        owners[frame.name()], depths[frame.name()], kinds[frame.name()] = owner(body), depth(body) + 1, "site"
    described = []
    for body in sorted(movable, key=depth):
        j = movable[body]
        x_wf = plant.CalcRelativeTransform(ctx, world, j.frame_on_parent()).GetAsMatrix4()
        revolute = j.type_name() == "revolute"
        axis = np.array(j.revolute_axis() if revolute else j.translation_axis(), dtype=float)
        axis = x_wf[:3, :3] @ axis
        lo, up = float(j.position_lower_limits()[0]), float(j.position_upper_limits()[0])
        force, reflected = effort.get(j.name(), (None, 0.0))
        vel = float(j.velocity_upper_limits()[0])
        described.append(
            JointDesc(
                j.name(),
                "revolute" if revolute else "prismatic",
                owner(j.parent_body().index()),
                j.child_body().name(),
                j.parent_body().name(),
                axis / np.linalg.norm(axis),
                x_wf[:3, 3].copy(),
                lo if abs(lo) < 1e300 else -INF,
                up if abs(up) < 1e300 else INF,  # a URDF continuous joint: ±1e308 (prepare_urdf) or ±inf
                damping=float(j.default_damping()),
                friction=None,
                armature=reflected,
                effort=force,
                velocity=vel if np.isfinite(vel) else None,
                effort_how="SDFormat <limit><effort> (Drake's actuator)" if force is not None else "no actuator in Drake's model",
            )
        )
    skipped += [f"Drake: {w}" for w in warnings]
    gravity = np.array(plant.gravity_field().gravity_vector(), dtype=float)
    return ModelDesc(source, "drake", described, frames, owners, depths, bodies, skipped, kinds, [], gravity, held=held)
