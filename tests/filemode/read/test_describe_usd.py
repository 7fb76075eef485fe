"""pxr's reading of a USD robot as file mode's description, pinned value by value on small .usda
stages written here: units (metersPerUnit 0.1, kilogramsPerUnit 3, so that a torque unit k·m² =
0.03, a force unit k·m = 0.3 and a mass unit k = 3 differ), degrees, each attribute's fallback
order, drives, force bounds, couplings, inertials, the tree's owners and depths, the single
precision bound and the authored poses that disagree with the joint frames."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("pxr")

from kinverify.backends.usd_stage import read_robot  # noqa: E402
from kinverify.filemode.read.describe_usd import (  # noqa: E402
    F32,
    _get,
    _inertial,
    _number,
    describe_usd,
    joint_values,
    pose_mismatches,
    usd_precision,
)

M, K = 0.1, 3.0  # metersPerUnit, kilogramsPerUnit of the stages below
TORQUE, FORCE = K * M * M, K * M
DEG = math.pi / 180
HEAD = f'#usda 1.0\n(\n    upAxis = "Z"\n    metersPerUnit = {M}\n    kilogramsPerUnit = {K}\n)\n'


def seven(x: float) -> float:
    """``x`` to 7 significant digits (a single-precision value per degree, per radian)."""
    return float(f"{x:.7g}")


def body(name: str, attrs: str = "", root: bool = False) -> str:
    api = '"PhysicsRigidBodyAPI", "PhysicsMassAPI"' + (', "PhysicsArticulationRootAPI"' if root else "")
    return f'def Xform "{name}" (apiSchemas = [{api}])\n{{\n{attrs}\n}}\n'


def joint(name: str, kind: str, b0: str | None, b1: str, attrs: str = "", schemas: tuple = ()) -> str:
    listed = ", ".join('"' + s + '"' for s in schemas)
    api = f" (apiSchemas = [{listed}])" if schemas else ""
    rels = (f"rel physics:body0 = </r/{b0}>\n" if b0 else "") + f"rel physics:body1 = </r/{b1}>\n"
    return f'def Physics{kind}Joint "{name}"{api}\n{{\n{rels}{attrs}\n}}\n'


def chain(names: list[str], root_joint: bool = True) -> str:
    """Bodies b0..bn (b0 the articulation root, mass 1 each) and, when ``root_joint``, b0 fixed to the world."""
    out = "".join(body(b, "float physics:mass = 1", root=i == 0) for i, b in enumerate(names))
    return out + (joint("root", "Fixed", None, names[0]) if root_joint else "")


def stage(folder, name: str, *prims: str, head: str = HEAD):
    path = folder / f"{name}.usda"
    path.write_text(head + 'def Xform "r"\n{\n' + "".join(prims) + "}\n")
    return read_robot(str(path))


# --- joint values ------------------------------------------------------------------------------

J1 = """uniform token physics:axis = "Z"
float physics:lowerLimit = -90
float physics:upperLimit = 120
float drive:angular:physics:stiffness = 2
float drive:angular:physics:damping = 4
float drive:angular:physics:maxForce = 5
float drive:angular:physics:targetPosition = 30
float drive:angular:physics:targetVelocity = 10
uniform token drive:angular:physics:type = "acceleration"
float state:angular:physics:position = 20
float newton:damping = 6
float newton:friction = 7
float mjc:damping = 100
float mjc:frictionloss = 100
float physxJoint:armature = 8
float newton:armature = 9
float mjc:armature = 10
float physxJoint:maxJointVelocity = 90
float newton:velocityLimit = 45
float physxJoint:jointFriction = 0.5
float mjc:actuatorfrcrange:max = 1000
custom float urdf:limit:effort = 12"""

J2 = """uniform token physics:axis = "X"
float drive:linear:physics:stiffness = 1.2345679
float drive:linear:physics:maxForce = inf
float drive:linear:physics:targetPosition = 0.2
float state:linear:physics:position = 0.5
double newton:damping = 1.23456789
float mjc:frictionloss = 2
float newton:armature = 9
float mjc:armature = 10
float newton:velocityLimit = 0.5"""

J3 = """float physics:upperLimit = 10
float mjc:actuatorfrcrange:min = -4
float mjc:actuatorfrcrange:max = 3
float mjc:damping = 5
float mjc:armature = 2"""

J4 = """float physics:lowerLimit = -10
float mjc:actuatorfrcrange:max = 3
token mjc:actuatorfrclimited = "false"
custom float urdf:limit:effort = 12"""

J5 = """float mjc:actuatorfrcrange:min = -3
token mjc:actuatorfrclimited = "true"
float newton:friction = 0.1"""

J6 = """float physxJoint:maxJointVelocity = inf
float newton:velocityLimit = 45
float mjc:actuatorfrcrange:max = 3"""

J7 = """float mjc:actuatorfrcrange:max = -5
token mjc:actuatorfrclimited = "0"
double mjc:damping = 1.23456789"""

J8 = """float mjc:actuatorfrcrange:max = -0.5
token mjc:actuatorfrclimited = "auto"
double newton:damping = 1.23456789"""


@pytest.fixture(scope="module")
def chain8(tmp_path_factory):
    """A chain of eight joints (read once; each test reads its values, so that each is a test of them)."""
    bodies = [f"b{i}" for i in range(9)]
    joints = [
        joint("j1", "Revolute", "b0", "b1", J1, ("PhysicsDriveAPI:angular",)),
        joint("j2", "Prismatic", "b1", "b2", J2, ("PhysicsDriveAPI:linear",)),
        joint("j3", "Revolute", "b2", "b3", J3),
        joint("j4", "Revolute", "b3", "b4", J4),
        joint("j5", "Revolute", "b4", "b5", J5),
        joint("j6", "Revolute", "b5", "b6", J6, ("PhysicsDriveAPI:angular",)),
        joint("j7", "Revolute", "b6", "b7", J7),
        joint("j8", "Prismatic", "b7", "b8", J8),
    ]
    return stage(tmp_path_factory.mktemp("values"), "values", chain(bodies), *joints)


@pytest.fixture
def values(chain8):
    """Each joint's values (``joint_values``), keyed by joint name."""
    return {j.name: joint_values(chain8, j) for j in chain8.joints if j.kind != "fixed"}


