"""One file's dynamics in two libraries (a one-file audit): Pinocchio against MuJoCo's URDF import
on a URDF, MuJoCo against Pinocchio's MJCF parser on an MJCF with the top-level pose it drops put
back as the direction of gravity; the section names the two libraries; an inertial MuJoCo's URDF
import reads otherwise is one error per link, by what differs first (mass, centre, tensor)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.backends import ModelSources
from kinverify.errors import BackendError
from kinverify.filemode.compare.audit_dynamics import AuditDynamicsSuite, _relabel, inertial_findings
from kinverify.filemode.compare.crosscheck import top_level_pose
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.run import VerifyOptions
from kinverify.suites.base import Section, Table, VerifyContext

JOINTS = ("joint1", "joint2", "joint3")
Q = np.random.default_rng(5).uniform(-1, 1, (4, 3))
OPTIONS = VerifyOptions(extra={"dynamics_samples": 3})


def context(q=Q) -> VerifyContext:
    return VerifyContext(ModelSources("arm3", JOINTS, (), (-1.0,) * 3, (1.0,) * 3, (True,) * 3), {}, q, OPTIONS)


@pytest.fixture(scope="module")
def arm3():
    return P.generated_pair("arm3")


def test_the_title_names_the_file_and_its_two_libraries_reference_first():
    assert AuditDynamicsSuite("urdf", "").title == "Dynamics: the URDF in pinocchio-urdf and mujoco-urdf"
    assert AuditDynamicsSuite("mjcf", "").title == "Dynamics: the MJCF in mujoco and pinocchio-mjcf"


def test_a_urdf_is_read_by_pinocchio_and_by_mujocos_urdf_import_with_mujocos_armature(arm3):
    pin, mj, origin = AuditDynamicsSuite("urdf", arm3[0]).models(context())
    assert origin == "MuJoCo's URDF import"
    assert list(pin.model.armature[pin.idx_v]) == list(mj.armature)
    for q in Q:
        assert pin.mass(q) == pytest.approx(mj.mass(q), abs=1e-9)
        assert pin.gravity(q) == pytest.approx(mj.gravity(q), abs=1e-9)


@pytest.fixture(scope="module")
def turned_mjcf(arm3):
    """arm3's MJCF mounted a quarter turn about x: gravity pulls along the arm's own y."""
    quat = f"{math.sqrt(0.5)!r} {math.sqrt(0.5)!r} 0 0"
    return arm3[1].replace('<body name="world_mount">', f'<body name="world_mount" quat="{quat}">', 1)


def test_an_mjcf_is_read_by_pinocchios_parser_with_gravity_turned_into_the_top_bodys_world(turned_mjcf):
    pin, mj, origin = AuditDynamicsSuite("mjcf", turned_mjcf, top_level_pose(turned_mjcf)).models(context())
    assert origin == "MJCF" and list(pin.model.armature[pin.idx_v]) == [0.01, 0.01, 0.01]
    q = Q[0]
    assert np.abs(mj.gravity(q)).max() > 0.5
    assert pin.gravity(q) == pytest.approx(mj.gravity(q), abs=1e-9)
    assert pin.mass(q) == pytest.approx(mj.mass(q), abs=1e-9)
    # without the pose put back, Pinocchio's world keeps gravity along its own -z
    unturned, _, _ = AuditDynamicsSuite("mjcf", turned_mjcf).models(context())
    assert np.abs(unturned.gravity(q) - mj.gravity(q)).max() > 0.1


def test_an_mjcfs_springs_and_friction_are_left_out_of_its_rigid_body_dynamics(arm3):
    """MuJoCo's inverse dynamics adds a joint's spring and friction loss (passive and constraint
    forces) that Pinocchio's rigid bodies do not have: the audit compares rigid bodies alike."""
    sprung = P.joint_attr(arm3[1], "joint2", "frictionloss", lambda _: "2")
    sprung = P.sub_once(r'<joint name="joint2"', '<joint name="joint2" stiffness="40" springref="0.3"', sprung)
    pin, mj, _ = AuditDynamicsSuite("mjcf", sprung).models(context())
    v, a = np.full(3, 0.4), np.full(3, -0.7)
    for q in Q:
        assert pin.inverse(q, v, a) == pytest.approx(mj.inverse(q, v, a), abs=1e-9)


