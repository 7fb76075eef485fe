"""An SDFormat file as a :class:`~kinverify.map.side.Side`: as Drake's plant gives it when Drake is
installed (its joint order, each joint's ``position_start``/``velocity_start``, its joint
actuators in their order with effort limit, reflected inertia (an armature) and PD controller
gains, the joints' default positions and damping), else in SDFormat declaration order from the
XML (``<axis><limit effort velocity>``, ``<axis><dynamics damping friction>``). Drake models no
Coulomb joint friction; couplings (``<mimic>``) are not read."""

from __future__ import annotations

from kinverify.backends import backend_info
from kinverify.errors import InputError, library_reason
from kinverify.filemode.read.describe_sdf import describe_sdf
from kinverify.filemode.read.loading import load_sdf
from kinverify.map.side import Actuator, MapJoint, Side

MOVABLE = {"revolute": "revolute", "continuous": "revolute", "prismatic": "prismatic"}


def read_sdf(path: str, options) -> Side:
    loaded = load_sdf(path)
    info = backend_info("drake-sdf")
    if not info.available:
        return declared_sdf(path, loaded)
    try:
        plant, _, warnings = info.backend_class.load_plant(loaded.text, "sdf", name="drake-sdf")
        desc = describe_sdf(loaded.text)
    except (RuntimeError, ValueError) as err:
        raise InputError(f"{path}: Drake cannot load it: {library_reason(err)}") from None
    joints, by_name = [], {}
    for index in plant.GetJointIndices():
        joint = plant.get_joint(index)
        if joint.num_positions() != 1 or joint.num_velocities() != 1 or joint.type_name() not in MOVABLE:
            continue
        j = MapJoint(
            joint.name(),
            MOVABLE[joint.type_name()],
            int(joint.position_start()),
            int(joint.velocity_start()),
            default=float(joint.default_positions()[0]),
            driven=False,
            joint_damping=float(joint.default_damping()),
            how={"default": "Drake's default position"},
        )
        velocity = float(joint.velocity_upper_limits()[0])
        if velocity < 1e300:
            j.velocity, j.how["velocity"] = velocity, "<limit velocity>"
        joints.append(j)
        by_name[j.name] = j
    actuators = []
    for a in plant.GetJointActuatorIndices():
        act = plant.get_joint_actuator(a)
        mj = by_name.get(act.joint().name())
        if mj is None:
            continue
        mj.driven, mj.mode = True, "Drake joint actuator"
        if act.effort_limit() < 1e300:
            mj.effort, mj.how["effort"] = float(act.effort_limit()), "Drake actuator effort limit"
        reflected = float(act.default_reflected_inertia())
        mj.armature, mj.how["armature"] = reflected, "Drake reflected inertia (rotor inertia × gear ratio²)"
        if act.has_controller():
            gains = act.get_controller_gains()
            mj.stiffness, mj.damping = float(gains.p()), float(gains.d())
            mj.how["stiffness"] = mj.how["damping"] = "drake:controller_gains"
        actuators.append(Actuator(act.name(), (mj.name,), "Drake joint actuator"))
    expresses = frozenset({"default", "effort", "velocity", "armature", "joint_damping", "stiffness", "damping"})
    notes = [f"Drake: {w}" for w in warnings]
    return Side(path, path, "sdf", "Drake plant order", joints, actuators, expresses, desc, notes)


def declared_sdf(path: str, loaded) -> Side:
    """Without Drake: the joints in SDFormat declaration order, their values as written."""
    joints = []
    for el in loaded.tree.iter("joint"):
        if el.get("type") not in MOVABLE:
            continue
        j = MapJoint(el.get("name"), MOVABLE[el.get("type")])
        for name, where in (
            ("effort", "axis/limit/effort"),
            ("velocity", "axis/limit/velocity"),
            ("joint_damping", "axis/dynamics/damping"),
            ("friction", "axis/dynamics/friction"),
            ("default", "axis/initial_position"),
        ):
            text = el.findtext(where)
            if text is not None and text.strip():
                setattr(j, name, float(text))
                j.how[name] = f"<{where}>"
        joints.append(j)
    notes = [
        "Drake is not installed: SDFormat declaration order, values as written (install the drake extra for "
        "Drake's order and actuators)"
    ]
    return Side(
        path,
        path,
        "sdf",
        "SDFormat declaration order",
        joints,
        None,
        frozenset({"effort", "velocity", "joint_damping", "friction"}),
        None,
        notes,
    )
