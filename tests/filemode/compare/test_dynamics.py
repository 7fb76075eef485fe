"""The dynamics of the two files compared as rigid bodies: what only MuJoCo adds is named and
left out, not reported as a residual nobody can place."""

from __future__ import annotations

import math
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.filemode.compare.context import FileModeInfo
from kinverify.backends import ModelSources
from kinverify.filemode.compare.dynamics import AlignedMujoco, FileDynamicsSuite, parameter_findings, velocity_findings
from kinverify.model.floating import BASE_COORDINATES, BASE_REVOLUTE
from kinverify.suites.base import VerifyContext
from kinverify.tracking.models import MujocoDynamics
from kinverify.filemode.pipeline import verify_files
from kinverify.run import VerifyOptions

OPTIONS = VerifyOptions(
    samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], extra={"dynamics_samples": 12}, suites=P.NO_PICTURES
)


def test_gravity_compensation_is_named_and_left_out_of_the_rigid_body_comparison(tmp_path):
    """The MJCF cancels the weight of link1 and link2 (gravcomp="1"), which a URDF cannot say: one
    warning naming it, and the gravity, inverse and forward dynamics agree."""
    urdf, mjcf = P.generated_pair("arm3")
    for body in ("link1", "link2"):
        mjcf = P.sub_once(rf'(<body name="{body}")', r'\1 gravcomp="1"', mjcf)
    result = verify_files(*P.write_pair(tmp_path, urdf, mjcf), OPTIONS)
    above = [f for f in result.findings if f.severity != "info" and not P.ignored_by_drake(f)]
    gravcomp = [f for f in above if "gravcomp" in f.message]
    assert len(gravcomp) == 1 and gravcomp[0].severity == "warning"
    assert gravcomp[0].values["mjcf_gravcomp"] == {"link1": 1.0, "link2": 1.0}
    assert not [f for f in above if f.kind == "dynamics_difference"], [f.message for f in above]
    dynamics = {c.property: c.passed for c in result.checks if c.property.startswith("dynamics.")}
    assert dynamics["dynamics.gravity"] and dynamics["dynamics.inverse"] and dynamics["dynamics.forward"]
    assert result.passed


def joint2(mjcf: str, attr: str, value: str) -> str:
    return P.sub_once(rf'(<joint name="joint2"[^>]*? {attr}=")[^"]*(")', rf"\g<1>{value}\g<2>", mjcf)


def dynamics_findings(result) -> list:
    return [f for f in result.findings if f.kind.startswith(("damping", "friction"))]