@pytest.mark.parametrize(
    "kind, pair, note",
    [
        ("urdf", ("pinocchio-urdf", "mujoco-urdf"), "pinocchio-urdf's joint armature is set to mujoco-urdf's"),
        ("mjcf", ("mujoco", "pinocchio-mjcf"), "pinocchio-mjcf's joint armature is set to mujoco's"),
    ],
)
def test_a_run_on_one_file_names_its_two_libraries_in_the_checks_and_the_section(arm3, kind, pair, note):
    text = arm3[0] if kind == "urdf" else arm3[1]
    out = AuditDynamicsSuite(kind, text, None).run(context())
    assert out.checks and {c.backends for c in out.checks} == {pair}
    assert all(c.passed for c in out.checks), [(c.property, c.max_error) for c in out.checks if not c.passed]
    assert out.section.title == f"Dynamics: the {kind.upper()} in {pair[0]} and {pair[1]}"
    columns = [c for t in out.section.tables for c in t.columns]
    assert not [c for c in columns if "URDF" in c or "MJCF" in c]
    assert [n for n in out.section.notes if note in n] == [note + " (a URDF has none): armature is not compared."]
    assert not [n for n in out.section.notes if "URDF cannot express joint armature" in n]


def test_the_section_names_the_libraries_in_place_of_the_formats():
    section = Section(
        "old",
        tables=[Table("t", ["property", "URDF", "MJCF", "URDF vs MJCF"], []), Table("u", ["x"], [])],
        notes=["kept", "URDF cannot express joint armature: taken from MJCF"],
    )
    out = _relabel(section, "new", "pin", "mj")
    assert out.title == "new"
    assert [t.columns for t in out.tables] == [["property", "pin", "mj", "pin vs mj"], ["x"]]
    assert out.notes == ["kept", "pin's joint armature is set to mj's (a URDF has none): armature is not compared."]


# --- inertials MuJoCo's URDF import reads otherwise -----------------------------------------


def inertial(urdf: str, link: str, **attrs) -> str:
    """``urdf`` with ``link``'s mass (``value``) or inertia attributes (``ixx``...) or origin (``xyz``) set."""
    for attr, value in attrs.items():
        tag = {"value": "mass", "xyz": "origin"}.get(attr, "inertia")
        urdf = P.sub_once(rf'(<link name="{link}">\s*<inertial>.*?<{tag}[^>]*? {attr}=")[^"]*(")', rf"\g<1>{value}\g<2>", urdf)
    return urdf


def test_a_urdf_both_libraries_read_alike_has_no_inertial_finding(arm3):
    assert inertial_findings(arm3[0], describe_urdf(arm3[0])) == []


def test_a_link_without_an_inertial_given_a_mass_from_its_geometry_is_one_error(arm3):
    urdf = P.sub_once(r'(<link name="link3">)\s*<inertial>.*?</inertial>', r"\1", arm3[0])
    (f,) = inertial_findings(urdf, describe_urdf(urdf))
    sphere = 4 / 3 * math.pi * 0.02**3 * 1000  # MuJoCo's default density on the 2 cm sphere
    assert (f.kind, f.severity, f.subject, f.property, f.unit) == ("parser_disagreement", "error", "link3", "inertia.mass", "kg")
    assert f.magnitude == pytest.approx(sphere, rel=1e-9)
    assert f.values == {
        "file": "URDF",
        "backends": ["pinocchio-urdf", "mujoco-urdf"],
        "backend": "mujoco-urdf",
        "pinocchio-urdf": 0.0,
        "mujoco-urdf": pytest.approx(sphere, rel=1e-9),
    }
    assert f.message == (
        f"mujoco-urdf gives link link3 a mass of {sphere:.6g} kg, pinocchio-urdf 0 kg (the link has no <inertial>: "
        "MuJoCo's URDF import takes one from its geometry)"
    )


def test_a_link_only_pinocchio_has_is_a_mass_difference(arm3):
    tool = (
        '<joint name="tool_mount" type="fixed"><parent link="end_effector"/><child link="tool"/></joint>'
        '<link name="tool"><inertial><mass value="0.5"/><inertia ixx="0.001" iyy="0.001" izz="0.001" ixy="0" ixz="0" iyz="0"/>'
        "</inertial></link></robot>"
    )
    desc = describe_urdf(arm3[0].replace("</robot>", tool))
    found = [f for f in inertial_findings(arm3[0], desc) if f.subject == "tool"]
    (f,) = found
    assert (f.property, f.magnitude) == ("inertia.mass", pytest.approx(0.5))
    assert f.message == "mujoco-urdf gives link tool a mass of 0 kg, pinocchio-urdf 0.5 kg"


def test_a_mass_read_otherwise_is_the_first_difference_named(arm3):
    urdf = arm3[0]
    desc = describe_urdf(inertial(urdf, "link2", value="0.8", xyz="0.0 0.01 0.135", ixx="0.005"))
    (f,) = inertial_findings(urdf, desc)
    assert (f.subject, f.property, f.unit) == ("link2", "inertia.mass", "kg")
    assert f.magnitude == pytest.approx(0.8 - 0.7634070148223197, rel=1e-9)
    assert f.message == "mujoco-urdf gives link link2 a mass of 0.763407 kg, pinocchio-urdf 0.8 kg"