def test_an_angular_drive_is_read_per_radian_in_si_units(values):
    drive = values["j1"]["drive"]
    assert drive["stiffness"] == seven(2 * TORQUE / DEG) and drive["damping"] == seven(4 * TORQUE / DEG)
    assert drive["stiffness"] == pytest.approx(3.437747, rel=1e-6)  # 2 × 0.03 N·m per degree
    assert drive["maxForce"] == pytest.approx(5 * TORQUE, rel=1e-12)
    assert drive["targetPosition"] == pytest.approx(30 * DEG, rel=1e-12)
    assert drive["targetVelocity"] == pytest.approx(10 * DEG, rel=1e-12)
    assert drive["type"] == "acceleration"


def test_a_linear_drive_is_read_per_metre_in_si_units(values):
    drive = values["j2"]["drive"]
    # per metre: force unit / length unit = k; not rounded to 7 digits (no degree in it)
    assert drive["stiffness"] == pytest.approx(1.2345679 * K, rel=1e-12)
    assert drive["damping"] is None and drive["targetVelocity"] is None
    assert drive["maxForce"] == math.inf
    assert drive["targetPosition"] == pytest.approx(0.2 * M, rel=1e-12)
    assert drive["type"] == "force"


def test_a_drive_with_no_value_authored_leaves_them_unset_and_is_a_force_drive(values):
    drive = values["j6"]["drive"]
    assert drive == {
        "stiffness": None,
        "damping": None,
        "maxForce": None,
        "targetPosition": None,
        "targetVelocity": None,
        "type": "force",
    }
    assert values["j3"]["drive"] is None


def test_the_force_bound_comes_from_the_drive_else_the_mjc_force_range(values):
    v = values
    assert v["j1"]["effort"] == pytest.approx(5 * TORQUE, rel=1e-12)  # the drive's, not the force range's 1000
    assert v["j1"]["effort_how"] == "USD drive:angular:physics:maxForce"
    assert v["j2"]["effort"] == math.inf and v["j2"]["effort_how"] == "USD drive:linear:physics:maxForce"
    assert v["j6"]["effort"] == math.inf
    assert v["j6"]["effort_how"] == "USD PhysicsDriveAPI:angular without maxForce (unbounded)"
    assert v["j3"]["effort"] == pytest.approx(4 * TORQUE, rel=1e-12)  # max(|-4|, |3|) N·m units
    assert v["j3"]["effort_how"] == "USD mjc:actuatorfrcrange"
    assert v["j8"]["effort"] == pytest.approx(0.5 * FORCE, rel=1e-12)  # no min (0), a negative max, "auto" limited
    assert v["j8"]["effort_how"] == "USD mjc:actuatorfrcrange"


def test_no_force_bound_is_read_from_a_range_turned_off_or_without_max(values):
    v = values
    assert v["j4"]["effort"] is None and v["j7"]["effort"] is None and v["j5"]["effort"] is None
    assert v["j4"]["effort_how"] == "no drive: urdf:limit:effort = 12 is a custom attribute no simulator reads"
    assert v["j5"]["effort_how"] == "no drive and no force range in the USD"
    assert v["j7"]["effort_how"] == "no drive and no force range in the USD"
    assert v["j4"]["custom_effort"] == 12.0 and v["j1"]["custom_effort"] == 12.0 and v["j5"]["custom_effort"] is None