def test_a_friction_difference_names_both_formats_words(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    result = verify_files(*P.write_pair(tmp_path, urdf, joint2(mjcf, "frictionloss", "0.5")), OPTIONS)
    (f,) = dynamics_findings(result)
    assert (f.kind, f.severity) == ("friction_difference", "error")
    assert f.message == "friction (URDF friction, MJCF frictionloss) 0 in the URDF, 0.5 in the MJCF on 1 joint: joint2"


def test_a_damping_difference_within_the_users_tolerance_is_not_reported(tmp_path):
    urdf, mjcf = P.generated_pair("arm3")
    # 1e-4 N·m·s/rad apart, under a damping tolerance of 1e-3 (a difference the default 1e-12 reports)
    changed = joint2(mjcf, "damping", "0.1001")
    loose = replace(OPTIONS, tolerances={"dynamics.damping": 1e-3})
    assert 'damping="0.1001"' in changed and dynamics_findings(verify_files(*P.write_pair(tmp_path, urdf, changed), loose)) == []


# --- the parameters compared on the files' own values (parameter_findings) -----------------

JOINTS = ("joint1", "joint2", "joint3")


@pytest.fixture(scope="module")
def arm3():
    """arm3's two files read (same joint names, identity alignment): damping 0.1, friction 0 on
    every joint in both, armature 0.01 in the MJCF only."""
    urdf, mjcf = P.generated_pair("arm3")
    return FileModeInfo.from_sources(SimpleNamespace(urdf=urdf, mjcf=mjcf, joint_names=list(JOINTS)))


def edited(info, u=None, m=None, u_kind="urdf", m_kind="mjcf", **m_desc):
    """``info`` with joint fields replaced (``u``/``m``: joint -> fields), the sides' kinds and MJCF fields."""
    u, m = u or {}, m or {}
    ud = replace(info.u, kind=u_kind, joints=[replace(j, **u.get(j.name, {})) for j in info.u.joints])
    md = replace(info.m, kind=m_kind, joints=[replace(j, **m.get(j.name, {})) for j in info.m.joints], **m_desc)
    return replace(info, u=ud, m=md)


def params(info, tolerances=None, kinds=None):
    out = parameter_findings(info, tolerances or {})
    return [f for f in out if kinds is None or f.kind in kinds]


DIFFS = ("damping_difference", "friction_difference", "armature_difference", "damping_unset", "friction_unset", "armature_unset")


def test_files_that_agree_on_damping_and_friction_give_no_parameter_finding(arm3):
    assert params(arm3, kinds=DIFFS) == []


def test_a_damping_both_files_state_differently_is_one_error_with_its_size(arm3):
    (f,) = params(edited(arm3, m={"joint2": {"damping": 0.35}}), kinds=DIFFS)
    assert (f.kind, f.severity, f.subject, f.other, f.property) == (
        "damping_difference",
        "error",
        "joint2",
        "joint2",
        "dynamics.damping",
    )
    assert (f.magnitude, f.unit) == (pytest.approx(0.25, rel=1e-12), "N·m·s/rad")
    assert f.values == {"urdf": 0.1, "mjcf": 0.35, "unset_in": None, "checks": [["dynamics.damping", "parameters"]]}
    assert f.message == "damping 0.1 in the URDF, 0.35 in the MJCF on 1 joint: joint2"


def test_joints_with_the_same_pair_of_frictions_are_one_finding_and_another_pair_another(arm3):
    info = edited(arm3, m={"joint1": {"friction": 0.5}, "joint3": {"friction": 0.5}, "joint2": {"friction": 0.75}})
    found = params(info, kinds=DIFFS)
    assert [(f.kind, f.subject, f.magnitude, f.unit) for f in found] == [
        ("friction_difference", "joint1, joint3", 0.5, "N·m"),
        ("friction_difference", "joint2", 0.75, "N·m"),
    ]
    assert (
        found[0].message
        == "friction (URDF friction, MJCF frictionloss) 0 in the URDF, 0.5 in the MJCF on 2 joints: joint1, joint3"
    )
    assert found[0].values["checks"] == [["dynamics.friction", "parameters"]]


@pytest.mark.parametrize("prop, field", [("dynamics.damping", "damping"), ("dynamics.friction", "friction")])
def test_a_difference_at_the_users_tolerance_is_not_reported_and_one_above_it_is(arm3, prop, field):
    info = edited(arm3, u={"joint2": {field: 0.5}}, m={"joint2": {field: 0.75}})
    assert params(info, {prop: 0.25}, kinds=DIFFS) == []  # exactly at the tolerance
    assert [f.magnitude for f in params(info, {prop: 0.125}, kinds=DIFFS)] == [0.25]
    other = "dynamics.friction" if prop == "dynamics.damping" else "dynamics.damping"
    assert [f.magnitude for f in params(info, {other: 1.0}, kinds=DIFFS)] == [0.25]  # another property's tolerance


def test_the_default_tolerance_tells_a_millionth_and_not_rounding(arm3):
    assert [f.magnitude for f in params(edited(arm3, m={"joint2": {"damping": 0.100001}}), kinds=DIFFS)] == [
        pytest.approx(1e-6, rel=1e-6)
    ]
    assert params(edited(arm3, m={"joint2": {"damping": 0.1 + 1e-13}}), kinds=DIFFS) == []


@pytest.mark.parametrize("side", ["u", "m"])
def test_a_value_one_file_cannot_express_is_not_compared(arm3, side):
    assert params(edited(arm3, **{side: {"joint2": {"damping": None, "friction": None}}}), kinds=DIFFS) == []


def test_a_damping_the_urdf_leaves_unset_is_a_warning_naming_the_urdf_words(arm3):
    info = edited(arm3, u={"joint2": {"damping": 0.0, "stated": frozenset({"friction"})}}, m={"joint2": {"damping": 0.3}})
    (f,) = params(info, kinds=DIFFS)
    assert (f.kind, f.severity, f.subject, f.magnitude) == ("damping_unset", "warning", "joint2", pytest.approx(0.3))
    assert f.values["unset_in"] == "URDF"
    assert f.message == (
        "the URDF leaves damping unset on 1 joint (no <dynamics damping>: 0 by default); the MJCF states 0.3: joint2"
    )


def test_a_friction_the_mjcf_leaves_unset_names_its_default_class(arm3):
    info = edited(arm3, u={"joint2": {"friction": 0.5}}, m={"joint2": {"stated": frozenset({"damping"})}})
    (f,) = params(info, kinds=DIFFS)
    assert (f.kind, f.values["unset_in"]) == ("friction_unset", "MJCF")
    assert f.message == (
        "the MJCF leaves friction (URDF friction, MJCF frictionloss) unset on 1 joint (no frictionloss on the "
        "joint or its default class: 0 by default); the URDF states 0.5: joint2"
    )


def test_an_unset_value_and_a_stated_one_of_the_same_size_are_two_findings(arm3):
    info = edited(
        arm3,
        u={"joint1": {"friction": 0.5}, "joint2": {"friction": 0.5}},
        m={"joint1": {"stated": frozenset({"damping"})}},
    )
    assert sorted((f.kind, f.subject) for f in params(info, kinds=DIFFS)) == [
        ("friction_difference", "joint2"),
        ("friction_unset", "joint1"),
    ]


def test_armature_is_compared_only_against_a_usd(arm3):
    changed = {"joint2": {"armature": 0.02}}
    assert params(edited(arm3, u=changed), kinds=DIFFS) == []  # a URDF and an MJCF: the inexpressible finding
    (f,) = params(edited(arm3, u=changed, u_kind="usd"), kinds=DIFFS)
    assert (f.kind, f.subject, f.magnitude, f.unit) == ("armature_difference", "joint2", pytest.approx(0.01), "kg·m²")
    assert f.message == "armature 0.02 in the URDF, 0.01 in the MJCF on 1 joint: joint2"
    (g,) = params(edited(arm3, u={"joint2": {"armature": 0.01}}, m={"joint2": {"armature": 0.0}}, m_kind="usd"), kinds=DIFFS)
    assert (g.kind, g.subject) == ("armature_difference", "joint2")


def test_a_usd_side_leaving_a_value_unset_names_the_usd_attributes(arm3):
    info = edited(
        arm3,
        u={"joint2": {"armature": 0.0, "stated": frozenset({"damping", "friction"})}},
        m={"joint2": {"armature": 0.02}},
        u_kind="usd",
    )
    (f,) = params(info, kinds=DIFFS)
    assert f.kind == "armature_unset" and "(no physxJoint:armature, newton:armature or mjc:armature on the joint: 0" in f.message
    info = edited(arm3, m={"joint2": {"damping": 0.0, "stated": frozenset()}}, m_kind="usd")
    (g,) = params(info, kinds=DIFFS)
    assert g.kind == "damping_unset" and "(no newton:damping or mjc:damping on the joint: 0 by default)" in g.message
    info = edited(arm3, u={"joint2": {"friction": 0.5}}, m={"joint2": {"stated": frozenset()}}, m_kind="usd")
    (h,) = params(info, kinds=DIFFS)
    assert "(no newton:friction or mjc:frictionloss on the joint: 0 by default)" in h.message


def test_velocity_limits_are_compared_against_a_usd_within_a_millionth(arm3):
    u = {"joint1": {"type": "prismatic"}}
    m = {j: {"velocity": 3.0} for j in JOINTS} | {"joint2": {"velocity": 2.5}, "joint1": {"velocity": 1.5}}
    assert params(edited(arm3, u=u, m=m), kinds=("velocity_difference",)) == []  # no USD: no velocity finding
    found = params(edited(arm3, u=u, m=m, m_kind="usd"), kinds=("velocity_difference",))
    assert [(f.subject, f.magnitude, f.unit, f.property, f.severity) for f in found] == [
        ("joint1", 1.5, "m/s", "limits.velocity", "error"),
        ("joint2", 0.5, "rad/s", "limits.velocity", "error"),
    ]
    assert found[1].message == "velocity limit 3 rad/s in the URDF, 2.5 rad/s in the MJCF on 1 joint: joint2"
    assert found[1].values == {"urdf": 3.0, "mjcf": 2.5}


def test_velocity_limits_a_millionth_apart_agree_and_the_same_pair_is_one_finding(arm3):
    # 1.000001 against 1: within a millionth of the larger value (not of the smaller)
    m = {"joint1": {"velocity": 1.000001}, "joint2": {"velocity": 2.0}, "joint3": {"velocity": 2.0}}
    u = {"joint1": {"velocity": 1.0}, "joint2": {"velocity": 2.5}, "joint3": {"velocity": 2.5}}
    (f,) = velocity_findings(edited(arm3, u=u, m=m, m_kind="usd"))
    assert (f.subject, f.magnitude) == ("joint2, joint3", pytest.approx(0.5))
    assert f.message.endswith("on 2 joints: joint2, joint3")
    assert velocity_findings(edited(arm3, u={"joint2": {"velocity": None}}, m={"joint2": {"velocity": 2.0}})) == []


def test_the_mjcf_armature_a_urdf_cannot_express_is_one_warning_with_its_values(arm3):
    info = edited(arm3, m={"joint2": {"armature": 0.02}, "joint3": {"armature": 0.0}})
    (f,) = params(info, kinds=("inexpressible",))
    assert (f.severity, f.subject, f.other, f.property, f.unit) == (
        "warning",
        "joint1, joint2",
        "joint1, joint2",
        "dynamics.armature",
        "kg·m²",
    )
    assert f.magnitude == pytest.approx(0.02) and f.values == {"mjcf": {"joint1": 0.01, "joint2": 0.02}}
    assert f.message == (
        "the MJCF gives 2 joints armature (rotor inertia) 0.01, 0.02, which a URDF cannot express: the URDF's "
        "dynamics lack it (the comparison gives Pinocchio the MJCF's)"
    )
    assert params(edited(arm3, u_kind="usd"), kinds=("inexpressible",)) == []  # a USD first side states armature


def test_an_mjcf_spring_is_one_warning_left_out_of_the_comparison(arm3):
    (f,) = params(edited(arm3, m={"joint3": {"stiffness": 5.0}}), kinds=("stiffness_inexpressible",))
    assert (f.subject, f.magnitude, f.unit, f.property) == ("joint3", 5.0, "N·m/rad", "dynamics.stiffness")
    assert f.message == (
        "the MJCF gives 1 joints a spring (stiffness 5), which a URDF cannot express: the URDF's dynamics lack it "
        "(springs are left out of the dynamics comparison)"
    )
    assert params(arm3, kinds=("stiffness_inexpressible",)) == []
    # a USD first side states armature, not springs: the spring is still said
    usd = params(edited(arm3, m={"joint3": {"stiffness": 5.0}}, u_kind="usd"), kinds=("stiffness_inexpressible",))
    assert [f.subject for f in usd] == ["joint3"]


def test_gravity_compensation_is_one_warning_with_its_shares(arm3):
    info = edited(arm3, gravcomp={"link2": 1.0, "link3": 0.5})
    (f,) = [f for f in params(info, kinds=("inexpressible",)) if f.property == "dynamics.gravity"]
    assert (f.magnitude, f.values) == (1.0, {"file": "MJCF", "mjcf_gravcomp": {"link2": 1.0, "link3": 0.5}})
    assert f.message == (
        "the MJCF compensates gravity on 2 bodies (gravcomp 0.5, 1: MuJoCo cancels that share of their weight), "
        "which a URDF cannot express: the rigid-body dynamics are compared without it: link2, link3"
    )


def test_a_free_joints_armature_and_damping_are_one_warning(arm3):
    info = edited(arm3, free_joint={"armature": 0.1, "damping": 0.2})
    (f,) = [f for f in params(info, kinds=("inexpressible",)) if f.property == "dynamics.mass_matrix"]
    assert (f.magnitude, f.values) == (0.2, {"file": "MJCF", "armature": 0.1, "damping": 0.2})
    assert f.message == (
        "the MJCF gives its free joint armature 0.1 and damping 0.2 (a floating base in a URDF has neither): "
        "left out of the rigid-body dynamics comparison"
    )


def test_drakes_rotor_inertia_is_named_as_the_reflected_inertia(arm3):
    ext = {"joint1": {"rotor_inertia": 0.001, "gear_ratio": 10.0}, "joint2": {"rotor_inertia": 0.002}, "joint3": {"x": 1}}
    info = replace(arm3, u=replace(arm3.u, extensions=ext))
    (f,) = params(info, kinds=("format_extension",))
    assert (f.subject, f.magnitude, f.unit, f.severity) == ("joint1, joint2", pytest.approx(0.1), "kg·m²", "info")
    assert f.values["reflected_inertia"] == {"joint1": pytest.approx(0.1), "joint2": pytest.approx(0.002)}
    assert f.message == (
        "the URDF's transmissions give rotor inertia and gear ratio (a Drake extension Pinocchio does not read): "
        "reflected inertia G²·I of joint1 0.1, joint2 0.002 kg·m², not in the comparison"
    )
    assert params(arm3, kinds=("format_extension",)) == []


# --- MuJoCo in the URDF's coordinates, Pinocchio with the reported differences substituted ---

RNG = np.random.default_rng(7)
STATES = [(RNG.uniform(-1, 1, 3), RNG.uniform(-1, 1, 3), RNG.uniform(-1, 1, 3)) for _ in range(3)]


def damped(mjcf: str, values=(0.1, 0.2, 0.3)) -> str:
    for joint, d in zip(JOINTS, values, strict=True):
        mjcf = P.joint_attr(mjcf, joint, "damping", lambda _, d=d: repr(d))
    return P.joint_attr(mjcf, "joint3", "frictionloss", lambda _: "0.05")


@pytest.fixture(scope="module")
def arm3_mjcf():
    return damped(P.generated_pair("arm3")[1])


def test_mujoco_read_through_a_flipped_joint_with_a_zero_offset_is_the_unflipped_files_dynamics(arm3_mjcf):
    """joint2's axis reversed and its zero 0.3 rad further (``ref``) in one MJCF: q_mjcf = -q + 0.3.
    Read through that map, it gives the other MJCF's mass matrix, forces and accelerations."""
    flipped = P.joint_attr(arm3_mjcf, "joint2", "axis", lambda _: "0.0 -1.0 0.0")
    flipped = P.sub_once(r'(<joint name="joint2" )', r'\1ref="0.3" ', flipped)
    ref = MujocoDynamics(arm3_mjcf, JOINTS, rigid=True)
    inner = MujocoDynamics(flipped, JOINTS, rigid=True)
    seen = AlignedMujoco(inner, np.array([1.0, -1.0, 1.0]), np.array([0.0, 0.3, 0.0]), np.array([0.0, 0.0, -9.81]))
    for q, v, a in STATES:
        assert not np.allclose(inner.mass(q), ref.mass(q), atol=1e-6)  # the map matters on these states
        assert seen.mass(q) == pytest.approx(ref.mass(q), abs=1e-10)
        assert seen.gravity(q) == pytest.approx(ref.gravity(q), abs=1e-10)
        assert seen.bias(q, v) == pytest.approx(ref.bias(q, v), abs=1e-10)
        assert seen.inverse(q, v, a) == pytest.approx(ref.inverse(q, v, a), abs=1e-10)
        assert seen.forward(q, v, a) == pytest.approx(ref.forward(q, v, a), abs=1e-8)
    # the parameters are the file's own, joint by joint
    assert (list(seen.damping), list(seen.friction), list(seen.armature)) == (
        [0.1, 0.2, 0.3],
        [0.0, 0.0, 0.05],
        [0.01, 0.01, 0.01],
    )
    assert seen.snapped_inertia_frames() == inner.snapped_inertia_frames() == []


def test_mujoco_is_given_the_gravity_of_the_aligned_world(arm3_mjcf):
    ref = MujocoDynamics(arm3_mjcf, JOINTS, rigid=True)
    twice = AlignedMujoco(MujocoDynamics(arm3_mjcf, JOINTS, rigid=True), np.ones(3), np.zeros(3), np.array([0.0, 0.0, -19.62]))
    q = STATES[0][0]
    assert twice.gravity(q) == pytest.approx(2 * ref.gravity(q), rel=1e-9) and np.abs(ref.gravity(q)).max() > 0.1


def rotated_joint2(urdf: str, mjcf: str, roll=0.3, yaw=0.7) -> tuple[str, str]:
    """joint2's frame turned by rpy (roll, 0, yaw) in both files alike (the same robot)."""
    urdf = P.sub_once(
        r'(<joint name="joint2".*?<origin xyz="0.0 0.0 0.3" rpy=")[^"]*(")', rf"\g<1>{roll!r} 0.0 {yaw!r}\g<2>", urdf
    )
    cz, sz, cx, sx = math.cos(yaw / 2), math.sin(yaw / 2), math.cos(roll / 2), math.sin(roll / 2)
    quat = f"{cz * cx!r} {cz * sx!r} {sz * sx!r} {sz * cx!r}"  # q_z(yaw) ⊗ q_x(roll), wxyz
    return urdf, P.sub_once(r'(<body name="link2" pos="0.0 0.0 0.3")', rf'\1 quat="{quat}"', mjcf)


@pytest.fixture(scope="module")
def changed_pair():
    """arm3 with joint2's frame turned (both files); the MJCF gives link2 another mass, an offset
    and turned inertial, and joint2 a damping of 0.5 (0.1 in the URDF)."""
    urdf, mjcf = rotated_joint2(*P.generated_pair("arm3"))
    mjcf = P.joint_attr(mjcf, "joint2", "damping", lambda _: "0.5")
    mjcf = P.sub_once(
        r'(<body name="link2".*?<inertial )[^>]*(/>)',
        r'\1pos="0.01 -0.02 0.14" mass="1.2" fullinertia="0.005 0.006 0.004 0.0001 0.0002 0.0003"\2',
        mjcf,
    )
    info = FileModeInfo.from_sources(SimpleNamespace(urdf=urdf, mjcf=mjcf, joint_names=list(JOINTS)))
    sources = ModelSources(
        "arm3", JOINTS, ("link3",), (-1.0,) * 3, (1.0,) * 3, (True,) * 3, urdf=urdf, mjcf=mjcf, mjcf_frames=("link3",)
    )
    return info, sources


def file_models(changed_pair, groups, damping_joints):
    info, sources = changed_pair
    suite = FileDynamicsSuite(info, groups, damping_joints, [])
    ctx = suite.context(VerifyContext(sources, {}, np.zeros((2, 3)), VerifyOptions(extra={"dynamics_samples": 1})))
    return suite.models(ctx)


def test_the_mjcf_inertial_and_damping_a_finding_reports_are_substituted_and_then_the_files_agree(changed_pair):
    info = changed_pair[0]
    pin, mj, label = file_models(changed_pair, {"joint2": info.m.body("link2")}, {"joint2"})
    assert label == "MJCF"
    for q, v, a in STATES:
        assert pin.mass(q) == pytest.approx(mj.mass(q), abs=1e-9)
        assert pin.gravity(q) == pytest.approx(mj.gravity(q), abs=1e-9)
        assert pin.bias(q, v) == pytest.approx(mj.bias(q, v), abs=1e-9)
        assert pin.inverse(q, v, a) == pytest.approx(mj.inverse(q, v, a), abs=1e-9)
        assert pin.forward(q, v, a) == pytest.approx(mj.forward(q, v, a), abs=1e-7)
    # the parameters stay each file's own: the damping is compared as a parameter
    assert list(pin.damping) == [0.1, 0.1, 0.1] and list(mj.damping) == [0.1, 0.5, 0.1]


def test_a_reported_body_no_compared_joint_moves_does_not_stop_the_next_from_being_substituted(changed_pair):
    info = changed_pair[0]
    link2 = info.m.body("link2")
    pin, mj, _ = file_models(changed_pair, {"(base)": link2, "link9": link2, "joint2": link2}, {"joint2"})
    for q, _, _ in STATES:
        assert pin.mass(q) == pytest.approx(mj.mass(q), abs=1e-9)


def test_without_a_finding_nothing_is_substituted(changed_pair):
    info = changed_pair[0]
    pin, mj, _ = file_models(changed_pair, {"link9": info.m.body("link2"), "(base)": info.m.body("link2")}, {"joint1"})
    q, v, a = STATES[0]
    assert abs(pin.mass(q)[1, 1] - mj.mass(q)[1, 1]) > 1e-3  # link2's inertial differs
    # the damping of joint2 is not substituted (joint1's is, and agrees): the forces differ by 0.4·q̇₂ there
    base, _, _ = file_models(changed_pair, {"joint2": info.m.body("link2")}, set())
    assert base.inverse(q, v, a) - mj.inverse(q, v, a) == pytest.approx([0.0, -0.4 * v[1], 0.0], abs=1e-9)
    assert base.forward(q, v, mj.inverse(q, v, a)) - a != pytest.approx(np.zeros(3), abs=1e-6)


def test_the_suite_compares_the_matched_joints_with_unmatched_ones_locked(changed_pair):
    info, sources = changed_pair
    al = replace(
        info.alignment, joints=[replace(j, type="prismatic") if j.urdf == "joint3" else j for j in info.alignment.joints]
    )
    locked = replace(info, alignment=al, matching=replace(info.matching, unmatched_urdf=["joint3"], unmatched_mjcf=["joint1"]))
    suite = FileDynamicsSuite(locked, {}, set(), [])
    q = np.arange(30.0).reshape(10, 3)
    ctx = suite.context(VerifyContext(sources, {}, q, VerifyOptions(extra={"dynamics_samples": 4})))
    assert (ctx.sources.joint_names, ctx.sources.mjcf_joint_names, ctx.sources.revolute) == (JOINTS, JOINTS, (True, True, False))
    assert (ctx.sources.frames, ctx.sources.mjcf_frames) == (("link3",), ("link3",))
    assert ctx.q == pytest.approx(q[:4]) and ctx.backends == {}
    assert 'name="joint3" type="fixed"' in ctx.sources.urdf and 'name="joint1" type="revolute"' in ctx.sources.urdf
    assert '<joint name="joint1"' not in ctx.sources.mjcf and '<joint name="joint3"' in ctx.sources.mjcf
    assert len(suite.context(VerifyContext(sources, {}, np.zeros((120, 3)), VerifyOptions())).q) == 100  # the default


def test_a_floating_base_leads_the_compared_coordinates(changed_pair):
    info, sources = changed_pair
    suite = FileDynamicsSuite(replace(info, base_coordinates=True), {}, set(), [])
    q = np.arange(18.0).reshape(2, 9)
    ctx = suite.context(VerifyContext(sources, {}, q, VerifyOptions()))
    assert ctx.sources.joint_names == BASE_COORDINATES + JOINTS == ctx.sources.mjcf_joint_names
    assert ctx.sources.revolute == BASE_REVOLUTE + (True,) * 3
    assert ctx.q == pytest.approx(q)


def test_mujoco_gravity_is_turned_with_a_world_the_mjcf_turns():
    """The MJCF mounts arm3 turned a quarter turn about x (T): MuJoCo's gravity is turned with it,
    so the arm feels the URDF's gravity (without it, it would pull along the arm's y)."""
    urdf, mjcf = P.generated_pair("arm3")
    mjcf = mjcf.replace(
        '<body name="world_mount">', f'<body name="world_mount" quat="{math.sqrt(0.5)!r} {math.sqrt(0.5)!r} 0 0">', 1
    )
    info = FileModeInfo.from_sources(SimpleNamespace(urdf=urdf, mjcf=mjcf, joint_names=list(JOINTS)))
    turn = np.eye(4)
    turn[1:3, 1:3] = [[0.0, -1.0], [1.0, 0.0]]
    sources = ModelSources("arm3", JOINTS, (), (-1.0,) * 3, (1.0,) * 3, (True,) * 3, urdf=urdf, mjcf=mjcf)
    pin, mj, _ = file_models((replace(info, alignment=replace(info.alignment, T=turn)), sources), {}, set())
    q = np.array([0.3, 0.8, -0.5])
    assert np.abs(pin.gravity(q)).max() > 0.5 and pin.gravity(q) == pytest.approx(mj.gravity(q), abs=1e-9)
    assert mj.t == pytest.approx(turn)  # a floating base's coordinates are conjugated by it


def test_a_floating_base_is_read_through_the_joint_map_behind_its_six_coordinates(arm3_mjcf):
    """Both MJCFs float arm3 on a free joint: the base's six coordinates pass as they are (the
    same world), the joints through the map; the mass matrix and gravity are the unflipped file's."""
    free = arm3_mjcf.replace('<body name="world_mount">', '<body name="world_mount"><freejoint name="root"/>', 1)
    flipped = P.joint_attr(free, "joint2", "axis", lambda _: "0.0 -1.0 0.0")
    flipped = P.sub_once(r'(<joint name="joint2" )', r'\1ref="0.3" ', flipped)
    names = BASE_COORDINATES + JOINTS
    ref = MujocoDynamics(free, names, rigid=True)
    inner = MujocoDynamics(flipped, names, rigid=True)
    seen = AlignedMujoco(inner, np.array([1.0, -1.0, 1.0]), np.array([0.0, 0.3, 0.0]), np.array([0.0, 0.0, -9.81]), np.eye(4))
    assert seen.t is None and inner.floating
    for q, _, _ in STATES:
        full = np.concatenate([[0.1, -0.2, 0.3, 0.4, -0.5, 0.6], q])
        assert not np.allclose(inner.mass(full), ref.mass(full), atol=1e-6)
        assert seen.mass(full) == pytest.approx(ref.mass(full), abs=1e-10)
        assert seen.gravity(full) == pytest.approx(ref.gravity(full), abs=1e-10)


def test_a_floating_base_in_a_turned_world_is_read_through_the_conjugated_base_coordinates(arm3_mjcf):
    """The MJCF's world and its base body's frame are both turned by T (0.4 rad about x: the arm
    hangs in a <frame> turned back): the same robot, whose base coordinates MuJoCo reads
    conjugated by T, and whose gravity is turned with the world."""
    free = arm3_mjcf.replace('<body name="world_mount">', '<body name="world_mount"><freejoint name="root"/>', 1)
    turn = np.eye(4)
    turn[1:3, 1:3] = [[math.cos(0.4), -math.sin(0.4)], [math.sin(0.4), math.cos(0.4)]]
    inside = P.sub_once(r'(<body name="base")', rf'<frame quat="{math.cos(0.2)!r} {math.sin(0.2)!r} 0 0">\1', free)
    inside = P.sub_once(r"(</body>)(\s*</worldbody>)", r"</frame>\1\2", inside)
    names = BASE_COORDINATES + JOINTS
    ref = MujocoDynamics(free, names, rigid=True)
    seen = AlignedMujoco(
        MujocoDynamics(inside, names, rigid=True), np.ones(3), np.zeros(3), turn[:3, :3] @ [0.0, 0.0, -9.81], turn
    )
    for q, _, _ in STATES:
        full = np.concatenate([[0.1, -0.2, 0.3, 0.4, -0.5, 0.6], q])
        assert seen.mass(full) == pytest.approx(ref.mass(full), abs=1e-9)
        assert seen.gravity(full) == pytest.approx(ref.gravity(full), abs=1e-9)


def test_an_armature_an_mjcf_leaves_unset_against_a_usd_names_the_mjcf_words(arm3):
    info = edited(arm3, u={"joint2": {"armature": 0.02}}, m={"joint2": {"armature": 0.0, "stated": frozenset()}}, u_kind="usd")
    (f,) = params(info, kinds=DIFFS)
    assert (f.kind, f.values["unset_in"]) == ("armature_unset", "MJCF")
    assert "(no armature on the joint or its default class: 0 by default); the URDF states 0.02: joint2" in f.message


def test_values_equal_to_twelve_decimals_are_one_pair(arm3):
    info = edited(arm3, m={"joint1": {"damping": 0.5}, "joint3": {"damping": 0.5 + 3e-13}})
    (f,) = params(info, kinds=DIFFS)
    assert f.subject == "joint1, joint3" and f.values["mjcf"] == 0.5


def test_a_damping_the_mjcf_leaves_unset_names_its_default_class(arm3):
    info = edited(arm3, u={"joint2": {"damping": 0.3}}, m={"joint2": {"damping": 0.0, "stated": frozenset()}})
    (f,) = params(info, kinds=DIFFS)
    assert f.message == (
        "the MJCF leaves damping unset on 1 joint (no damping on the joint or its default class: 0 by default); "
        "the URDF states 0.3: joint2"
    )


def test_a_run_compares_the_files_after_the_substitutions(changed_pair):
    """The suite's own run on the pair: with link2's inertial and joint2's damping substituted, every
    state check passes and the damping parameter still differs (it is compared on the files' values)."""
    info, sources = changed_pair
    suite = FileDynamicsSuite(info, {"joint2": info.m.body("link2")}, {"joint2"}, [])
    out = suite.run(
        VerifyContext(sources, {}, np.random.default_rng(11).uniform(-1, 1, (3, 3)), VerifyOptions(extra={"dynamics_samples": 3}))
    )
    passed = {c.property: c.passed for c in out.checks}
    assert passed["dynamics.mass_matrix"] and passed["dynamics.inverse"] and passed["dynamics.forward"]
    assert passed["dynamics.damping"] is False
    assert FileDynamicsSuite.forward_scales_with_acceleration  # rounded files: the forward floor grows with q̈
