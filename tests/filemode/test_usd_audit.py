"""The one-file audit of a USD robot: the section listing, joint by joint and body by body, what
the file states in SI units and radians (and what it leaves unset), its couplings, and the two
findings (a force bound kept only as a custom attribute; bodies with no mass), on a small stage
in half-metre and two-kilogram units."""

from __future__ import annotations

import math

import pytest

pytest.importorskip("pxr")

from kinverify.backends.usd_stage import read_robot  # noqa: E402
from kinverify.filemode.read.describe_usd import describe_usd  # noqa: E402
from kinverify.filemode.read.loading import LoadedFile  # noqa: E402
from kinverify.filemode.usd_audit import _value, statements  # noqa: E402

HEAD = '#usda 1.0\n(\n    upAxis = "Z"\n    metersPerUnit = 0.5\n    kilogramsPerUnit = 2\n)\n'
BODY = 'def Xform "{name}" (apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsMassAPI"{root}])\n{{\n{attrs}\n}}\n'
STAGE = (
    BODY.format(
        name="b0",
        root=', "PhysicsArticulationRootAPI"',
        attrs="float physics:mass = 1\npoint3f physics:centerOfMass = (0, 0, 0)\nfloat3 physics:diagonalInertia = (1, 1, 1)",
    )
    + BODY.format(name="b1", root="", attrs="float physics:mass = 1")
    + BODY.format(name="zz", root="", attrs="")
    + BODY.format(name="b3", root="", attrs="")
    + """def PhysicsFixedJoint "root"
{
rel physics:body1 = </r/b0>
}
def PhysicsRevoluteJoint "j1" (apiSchemas = ["PhysicsDriveAPI:angular"])
{
rel physics:body0 = </r/b0>
rel physics:body1 = </r/b1>
float physics:lowerLimit = -90
float physics:upperLimit = 90
float drive:angular:physics:stiffness = 2
float drive:angular:physics:maxForce = 5
float state:angular:physics:position = 90
float mjc:damping = 3
float physxJoint:maxJointVelocity = 180
custom float urdf:limit:effort = 99
}
def PhysicsPrismaticJoint "j2"
{
rel physics:body0 = </r/b1>
rel physics:body1 = </r/zz>
float newton:friction = 0
custom float urdf:limit:effort = 12.5
}
def PhysicsPrismaticJoint "j3"
{
rel physics:body0 = </r/zz>
rel physics:body1 = </r/b3>
float mjc:actuatorfrcrange:max = 4
rel newton:mimicJoint = </r/j1>
float newton:mimicCoef0 = 3
float newton:mimicCoef1 = 2
}
"""
)


@pytest.fixture(scope="module")
def described(tmp_path_factory):
    path = tmp_path_factory.mktemp("audit") / "robot.usda"
    path.write_text(HEAD + 'def Xform "r"\n{\n' + STAGE + "}\n")
    return str(path), describe_usd(read_robot(str(path)))


@pytest.fixture
def audit(described):
    """(path, description, section, findings): the audit made in each test (so that each is a test of it)."""
    path, desc = described
    loaded = LoadedFile(path, "usd", path, path, "r", ("USD: layer x.usd is absent",))
    return path, desc, *statements(desc, loaded)


def test_a_value_is_written_with_six_digits_and_its_unit():
    assert _value(None) == "unset" and _value(None, "N") == "unset"
    assert _value(math.inf, "N") == "unbounded" and _value(-math.inf) == "-inf"
    assert _value(1.23456789, "m") == "1.23457 m" and _value(1.23456789) == "1.23457" and _value(2) == "2"
    assert _value(0.0) == "0" and _value(-2.5, "N") == "-2.5 N"


def test_the_summary_names_the_joints_bodies_root_and_units(audit):
    path, _, section, _ = audit
    assert section.title == "USD: what the file states"
    assert section.summary == (
        f"{path}: 3 movable joints, 4 rigid bodies, root b0 (fixed to the world); metersPerUnit 0.5, kilogramsPerUnit 2, upAxis Z"
    )