def test_damping_newton_per_degree_else_mjc_per_radian(values):
    v = values
    assert v["j1"]["damping"] == seven(6 * TORQUE / DEG)  # newton:damping, per degree, wins over mjc:damping
    assert v["j2"]["damping"] == pytest.approx(1.23456789 * K, rel=1e-12)  # linear: per metre, all its digits
    assert v["j3"]["damping"] == pytest.approx(5 * TORQUE, rel=1e-12)  # mjc:damping: already per radian
    assert v["j7"]["damping"] == pytest.approx(1.23456789 * TORQUE, rel=1e-12)
    assert v["j8"]["damping"] == pytest.approx(1.23456789 * K, rel=1e-12)
    assert v["j4"]["damping"] is None


def test_friction_armature_and_velocity_follow_their_fallback_order(values):
    v = values
    assert v["j1"]["friction"] == pytest.approx(7 * TORQUE, rel=1e-12)  # newton:friction over mjc:frictionloss
    assert v["j2"]["friction"] == pytest.approx(2 * FORCE, rel=1e-12)  # mjc:frictionloss
    assert v["j5"]["friction"] == pytest.approx(0.1 * TORQUE, rel=1e-12)
    assert v["j4"]["friction"] is None
    assert v["j1"]["armature"] == pytest.approx(8 * TORQUE, rel=1e-12)  # physxJoint first
    assert v["j2"]["armature"] == pytest.approx(9 * K, rel=1e-12)  # then newton, linear: mass units
    assert v["j3"]["armature"] == pytest.approx(2 * TORQUE, rel=1e-12)  # then mjc
    assert v["j4"]["armature"] is None
    assert v["j1"]["velocity"] == 1.570796  # physxJoint:maxJointVelocity 90 °/s, to 7 digits
    assert v["j2"]["velocity"] == pytest.approx(0.5 * M, rel=1e-12)
    assert v["j6"]["velocity"] is None  # an infinite physxJoint bound: no bound (newton's is not looked at)
    assert v["j3"]["velocity"] is None


def test_initial_positions_physx_friction_and_range(values):
    v = values
    assert v["j1"]["initial"] == pytest.approx(20 * DEG, rel=1e-12)
    assert v["j2"]["initial"] == pytest.approx(0.5 * M, rel=1e-12)
    assert v["j3"]["initial"] is None
    assert v["j1"]["physx_friction"] == 0.5 and v["j2"]["physx_friction"] is None
    assert [v[f"j{i}"]["range"] for i in range(1, 6)] == [True, False, True, True, False]


def test_a_number_is_an_authored_scalar_float_as_written(tmp_path):
    attrs = 'float a = 0.1\ndouble b = 0.1\ntoken c = "abc"\nfloat3 d = (1, 2, 3)\nfloat e\nstring s = "2.5"'
    robot = stage(tmp_path, "n", body("b0", attrs, root=True), joint("root", "Fixed", None, "b0"))
    prim = robot.stage.GetPrimAtPath("/r/b0")
    assert _number(prim, "a") == 0.1 and _number(prim, "b") == 0.1  # a float as written, not 0.10000000149
    assert _number(prim, "c") is None and _number(prim, "d") is None and _number(prim, "e") is None
    assert _number(prim, "s") == 2.5 and _number(prim, "absent") is None
    assert _get(prim, "e") is None and _get(prim, "absent") is None and _get(prim, "c") == "abc"


# --- couplings -----------------------------------------------------------------------------------

MIMICS = [
    joint("lead", "Revolute", "b0", "b1"),
    joint(
        "n1",
        "Revolute",
        "b1",
        "b2",
        "rel newton:mimicJoint = </r/lead>\nfloat newton:mimicCoef0 = 10\nfloat newton:mimicCoef1 = -2",
        ("NewtonMimicAPI",),
    ),
    joint("n2", "Revolute", "b2", "b3", "rel newton:mimicJoint = </r/lead>\nbool newton:mimicEnabled = false"),
    joint("n3", "Revolute", "b3", "b4", "rel newton:mimicJoint = </r/lead>\nbool newton:mimicEnabled = true"),
    joint("n4", "Prismatic", "b4", "b5", "rel newton:mimicJoint = </r/lead>\nfloat newton:mimicCoef0 = 3"),
    joint(
        "p1",
        "Revolute",
        "b5",
        "b6",
        "rel physxMimicJoint:rotX:referenceJoint = </r/lead>\n"
        "float physxMimicJoint:rotX:gearing = -0.5\nfloat physxMimicJoint:rotX:offset = 30",
        ("PhysicsDriveAPI:angular", "PhysxMimicJointAPI:rotX"),
    ),
    joint(
        "p2",
        "Prismatic",
        "b6",
        "b7",
        "rel physxMimicJoint:transY:referenceJoint = </r/n4>\nfloat physxMimicJoint:transY:offset = 2",
        ("PhysxMimicJointAPI:transY",),
    ),
    joint(  # newton names a body, not a joint: the PhysX schema is read instead
        "p3",
        "Revolute",
        "b7",
        "b8",
        "rel newton:mimicJoint = </r/b0>\nrel physxMimicJoint:rotZ:referenceJoint = </r/lead>\n"
        "float physxMimicJoint:rotZ:gearing = 2",
        ("PhysxMimicJointAPI:rotZ",),
    ),
    joint(  # no reference joint, a reference that is no joint
        "p4",
        "Revolute",
        "b8",
        "b9",
        "float physxMimicJoint:rotX:gearing = 2\nrel physxMimicJoint:rotY:referenceJoint = </r/b1>",
        ("PhysxMimicJointAPI:rotX", "PhysxMimicJointAPI:rotY"),
    ),
    joint("fixed", "Fixed", "b9", "b10", "rel newton:mimicJoint = </r/lead>"),  # not movable: no coupling
    joint(  # an instance name with a namespace: all of it after the schema's name
        "p5",
        "Revolute",
        "b10",
        "b11",
        "rel physxMimicJoint:rot:X:referenceJoint = </r/lead>\nfloat physxMimicJoint:rot:X:gearing = 3",
        ("PhysxMimicJointAPI:rot:X",),
    ),
]