def test_a_mass_within_a_billionth_of_the_larger_of_a_kilogram_and_the_mass_agrees(arm3):
    urdf = arm3[0]
    light = describe_urdf(inertial(urdf, "link2", value=repr(0.7634070148223197 + 1.5e-9)))
    assert [f.subject for f in inertial_findings(urdf, light)] == ["link2"]  # 1.5e-9 kg: above 1e-9 × 1 kg
    heavy = inertial(urdf, "link1", value="5.0")
    assert inertial_findings(heavy, describe_urdf(inertial(heavy, "link1", value="5.000000003"))) == []  # 3e-9: 0.6e-9 × 5 kg


def test_a_centre_of_mass_read_otherwise_is_measured_on_the_models_scale(arm3):
    urdf = arm3[0]
    desc = describe_urdf(inertial(urdf, "link2", xyz="0.0 0.0 0.1350005"))
    (f,) = inertial_findings(urdf, desc)
    assert (f.subject, f.property, f.magnitude, f.unit, f.severity) == ("link2", "inertia.com", None, "", "error")
    assert f.message == "mujoco-urdf gives link link2 its centre of mass 5e-07 m from pinocchio-urdf's"
    assert inertial_findings(urdf, desc, scale=1000.0) == []  # a model a thousand times larger: 1e-6 m


def test_an_inertia_read_otherwise_is_the_largest_component_apart(arm3):
    urdf = arm3[0]
    desc = describe_urdf(inertial(urdf, "link2", ixx=repr(0.004842168172904483 + 2e-6)))
    (f,) = inertial_findings(urdf, desc)
    assert (f.subject, f.property, f.magnitude) == ("link2", "inertia.tensor", None)
    assert f.message == "mujoco-urdf gives link link2 an inertia up to 2e-06 kg·m² from pinocchio-urdf's"
    assert inertial_findings(urdf, describe_urdf(inertial(urdf, "link2", ixx=repr(0.004842168172904483 + 5e-10)))) == []


def test_links_are_named_from_the_base_out(arm3):
    urdf = arm3[0]
    desc = describe_urdf(inertial(inertial(urdf, "link3", value="0.04"), "link1", value="0.95"))
    assert [f.subject for f in inertial_findings(urdf, desc)] == ["link1", "link3"]


def test_a_centre_of_mass_more_than_a_nanometre_apart_on_a_metre_scale_is_named(arm3):
    urdf = arm3[0]
    (f,) = inertial_findings(urdf, describe_urdf(inertial(urdf, "link2", xyz="0.0 0.0 0.1350000015")))
    assert (f.subject, f.property) == ("link2", "inertia.com")


def test_a_centre_of_mass_within_the_models_scale_leaves_the_inertia_to_be_named(arm3):
    urdf = arm3[0]
    desc = describe_urdf(inertial(urdf, "link2", xyz="0.0 0.0 0.13500001", ixx=repr(0.004842168172904483 + 2e-6)))
    (f,) = inertial_findings(urdf, desc, scale=1000.0)  # 1e-8 m apart: within 1e-6 m on this scale
    assert (f.subject, f.property) == ("link2", "inertia.tensor")


BALL_MJCF = """<mujoco model="ball"><worldbody>
  <body name="a"><joint name="j1" axis="0 0 1"/><geom type="sphere" size="0.05" mass="1"/>
    <body name="b" pos="0.2 0 0"><joint name="j2" type="ball"/><geom type="sphere" size="0.05" mass="1"/></body>
  </body></worldbody></mujoco>"""


def test_a_model_moved_by_a_joint_not_compared_is_refused_by_the_library_that_read_it():
    """An MJCF's ball joint (3 degrees of freedom, not compared): Pinocchio's MJCF parser read it,
    and is the one named, with the format it read."""
    ctx = VerifyContext(ModelSources("ball", ("j1",), (), (-1.0,), (1.0,), (True,)), {}, Q[:, :1], OPTIONS)
    with pytest.raises(BackendError) as err:
        AuditDynamicsSuite("mjcf", BALL_MJCF).models(ctx)
    assert err.value.backend == "pinocchio-mjcf"
    assert str(err.value) == (
        "pinocchio-mjcf: dynamics needs the model to move by the compared joints only (1 degree of freedom), the MJCF has 4"
    )


def test_mujocos_urdf_import_is_named_when_it_lacks_a_joint(arm3):
    ctx = VerifyContext(
        ModelSources("arm3", ("joint1", "nowhere"), (), (-1.0,) * 2, (1.0,) * 2, (True,) * 2), {}, Q[:, :2], OPTIONS
    )
    with pytest.raises(BackendError) as err:
        AuditDynamicsSuite("urdf", arm3[0]).models(ctx)
    assert str(err.value) == "mujoco-urdf: URDF lacks joint 'nowhere'"