def test_each_joint_row_says_what_the_file_states_in_si_units(audit):
    _, _, section, _ = audit
    joints = section.tables[0]
    assert joints.title == "Joints (SI units, radians; 'unset': the file leaves it to the simulator's default)"
    assert joints.columns == [
        "joint",
        "type",
        "limits",
        "force bound",
        "force bound from",
        "damping",
        "friction",
        "armature",
        "velocity limit",
        "drive (per radian)",
        "initial position",
    ]
    rows = {r[0]: r for r in joints.rows}
    assert list(rows) == ["j1", "j2", "j3"]
    # j1: force bound 5 × 2 kg × 0.25 m², damping 3 × 0.5 N·m, 180 °/s, initial 90°, a drive per radian
    assert rows["j1"] == [
        "j1",
        "revolute",
        "[-1.5708, 1.5708]",
        "2.5 N·m",
        "USD drive:angular:physics:maxForce",
        "1.5",
        "unset",
        "unset",
        "3.14159",
        "stiffness 57.2958, maxForce 2.5, type force",
        "1.5708",
    ]
    assert rows["j2"][1:4] == ["prismatic", "[-inf, unbounded]", "unset"]
    assert rows["j2"][4].startswith("no drive: urdf:limit:effort = 12.5 is a custom attribute")
    assert rows["j2"][5:] == ["unset", "0", "unset", "unset", "none", "unset"]  # a friction of 0 is stated
    assert rows["j3"][3:5] == ["4 N", "USD mjc:actuatorfrcrange"]  # 4 × 2 kg × 0.5 m


def test_each_body_row_says_whether_its_mass_and_inertia_are_stated(audit):
    _, _, section, _ = audit
    bodies = section.tables[1]
    assert bodies.title == "Rigid bodies" and bodies.columns == ["body", "mass [kg]", "centre of mass and inertia"]
    assert bodies.rows == [
        ["b0", "2", "stated"],
        ["b1", "2", "unset (derived from the colliders)"],
        ["zz", "unset (no MassAPI mass)", "unset"],
        ["b3", "unset (no MassAPI mass)", "unset"],
    ]


def test_couplings_are_listed_with_their_schema(audit):
    _, _, section, _ = audit
    assert len(section.tables) == 3 and section.tables[2].title == "Couplings"
    assert section.tables[2].columns == ["follower", "leader", "multiplier", "offset", "schema"]
    assert section.tables[2].rows == [["j3", "j1", "2", "1.5", "NewtonMimicAPI"]]  # 3 units × 0.5 m


def test_notes_are_the_loading_warnings_then_what_was_skipped(audit):
    _, desc, section, _ = audit
    assert section.notes[0] == "USD: layer x.usd is absent" and section.notes[1:] == desc.skipped
    assert "bodies leave their inertial to the simulator" in section.notes[1]


def test_a_force_bound_kept_as_a_custom_attribute_and_bodies_with_no_mass_are_found(audit):
    _, _, _, found = audit
    assert [f.kind for f in found] == ["effort_unset", "inertial_unset"]
    effort, mass = found
    assert effort.subject == "j2" and effort.property == "limits.effort"  # j1's custom effort is not its bound
    assert effort.values == {"file": "USD", "unset_in": "USD", "custom": {"j2": 12.5}}
    assert "no force bound on 1 joints" in effort.message and effort.message.endswith(": j2 12.5")
    assert "survives only as the custom attribute urdf:limit:effort, which no simulator reads" in effort.message
    assert mass.subject == "b3, zz" and mass.subject_type == "link"
    assert mass.values == {"file": "USD", "bodies": ["b3", "zz"]}
    assert "no mass for 2 bodies" in mass.message and mass.message.endswith("colliders' volume): b3, zz")


def test_a_floating_robot_with_every_value_stated_has_no_coupling_table_and_no_finding(tmp_path):
    path = tmp_path / "float.usda"
    text = (
        HEAD
        + 'def Xform "r"\n{\n'
        + BODY.format(name="a", root=', "PhysicsArticulationRootAPI"', attrs="float physics:mass = 1")
        + BODY.format(name="b", root="", attrs="float physics:mass = 1")
        + 'def PhysicsRevoluteJoint "j"\n{\nrel physics:body0 = </r/a>\nrel physics:body1 = </r/b>\n}\n}\n'
    )
    path.write_text(text)
    desc = describe_usd(read_robot(str(path)))
    section, found = statements(desc, LoadedFile(str(path), "usd", str(path), str(path), "r"))
    assert found == [] and len(section.tables) == 2
    assert "root a (floating)" in section.summary
    assert section.tables[0].rows[0][3:5] == ["unset", "no drive and no force range in the USD"]