@pytest.fixture(scope="module")
def mimic_robot(tmp_path_factory):
    bodies = [f"b{i}" for i in range(12)]
    return stage(tmp_path_factory.mktemp("mimic"), "mimic", chain(bodies), *MIMICS)


@pytest.fixture
def mimic(mimic_robot):
    return describe_usd(mimic_robot)


def test_couplings_of_both_schemas_with_their_defaults_and_units(mimic):
    got = {c.follower: (c.leader, c.multiplier, c.offset, c.source) for c in mimic.couplings}
    assert got == {
        "n1": ("lead", -2.0, pytest.approx(10 * DEG, rel=1e-12), "NewtonMimicAPI"),
        "n3": ("lead", 1.0, 0.0, "NewtonMimicAPI"),  # no coefficients: follower = leader
        "n4": ("lead", 1.0, pytest.approx(3 * M, rel=1e-12), "NewtonMimicAPI"),  # a prismatic offset in stage units
        "p1": ("lead", 0.5, pytest.approx(-30 * DEG, rel=1e-12), "PhysxMimicJointAPI"),
        "p2": ("n4", -0.0, pytest.approx(-2 * M, rel=1e-12), "PhysxMimicJointAPI"),
        "p3": ("lead", -2.0, 0.0, "PhysxMimicJointAPI"),
        "p5": ("lead", -3.0, 0.0, "PhysxMimicJointAPI"),
    }


# --- inertials ----------------------------------------------------------------------------------

INERTIALS = {
    "plain": "float physics:mass = 1",
    "full": "float physics:mass = 2\npoint3f physics:centerOfMass = (1, 2, 3)\nfloat3 physics:diagonalInertia = (4, 5, 6)\n"
    "quatf physics:principalAxes = (0, 0.70710677, 0.70710677, 0)",
    "zero": "float physics:mass = 0",
    "none": "",
    "nancom": "float physics:mass = 1\npoint3f physics:centerOfMass = (nan, 0, 0)\nfloat3 physics:diagonalInertia = (1, 1, 1)",
    "nodiag": "float physics:mass = 1\npoint3f physics:centerOfMass = (1, 0, 0)\nfloat3 physics:diagonalInertia = (0, 0, 0)",
    "onediag": "float physics:mass = 1\npoint3f physics:centerOfMass = (1, 0, 0)\nfloat3 physics:diagonalInertia = (0, 0, 2)",
    "nocom": "float physics:mass = 1\nfloat3 physics:diagonalInertia = (1, 1, 1)",
    "quarter": "float physics:mass = 1\npoint3f physics:centerOfMass = (0, 0, 0)\nfloat3 physics:diagonalInertia = (4, 5, 6)\n"
    "quatf physics:principalAxes = (0.70710677, 0, 0, 0.70710677)",
    "identity": "float physics:mass = 1\npoint3f physics:centerOfMass = (0, 0, 0)\nfloat3 physics:diagonalInertia = (4, 5, 6)\n"
    "quatf physics:principalAxes = (1, 0, 0, 0)",
}


@pytest.fixture(scope="module")
def masses(tmp_path_factory):
    names = list(INERTIALS)
    prims = [body(n, INERTIALS[n], root=i == 0) for i, n in enumerate(names)] + [joint("root", "Fixed", None, names[0])]
    prims += [joint(f"j{i}", "Revolute", a, b) for i, (a, b) in enumerate(zip(names, names[1:], strict=False))]
    return stage(tmp_path_factory.mktemp("masses"), "masses", *prims)


POSE = np.array([[0.0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]])  # a quarter turn about z, moved by (1, 2, 3)


def test_a_stated_inertial_in_si_units_turned_by_its_principal_axes_and_taken_to_the_world(masses):
    inertial, why = _inertial(masses, "/r/full", POSE, "j0")
    assert why == "" and inertial.owner == "j0" and inertial.name == "full" and inertial.com_known
    assert inertial.mass == pytest.approx(2 * K, rel=1e-12)
    assert inertial.com_local == pytest.approx([0.1, 0.2, 0.3], rel=1e-7)
    # principal axes: half a turn about (x + y)/√2 swaps x and y
    assert inertial.inertia_local == pytest.approx(np.diag([5.0, 4, 6]) * K * M * M, abs=1e-7)
    assert inertial.com == pytest.approx([1 - 0.2, 2 + 0.1, 3 + 0.3], rel=1e-7)
    assert inertial.inertia == pytest.approx(np.diag([4.0, 5, 6]) * K * M * M, abs=1e-7)  # the quarter turn swaps back


@pytest.mark.parametrize(
    "name, inertia",
    [("quarter", np.diag([5.0, 4, 6])), ("identity", np.diag([4.0, 5, 6])), ("onediag", np.diag([0.0, 0, 2]))],
)
def test_principal_axes_turn_the_diagonal_inertia(masses, name, inertia):
    inertial, why = _inertial(masses, f"/r/{name}", np.eye(4), None)
    assert why == "" and inertial.com_known and inertial.inertia_local == pytest.approx(inertia * K * M * M, abs=1e-7)


def test_a_body_with_no_mass_leaves_it_to_the_simulator(masses):
    for name in ("zero", "none"):
        assert _inertial(masses, f"/r/{name}", np.eye(4), None) == (
            None,
            f"{name}: no MassAPI mass (the simulator derives it from the colliders)",
        )


@pytest.mark.parametrize("name", ["plain", "nancom", "nodiag", "nocom"])
def test_a_mass_with_no_usable_centre_of_mass_or_inertia_is_compared_alone(masses, name):
    inertial, why = _inertial(masses, f"/r/{name}", POSE, "j")
    assert not inertial.com_known and inertial.mass == pytest.approx(K, rel=1e-12)
    assert why == f"{name}: mass 3 kg with no centre of mass or inertia (derived from the colliders)"
    assert inertial.com_local == pytest.approx([0, 0, 0]) and inertial.com == pytest.approx([1, 2, 3])
    assert np.all(inertial.inertia_local == 0) and np.all(inertial.inertia == 0)


# --- the description: tree, owners, sites, skipped ---------------------------------------------

TREE = [
    body("b0", "float physics:mass = 1", root=True),
    body("b1", "float physics:mass = 1"),
    body("b2", "float physics:mass = 0"),
    body("b3", "float physics:mass = 1"),
    body("b4", ""),
    body(
        "b5",
        'float physics:mass = 1\ndef Xform "tool"\n{\ndouble3 xformOp:translate = (0, 0, 2)\n'
        'uniform token[] xformOpOrder = ["xformOp:translate"]\n}\n'
        'def Xform "tip" (apiSchemas = ["MjcSiteAPI"])\n{\n}\n',
    ),
    joint("root", "Fixed", None, "b0", "point3f physics:localPos0 = (0, 0, 3)\npoint3f physics:localPos1 = (1, 0, 0)"),
    joint(
        "j1",
        "Revolute",
        "b0",
        "b1",
        'uniform token physics:axis = "X"\npoint3f physics:localPos0 = (0, 0, 1)\n'
        "quatf physics:localRot0 = (0.70710677, 0, 0, 0.70710677)\n"
        "float physics:lowerLimit = -90\nfloat physics:upperLimit = 120\nfloat newton:damping = 1\n"
        "float newton:friction = 1\nfloat newton:armature = 1\nfloat mjc:actuatorfrcrange:max = 1\n"
        "float physxJoint:maxJointVelocity = 90",
    ),
    joint(  # runs from the child (body0) to the parent (body1): flipped
        "jflip",
        "Revolute",
        "b2",
        "b1",
        'uniform token physics:axis = "Y"\npoint3f physics:localPos1 = (2, 0, 0)\nfloat state:angular:physics:position = 5',
    ),
    joint("jsph", "Spherical", "b1", "b3"),
    joint("jfix", "Fixed", "b2", "b4", "point3f physics:localPos0 = (0, 1, 0)"),
    joint(
        "j5",
        "Prismatic",
        "b4",
        "b5",
        'uniform token physics:axis = "Z"\ncustom float urdf:limit:effort = 7\nfloat physxJoint:jointFriction = 0.3',
    ),
]


@pytest.fixture(scope="module")
def tree_robot(tmp_path_factory):
    return stage(tmp_path_factory.mktemp("tree"), "tree", *TREE)


@pytest.fixture
def tree(tree_robot):
    return tree_robot, describe_usd(tree_robot)


def test_each_movable_joint_with_its_world_axis_line_parent_and_child(tree):
    desc = tree[1]
    assert [j.name for j in desc.joints] == ["j1", "jflip", "j5"]
    j1, flip, j5 = desc.joints
    assert (j1.type, j1.parent, j1.child, j1.parent_frame) == ("revolute", None, "b1", "b0")
    assert j1.axis == pytest.approx([0, 1, 0], abs=1e-7)  # X turned a quarter about z
    assert j1.anchor == pytest.approx([-0.1, 0, 0.4], abs=1e-7)  # root 0.3 up and 0.1 back, the joint 0.1 above it
    assert (j1.lower, j1.upper) == pytest.approx((-math.pi / 2, 2 * math.pi / 3), rel=1e-7)
    assert (flip.parent, flip.child, flip.parent_frame) == ("j1", "b2", "b1")
    # the joint frame is b1's localPos1 (2, 0, 0) units; the tree runs against the joint: its axis reversed
    assert flip.axis == pytest.approx([1, 0, 0], abs=1e-7)  # -(b1's y, world -x)
    assert flip.anchor == pytest.approx([-0.1, 0.2, 0.4], abs=1e-7)
    assert (j5.type, j5.parent, j5.child, j5.parent_frame) == ("prismatic", "jflip", "b5", "b4")


def test_joint_values_and_what_each_joint_states(tree):
    j1, flip, j5 = tree[1].joints
    assert j1.damping == seven(TORQUE / DEG) and j1.friction == pytest.approx(TORQUE) and j1.armature == pytest.approx(TORQUE)
    assert j1.effort == pytest.approx(TORQUE) and j1.effort_how == "USD mjc:actuatorfrcrange" and j1.stiffness is None
    assert j1.stated == {"damping", "friction", "armature", "effort", "range"}
    assert (flip.damping, flip.friction, flip.armature, flip.effort, flip.velocity) == (0.0, 0.0, 0.0, None, None)
    assert flip.stated == frozenset() and j5.stated == frozenset()
    assert "urdf:limit:effort = 7" in j5.effort_how
    ext = tree[1].extensions
    assert j1.velocity == 1.570796 and ext["j1"] == {"velocity": 1.570796} and ext["jflip"] == {"initial": pytest.approx(5 * DEG)}
    assert ext["j5"] == {"custom_effort": 7.0, "physx_friction": pytest.approx(0.3)}


def test_frames_owners_and_depths_of_bodies_and_sites(tree):
    robot, desc = tree
    assert desc.frame_owner == {"b0": None, "b1": "j1", "b2": "jflip", "b3": "j1", "b4": "jflip", "b5": "j5"} | {
        "tool": "j5",
        "tip": "j5",
        "r": None,  # the Xform holding the robot, under no body: fixed in the world (the root's frame)
    }
    assert desc.frame_depth == {"b0": 0, "b1": 1, "b2": 2, "b3": 2, "b4": 3, "b5": 4, "tool": 5, "tip": 5, "r": 1}
    assert desc.frame_kind == {"b0": "link", "b1": "link", "b2": "link", "b3": "link", "b4": "link", "b5": "link"} | {
        "tool": "link",
        "tip": "site",
        "r": "link",
    }
    assert desc.frames["tool"] == pytest.approx(desc.frames["b5"] @ robot.sites["tool"][1])
    assert desc.frames["tool"][:3, 3] - desc.frames["b5"][:3, 3] == pytest.approx([0, 0, 0.2], abs=1e-7)
    assert desc.frames["b0"][:3, 3] == pytest.approx([-0.1, 0, 0.3])


def test_the_description_names_held_joints_and_bodies_with_no_inertial(tree):
    robot, desc = tree
    assert (desc.kind, desc.library, desc.native) == ("usd", "usd-core", robot)
    assert desc.held == ["jsph"]
    assert desc.skipped[0] == "jsph: spherical joint; only 1-DOF joints are compared (held at 0)"
    assert desc.skipped[1].startswith("6 bodies leave their inertial to the simulator: b0: mass 3 kg with no centre")
    assert "; b2: no MassAPI mass" in desc.skipped[1] and "; b4: no MassAPI mass" in desc.skipped[1]
    assert desc.skipped[2:] == robot.notes
    assert desc.no_inertial == {"b2", "b4"}
    assert sorted(b.name for b in desc.bodies) == ["b0", "b1", "b3", "b5"]
    assert desc.body("b1").owner == "j1" and desc.body("b3").owner == "j1" and desc.body("b5").owner == "j5"
    assert desc.couplings == [] and desc.gravity == pytest.approx([0, 0, -9.81])


def test_a_d6_joint_is_held(tmp_path):
    desc = describe_usd(
        stage(tmp_path, "d6", chain(["b0", "b1", "b2"]), joint("free6", "", "b0", "b1"), joint("j", "Revolute", "b1", "b2"))
    )
    assert desc.held == ["free6"] and desc.skipped[0] == "free6: d6 joint; only 1-DOF joints are compared (held at 0)"
    assert [j.name for j in desc.joints] == ["j"] and desc.joints[0].parent is None


# --- single precision -------------------------------------------------------------------------


def test_single_precision_bounds_add_up_along_the_tree(tree):
    robot = tree[0]
    p = usd_precision(robot)
    s3 = math.sqrt(3) * F32
    root = (8 * F32, s3 * (0.3 + 0.1))  # the root's joint to the world: localPos0 (0, 0, 3), localPos1 (1, 0, 0) units
    b1 = (root[0] + 8 * F32, root[1] + s3 * 0.1)
    b2 = (b1[0] + 8 * F32, b1[1] + s3 * 0.2)  # jflip: localPos1 (2, 0, 0)
    b4 = (b2[0] + 8 * F32, b2[1] + s3 * 0.1)
    assert p.frames["b0"] == pytest.approx(root, rel=1e-9) and p.frames["b1"] == pytest.approx(b1, rel=1e-9)
    assert p.frames["b2"] == pytest.approx(b2, rel=1e-9) and p.frames["b4"] == pytest.approx(b4, rel=1e-9)
    assert p.frames["b3"] == pytest.approx((b1[0] + 8 * F32, b1[1]), rel=1e-9)
    assert p.frames["tool"] == p.frames["b5"] == pytest.approx((b4[0] + 8 * F32, b4[1]), rel=1e-9)
    assert p.limit == pytest.approx(2 * math.pi / 3 * F32, rel=1e-6)  # the largest finite limit, 120°
    assert (p.relative, p.inertial_angle, p.angle) == (2 * F32, 8 * F32, 8 * F32)
    assert p.com == 0.0  # no body's xform is authored: every one at the origin
    assert p.examples == dict.fromkeys(("limit", "relative", "inertial_angle", "angle"), "float32")
    assert p.describe() == "the USD writes single-precision numbers (float, point3f, quatf: about 7 significant digits)"


def test_a_floating_root_is_exact_and_the_centre_of_mass_bound_grows_with_reach(tmp_path):
    moved = 'float physics:mass = 1\ndouble3 xformOp:translate = (3, 4, 0)\nuniform token[] xformOpOrder = ["xformOp:translate"]'
    robot = stage(
        tmp_path,
        "floating",
        body("b0", "float physics:mass = 1", root=True),
        body("b1", moved),
        joint("j", "Revolute", "b0", "b1", "point3f physics:localPos0 = (3, 4, 0)"),
    )
    p = usd_precision(robot)
    assert robot.floating and p.frames["b0"] == (0.0, 0.0)
    assert p.frames["b1"] == pytest.approx((8 * F32, math.sqrt(3) * F32 * 0.5), rel=1e-9)
    assert p.com == pytest.approx(0.5 * F32, rel=1e-9) and p.limit == 0.0
    assert pose_mismatches(robot) == []


# --- authored poses against the joint frames ----------------------------------------------------


def xform(translate: str, orient: str = "(1, 0, 0, 0)", mass: str = "float physics:mass = 1") -> str:
    return (
        f"{mass}\ndouble3 xformOp:translate = {translate}\nquatd xformOp:orient = {orient}\n"
        'uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:orient"]'
    )


Q90 = "(0.7071067811865476, 0, 0, 0.7071067811865476)"


@pytest.fixture(scope="module")
def posed(tmp_path_factory):
    """Everything moved by (5, 0, 0) (the root's pose is taken as given); b1 turned a quarter and b2
    slid 2 units by their joints' initial positions (where they are authored); b3 0.1 units off;
    b4 turned by a quaternion of length 0.99; b5 turned by 0.002 rad."""
    small = f"({math.cos(0.001)!r}, 0, 0, {math.sin(0.001)!r})"
    prims = [
        body("b0", xform("(5, 0, 0)"), root=True),
        body("b1", xform("(5, 0, 1)", Q90)),
        body("b2", xform("(5, 3, 1)", Q90)),
        body("b3", xform("(5.1, 3, 2)", Q90)),
        body("b4", xform("(5, 3, 3)", "(0.7, 0, 0, 0.7)")),
        body("b5", xform("(5, 3, 4)", small)),
        joint("root", "Fixed", None, "b0"),
        joint(
            "j1",
            "Revolute",
            "b0",
            "b1",
            'uniform token physics:axis = "Z"\npoint3f physics:localPos0 = (0, 0, 1)\nfloat state:angular:physics:position = 90',
        ),
        joint(
            "j2",
            "Prismatic",
            "b1",
            "b2",
            'uniform token physics:axis = "X"\npoint3f physics:localPos0 = (1, 0, 0)\nfloat state:linear:physics:position = 2',
        ),
        joint("j3", "Revolute", "b2", "b3", "point3f physics:localPos0 = (0, 0, 1)"),
        joint(
            "j4",
            "Fixed",
            "b3",
            "b4",
            "point3f physics:localPos0 = (0, 0, 1)\nquatf physics:localRot0 = (0.70710677, 0, 0, -0.70710677)",
        ),
        joint("j5", "Revolute", "b4", "b5", "point3f physics:localPos0 = (0, 0, 1)"),
    ]
    return stage(tmp_path_factory.mktemp("posed"), "posed", *prims)


def test_bodies_authored_elsewhere_than_their_joint_frames_put_them(posed):
    found = {b.split(" (")[0]: (b, p, r) for b, p, r in pose_mismatches(posed)}
    assert sorted(found) == ["b3", "b4", "b5"]  # b1 and b2 sit where their initial positions put them
    assert found["b3"][0] == "b3" and found["b3"][1] == pytest.approx(0.01, rel=1e-6) and found["b3"][2] < 1e-6
    name, pos, rot = found["b4"]
    assert "b4 (its xformOp:orient is not a unit quaternion, |q| = 0.989949494: pxr reads it as a turn)" == name
    assert pos < 1e-6 and rot > 0.01
    assert found["b5"][0] == "b5" and found["b5"][1] < 1e-6 and found["b5"][2] == pytest.approx(0.002, rel=1e-4)


def test_the_first_body_after_the_root_is_checked_too(tmp_path):
    moved = 'float physics:mass = 1\ndouble3 xformOp:translate = (0, 0, 2)\nuniform token[] xformOpOrder = ["xformOp:translate"]'
    robot = stage(
        tmp_path,
        "first",
        body("b0", "float physics:mass = 1", root=True),
        body("b1", moved),
        joint("j", "Revolute", "b0", "b1", "point3f physics:localPos0 = (0, 0, 1)"),
    )
    assert pose_mismatches(robot) == [("b1", pytest.approx(0.1, rel=1e-9), 0.0)]


def test_a_body_is_named_only_beyond_twice_its_single_precision_bound(tmp_path):
    """Floating root (exact); b1, b2 hang 0.5 m out (bound: √3·F32·0.5 m plus 8·F32 rad times 0.5 m),
    b3, b4, b5 at the root's origin (bound: 8·F32 rad, no length). Offsets at 1.25 and 0.8 times
    twice the bound: the first named, the second not."""
    allowed_pos = 2 * (math.sqrt(3) * F32 * 0.5 + 8 * F32 * 0.5)
    allowed_rot = 2 * 8 * F32

    def turned(angle: float) -> str:
        return xform("(0, 0, 0)", f"({math.cos(angle / 2)!r}, 0, 0, {math.sin(angle / 2)!r})")

    prims = [
        body("b0", xform("(0, 0, 0)"), root=True),
        body("b1", xform(f"({3 + 1.25 * allowed_pos / M!r}, 4, 0)")),
        body("b2", xform(f"({3 + 0.8 * allowed_pos / M!r}, 4, 0)")),
        body("b3", turned(1.25 * allowed_rot)),
        body("b4", turned(0.8 * allowed_rot)),
        body("b5", xform("(0, 0, 0)")),
    ]
    prims += [joint(f"j{i}", "Revolute", "b0", f"b{i}", "point3f physics:localPos0 = (3, 4, 0)") for i in (1, 2)]
    prims += [joint(f"j{i}", "Revolute", "b0", f"b{i}") for i in (3, 4, 5)]
    found = pose_mismatches(stage(tmp_path, "bounds", *prims))
    assert [b for b, _, _ in found] == ["b1", "b3"]
    assert found[0][1] == pytest.approx(1.25 * allowed_pos, rel=0.05) and found[1][2] == pytest.approx(
        1.25 * allowed_rot, rel=0.05
    )


def test_a_rotation_that_agrees_is_reported_as_none_not_as_rounding_beyond_one(tmp_path):
    """A body turned 74° about z as its joint frame says, moved 0.01 m: its rotation offset is 0
    (the cosine, computed a rounding above 1, is clipped), never NaN."""
    q = f"({math.cos(math.radians(37))!r}, 0, 0, {math.sin(math.radians(37))!r})"
    robot = stage(
        tmp_path,
        "agree",
        body("b0", xform("(0, 0, 0)"), root=True),
        body("b1", xform("(0.1, 0, 1)", q)),
        joint("j", "Revolute", "b0", "b1", f"point3f physics:localPos0 = (0, 0, 1)\nquatf physics:localRot0 = {q}"),
    )
    assert pose_mismatches(robot) == [("b1", pytest.approx(0.01, rel=1e-6), 0.0)]
