"""After the suites: the dynamics compared with the reported differences substituted, the
parameter findings, the rounding note and its culprits, accepted differences and what the report
keeps. Each test runs file mode on the three-joint arm (no suite but the one it needs: about
0.15 s each) with one or two edits of the MJCF."""

from __future__ import annotations

import dataclasses
import math
import re
import time

import numpy as np
import pytest

import tests.filemode.pairs as P
from kinverify.filemode.findings.finish import _snap_note
from kinverify.filemode.pipeline import verify_files
from kinverify.generate.usd import generate_usd
from kinverify.model.specfile import load_spec
from kinverify.pipeline.sampling import Samples
from kinverify.run import VerifyOptions
from tests.paths import MODELS

BASE = VerifyOptions(samples=4, fd_samples=2, backends=["pinocchio-urdf", "mujoco"], extra={"dynamics_samples": 4})
URDF, MJCF = P.generated_pair("arm3")
LINK2_MASS = 0.7634070148223197


def heavier_link2(mjcf: str, mass: float = 0.9) -> str:
    return P.sub_once(rf'(<inertial pos="0.0 0.0 0.135" mass="){LINK2_MASS}', lambda m: m[1] + repr(mass), mjcf)


def damped(mjcf: str, joint: str = "joint2", damping: str = "0.3") -> str:
    return P.joint_attr(mjcf, joint, "damping", lambda s: damping)


EDITED = damped(heavier_link2(MJCF))  # link2 0.9 kg instead of 0.763, joint2 damped 0.3 instead of 0.1


def run(tmp_path, mjcf=EDITED, suites=(), urdf=URDF, **kw):
    tolerances = kw.pop("tolerances", {})
    opts = dataclasses.replace(BASE, suites=list(suites), tolerances=tolerances)
    return verify_files(*P.write_pair(tmp_path, urdf, mjcf), opts, **kw)


def kinds(result) -> list[tuple[str, str]]:
    return [(f.kind, f.subject) for f in result.findings if f.severity != "info" and f.kind != "inexpressible"]


def test_the_dynamics_are_compared_with_each_reported_difference_substituted(tmp_path):
    """link2's inertial and joint2's damping differ: the MJCF's are substituted on the Pinocchio
    side, so the rigid-body dynamics agree and the damping check is explained by its finding; the
    substitutions are said first in the section's notes."""
    start = time.perf_counter()
    result = run(tmp_path, suites=["dynamics"])
    elapsed = time.perf_counter() - start
    assert list(result.sections) == ["filemode", "dynamics", "map"]
    notes = result.sections["dynamics"].notes
    assert notes[0] == (
        "Substituted on the Pinocchio side before comparing (each reported as a finding): "
        "the MJCF's inertial of link2; the MJCF's damping of joint2."
    )
    checks = {c.property: c for c in result.checks}
    assert {p for p in checks if p.startswith("dynamics.")} >= {"dynamics.mass_matrix", "dynamics.gravity", "dynamics.damping"}
    assert all(checks[p].passed for p in ("dynamics.mass_matrix", "dynamics.gravity", "dynamics.bias", "dynamics.inverse"))
    assert checks["dynamics.damping"].kind == "explained"
    assert checks["dynamics.damping"].note.endswith("explained by damping_difference on joint joint2")
    assert kinds(result) == [("damping_difference", "joint2")] and result.verdict == "fail"
    assert 0 < result.timings["dynamics"] <= elapsed and not result.internal_errors  # a part of the whole run


def test_without_the_dynamics_suite_no_dynamics_are_compared_but_the_parameters_still_are(tmp_path):
    result = run(tmp_path)
    assert list(result.sections) == ["filemode", "map"] and "dynamics" not in result.timings
    assert kinds(result) == [("damping_difference", "joint2")]
    assert not [c for c in result.checks if c.property.startswith("dynamics.")]


def test_the_tolerances_the_user_sets_decide_what_is_substituted_and_what_differs(tmp_path):
    """A mass tolerance of 0.5 kg: link2's 0.137 kg is no difference, so it is not substituted and
    the dynamics then differ by it, one finding; a damping tolerance of 1: no damping difference,
    nothing substituted for it."""
    result = run(tmp_path, suites=["dynamics"], tolerances={"inertia.mass": 0.5, "dynamics.damping": 1.0})
    assert "Substituted" not in " ".join(result.sections["dynamics"].notes)
    assert kinds(result) == [("dynamics_difference", "")]
    (f,) = [f for f in result.findings if f.kind == "dynamics_difference"]
    assert "dynamics.mass_matrix" in f.message
    com = run(tmp_path, mjcf=heavier_link2(MJCF), suites=["dynamics"], tolerances={"inertia.com": 0.5, "inertia.tensor": 1.0})
    assert com.sections["dynamics"].notes[0].endswith(": the MJCF's inertial of link2.")  # the mass tolerance is the mass's
    assert kinds(com) == []


def test_a_damping_difference_of_several_joints_substitutes_each(tmp_path):
    """joint2 and joint3 both damped 0.3 in the MJCF: one finding for the two, each substituted."""
    result = run(tmp_path, mjcf=damped(damped(MJCF), "joint3"), suites=["dynamics"])
    assert kinds(result) == [("damping_difference", "joint2, joint3")]
    assert result.sections["dynamics"].notes[0].endswith("the MJCF's damping of joint2, joint3.")
    assert all(c.passed or c.kind == "explained" for c in result.checks)


def test_a_damping_the_urdf_leaves_unset_is_substituted_too(tmp_path):
    """joint2 without <dynamics damping> in the URDF (0 by default), 0.1 in the MJCF: a warning
    naming the silent file, and the MJCF's damping substituted like a difference's."""
    urdf = P.sub_once(r'(<joint name="joint2".*?<dynamics) damping="0.1"', lambda m: m[1], URDF)
    result = run(tmp_path, urdf=urdf, mjcf=MJCF, suites=["dynamics"])
    assert kinds(result) == [("damping_unset", "joint2")]
    assert result.sections["dynamics"].notes[0].endswith(": the MJCF's damping of joint2.")
    (damping,) = [c for c in result.checks if c.property == "dynamics.damping"]
    assert damping.kind == "explained" and damping.note.endswith("explained by damping_unset on joint joint2")


def test_a_centre_of_mass_mujoco_moves_to_the_body_origin_is_substituted_and_said(tmp_path):
    """Both files put link3's centre of mass 0.5 µm above its origin; MuJoCo's compiler puts it at
    the origin (within about 1e-6 m): the files agree, yet the MJCF's inertial is substituted, so
    that both libraries hold what MuJoCo runs, and the note says why."""
    urdf = P.sub_once(r'(<link name="link3">\s*<inertial>\s*<origin xyz=")0.0 0.0 0.05', lambda m: m[1] + "0.0 0.0 5e-07", URDF)
    mjcf = P.sub_once(r'(<inertial pos=")0.0 0.0 0.05(" mass="0.0335)', lambda m: m[1] + "0.0 0.0 5e-07" + m[2], MJCF)
    result = run(tmp_path, urdf=urdf, mjcf=mjcf, suites=["dynamics"])
    assert (
        result.sections["dynamics"]
        .notes[0]
        .endswith(": the MJCF's inertial of link3 (MuJoCo put its centre of mass at the body origin).")
    )
    assert kinds(result) == [] and result.verdict == "pass"


def test_the_dynamics_are_sampled_as_many_times_as_asked_at_least_once(tmp_path):
    """One sample asked (``--samples 1``): the dynamics see the joint ranges' edge configurations
    and one uniform draw, as many as the sampler makes for these ranges and that count."""
    lower, upper = [-math.pi, -math.pi / 2, -3 * math.pi / 4], [math.pi, math.pi / 2, 3 * math.pi / 4]
    expected = len(Samples(lower, upper, [True] * 3, 1, seed=3))
    opts = dataclasses.replace(BASE, suites=["dynamics"], samples=1, seed=3, extra={"dynamics_samples": 1000})
    result = verify_files(*P.write_pair(tmp_path, URDF, EDITED), opts)
    (mass,) = [c for c in result.checks if c.property == "dynamics.mass_matrix"]
    assert mass.samples == expected and mass.passed


def test_the_dynamics_are_compared_at_the_configurations_the_users_seed_draws(tmp_path):
    """Seed 5, 20 uniform draws besides the joint ranges' edge configurations; link2's 0.137 kg
    within a mass tolerance of 0.5, so not substituted: the dynamics differ, and each check's worst
    configuration is one of those the seed draws (the mass matrix's among the uniform draws)."""
    lower, upper = [-math.pi, -math.pi / 2, -3 * math.pi / 4], [math.pi, math.pi / 2, 3 * math.pi / 4]
    drawn = np.asarray(Samples(lower, upper, [True] * 3, 20, seed=5))
    edges = len(Samples(lower, upper, [True] * 3, 0))
    opts = dataclasses.replace(
        BASE, suites=["dynamics"], samples=20, seed=5, extra={"dynamics_samples": 1000}, tolerances={"inertia.mass": 0.5}
    )
    result = verify_files(*P.write_pair(tmp_path, URDF, heavier_link2(MJCF)), opts)
    state = [c for c in result.checks if c.property in ("dynamics.mass_matrix", "dynamics.gravity", "dynamics.bias")]
    assert len(state) == 3 and not any(c.passed for c in state)
    rows = {c.property: [i for i, q in enumerate(drawn) if np.allclose(q, c.worst_q, rtol=0, atol=1e-12)] for c in state}
    assert all(c.samples == len(drawn) for c in state) and all(len(found) == 1 for found in rows.values())
    assert rows["dynamics.mass_matrix"][0] >= edges


@pytest.mark.parametrize(
    "edit, body, subject",
    [
        # link3 hung from a 0.2 kg suspension on a slide joint the URDF lacks, held at zero
        (lambda mjcf: P.suspended(mjcf, "link3", 0.2), "link2", "suspension_joint"),
        # a 0.1 kg tool body welded to link3, no link of the URDF its twin
        (
            lambda mjcf: P.sub_once(
                r'(<site name="end_effector"[^>]*/>)',
                lambda m: (
                    m[1]
                    + '<body name="tool" pos="0 0 0.08"><inertial pos="0 0 0.01" mass="0.1" diaginertia="1e-5 1e-5 1e-5"/></body>'
                ),
                mjcf,
            ),
            "link3",
            "tool",
        ),
    ],
    ids=["moved-by-a-joint-in-one-file", "fixed-in-one-file"],
)
def test_a_part_in_the_mjcf_only_is_substituted_with_the_rigid_body_it_joins(tmp_path, edit, body, subject):
    """A part the URDF lacks (its own finding, extra_parts) weighs in the MJCF's rigid body: that
    body's whole inertial is substituted, so the rigid-body dynamics agree."""
    result = run(tmp_path, mjcf=edit(MJCF), suites=["dynamics"])
    assert result.sections["dynamics"].notes[0].endswith(f": the MJCF's inertial of {body}.")
    assert kinds(result) == [("extra_parts", subject)]
    dynamics = [c for c in result.checks if c.property.startswith("dynamics.")]
    assert len(dynamics) == 7 and all(c.passed for c in dynamics)


def test_the_total_mass_is_said_beside_a_mass_difference(tmp_path):
    """The MJCF's world mount (1 kg, welded to the world) and link2's extra 0.137 kg."""
    result = run(tmp_path, mjcf=heavier_link2(MJCF), suites=["inertia"])
    (total,) = [f for f in result.findings if f.kind == "total_mass"]
    assert total.magnitude == pytest.approx(1.0 + 0.9 - LINK2_MASS, rel=1e-9)
    assert total.values["causes"] == ["world_parts", "mass_difference"]
    assert not [f for f in run(tmp_path).findings if f.kind == "total_mass"]  # the world mount alone: said already
    assert kinds(result) == [("mass_difference", "link2")]


def test_a_base_welded_to_the_world_is_sized_by_its_mass_beyond_the_mass_tolerance_else_by_its_inertia(tmp_path):
    """The MJCF's base 0.1 kg heavier with its centre of mass 1 cm up, beside the MJCF's 1 kg world
    mount: one warning for the base (it cannot move), sized 1.1 kg; with a mass tolerance of 2 kg
    the masses agree, so it is sized by its inertia and no total mass is said."""
    mjcf = P.sub_once(
        r'<inertial pos="0.0 0.0 0.0" mass="1.5707963267948968"', '<inertial pos="0.0 0.0 0.01" mass="1.6707963267948968"', MJCF
    )
    for tolerances, unit in (({}, "kg"), ({"inertia.mass": 2.0}, "kg·m²")):
        result = run(tmp_path, mjcf=mjcf, tolerances=tolerances)
        (f,) = [f for f in result.findings if f.kind == "base_inertial_difference"]
        assert (f.subject, f.severity, f.unit) == ("base", "warning", unit)
        assert f.magnitude == pytest.approx(1.1 if unit == "kg" else f.values["inertia_kgm2"], rel=1e-9)
        total = [f.magnitude for f in result.findings if f.kind == "total_mass"]
        assert total == ([pytest.approx(1.1, rel=1e-9)] if unit == "kg" else [])


def test_fk_agreeing_to_the_written_precision_is_one_rounding_note_naming_the_rounded_number(tmp_path):
    """Both files turn link3 a quarter turn about x; the URDF writes it rpy 1.5708 (π/2 to 4
    decimals, 3.7e-6 rad off), the MJCF exactly. A pass with one rounding note, from link3 on,
    naming the number as written and the constant it rounds."""
    urdf = P.sub_once(r'(<joint name="joint3".*?<origin xyz="0\.0 0\.0 0\.25" rpy=")0\.0 ', lambda m: m[1] + "1.5708 ", URDF)
    mjcf = P.sub_once(r'(<body name="link3")', lambda m: m[1] + ' quat="0.7071067811865476 0.7071067811865475 0 0"', MJCF)
    result = run(tmp_path, urdf=urdf, mjcf=mjcf, suites=["kinematics"])
    assert result.verdict == "pass"
    (f,) = [f for f in result.findings if f.kind == "rounding"]
    assert (f.subject, f.other) == ("link3", "link3") and f.magnitude == pytest.approx(1.5708 - math.pi / 2, rel=1e-3)
    assert "the URDF writes 1.5708 for π/2 at joint3 (rounded to 4 decimals)" in f.message
    assert f.values["culprits"] == [["URDF", "joint3", "1.5708", "π/2", 4]]
    raised = [c for c in result.checks if "written precision" in c.note]
    assert raised and all(c.passed for c in raised)


def test_the_kinematics_a_moved_joint_frame_fails_are_its_findings(tmp_path):
    """link3 1 mm higher in the MJCF (the end effector with it): one moved frame, joint3's; every
    kinematics check it fails is marked explained by it, so nothing else is said (no disagreement
    starting there, no frame convention)."""
    mjcf = P.body_attr(MJCF, "link3", "pos", lambda v: "0.0 0.0 0.251")
    result = run(tmp_path, mjcf=mjcf, suites=["kinematics"])
    assert kinds(result) == [("joint_origin_moved", "joint3")]
    (moved,) = [f for f in result.findings if f.kind == "joint_origin_moved"]
    assert moved.magnitude == pytest.approx(1e-3, rel=1e-6)
    assert not [f for f in result.findings if f.kind in ("frame_convention", "disagreement_starts")]
    explained = [c for c in result.checks if c.kind == "explained"]
    assert explained and all(c.note.endswith("explained by joint_origin_moved on joint joint3") for c in explained)
    assert all(c.passed for c in result.checks if c.kind != "explained") and result.verdict == "fail"


def test_accepted_differences_are_written_for_review_and_then_accept_the_finding(tmp_path):
    path = tmp_path / "accepted.toml"
    first = run(tmp_path, write_accepted=str(path))
    assert f"accepted differences written to {path}: review each entry and give its reason" in first.notes
    text = path.read_text()
    assert f"{tmp_path}/robot.urdf + {tmp_path}/robot.xml" in text and 'kind = "damping_difference"' in text
    path.write_text(text.replace('reason = ""', 'reason = "tuned on the real arm"'))
    second = run(tmp_path, accept=str(path))
    (f,) = [f for f in second.findings if f.kind == "damping_difference"]
    assert f.accepted and f.values["accepted_reason"] == "tuned on the real arm" and second.verdict == "pass"
    # the accepted magnitude is kept to the damping's tolerance: 0.25 against 0.2 is another difference
    path.write_text(re.sub(r"magnitude = 0\.(1999+\d*|2)\n", "magnitude = 0.25\n", path.read_text()))
    third = run(tmp_path, accept=str(path))
    assert not [f for f in third.findings if f.accepted] and third.verdict == "fail"


def test_the_report_keeps_the_files_the_joint_and_frame_pairs_and_the_notes(tmp_path):
    result = run(tmp_path)
    assert result.model_info["files"] == {"urdf": f"{tmp_path}/robot.urdf", "mjcf": f"{tmp_path}/robot.xml"}
    assert result.model_info["joint_pairs"] == [
        ["joint1", "joint1", "name"],
        ["joint2", "joint2", "name"],
        ["joint3", "joint3", "name"],
    ]
    assert ["end_effector", "end_effector", "same name"] in result.model_info["frame_pairs"]
    assert result.model_info["frame_pairs"][0] == ["base", "base", "joint1 hangs from it"]
    assert [n for n in result.notes if n.startswith("written precision: the URDF writes")]
    section = result.sections["filemode"]
    assert [f["kind"] for f in section.data["findings"]] == [f.kind for f in result.findings]


def test_a_mass_from_an_absent_mesh_leaves_the_dynamics_uncompared(tmp_path):
    """The MJCF's link2 states no <inertial> and its geom is a mesh file that is absent: its mass is
    not known, so no dynamics are compared (a placeholder mass would make them meaningless)."""
    mjcf = P.sub_once(r'(<body name="link2"[^>]*>.*?)<inertial [^>]*/>', lambda m: m[1], MJCF)
    mjcf = P.sub_once(r'<geom name="link2_geom"[^>]*/>', '<geom name="link2_mesh" type="mesh" mesh="link2"/>', mjcf)
    mjcf = P.sub_once(r"<worldbody>", '<asset><mesh name="link2" file="absent/link2.stl"/></asset><worldbody>', mjcf)
    result = run(tmp_path, mjcf=mjcf.replace(' inertiafromgeom="false"', ""), suites=["dynamics"])
    dynamics = result.sections["dynamics"]
    assert dynamics.summary == "not compared: the masses of link2 come from mesh files that are absent (see mass_unknown)"
    assert not [c for c in result.checks if c.property.startswith("dynamics.")] and "dynamics" not in result.timings


def test_an_accepted_difference_without_a_property_must_have_its_size_exactly(tmp_path):
    """link3 1 mm higher in the MJCF: joint3's moved frame accepted at 1 mm passes; at 2 mm it is
    another difference (no property's tolerance to allow for: the size as recorded)."""
    mjcf = P.body_attr(MJCF, "link3", "pos", lambda v: "0.0 0.0 0.251")
    path = tmp_path / "accepted.toml"
    for size, accepted in ((0.001, True), (0.002, False)):
        path.write_text(
            f'[[accepted]]\nkind = "joint_origin_moved"\nsubject = "joint3"\nmagnitude = {size!r}\nreason = "as built"\n'
        )
        result = run(tmp_path, mjcf=mjcf, accept=str(path))
        (f,) = [f for f in result.findings if f.kind == "joint_origin_moved"]
        assert (f.property, f.accepted, result.verdict) == ("", accepted, "pass" if accepted else "fail")


@pytest.mark.parametrize("other", ["urdf", "mjcf"])
def test_a_usd_side_has_no_xml_to_find_rounded_constants_in(tmp_path, other):
    """The arm as USD beside its URDF (the USD second) or its MJCF (the USD first): the rounded
    constants are looked for in the other file alone, and the findings are made (no internal error
    from reading a USD as XML)."""
    pytest.importorskip("pxr")
    text, name, backend = {"urdf": (URDF, "arm.urdf", "pinocchio-urdf"), "mjcf": (MJCF, "arm.xml", "mujoco")}[other]
    (tmp_path / name).write_text(text)
    (tmp_path / "arm.usda").write_text(generate_usd(load_spec(MODELS / "arm3.toml")))
    files = {other: str(tmp_path / name), "usd": str(tmp_path / "arm.usda")}
    order = ("urdf", "usd") if other == "urdf" else ("usd", "mjcf")
    opts = dataclasses.replace(BASE, backends=[backend, "usd"], suites=[])
    result = verify_files(*(files[k] for k in order), opts, kinds=order)
    assert result.internal_errors == [] and result.verdict == "pass"
    assert result.model_info["files"] == files


def test_a_frame_convention_where_nothing_differs_is_kept(tmp_path):
    """link1's frame turned a quarter turn about its own joint (z) in the MJCF, all it holds turned
    back: the same robot, another choice of frame; said as a convention, and a pass."""
    result = run(tmp_path, mjcf=P.reframed_body(MJCF, "link1", math.pi / 2), suites=["kinematics"])
    (f,) = [f for f in result.findings if f.kind == "frame_convention"]
    assert f.subject == "link1" and f.magnitude == pytest.approx(math.pi / 2, rel=1e-9)
    assert result.verdict == "pass" and kinds(result) == []


def test_no_frame_convention_is_claimed_where_a_disagreement_starts(tmp_path):
    """link1's frame turned a quarter turn about its joint in the MJCF, and joint1's axis tilted by
    1e-10 rad: within the alignment's tolerance (a convention, the motion agreeing), but the user
    asks for 1e-12 rad. The frames from link1 on turn apart by up to 2·sin(q/2)·1e-10 rad (2e-10 at
    joint1's limit π): one disagreement from link1, and no convention claimed there."""
    mjcf = P.joint_attr(P.reframed_body(MJCF, "link1", math.pi / 2), "joint1", "axis", lambda s: "1e-10 0.0 1.0")
    strict = run(tmp_path, mjcf=mjcf, suites=["kinematics"], tolerances={"fk.rotation": 1e-12})
    assert kinds(strict) == [("disagreement_starts", "link1")] and strict.verdict == "fail"
    (f,) = [f for f in strict.findings if f.kind == "disagreement_starts"]
    assert f.values["frames"] == ["link1", "link2", "link3", "end_effector"]
    assert f.magnitude == pytest.approx(2e-10, rel=1e-3)
    assert not [f for f in strict.findings if f.kind == "frame_convention"]
    default = run(tmp_path, mjcf=mjcf, suites=["kinematics"])  # the tilt within the default 1e-9 rad
    assert [(f.kind, f.subject) for f in default.findings if f.kind == "frame_convention"] == [("frame_convention", "link1")]
    assert default.verdict == "pass"


def test_an_accepted_size_may_move_by_its_propertys_tolerance(tmp_path):
    """A damping tolerance of 0.1 set by the user: joint2's 0.2 difference accepted at 0.25 is the
    same difference (0.05 apart, within 0.1); at 0.35 it is another."""
    path = tmp_path / "accepted.toml"
    for size, accepted in ((0.25, True), (0.35, False)):
        path.write_text(
            f'[[accepted]]\nkind = "damping_difference"\nsubject = "joint2"\nmagnitude = {size!r}\nreason = "tuned"\n'
        )
        result = run(tmp_path, accept=str(path), tolerances={"dynamics.damping": 0.1})
        (f,) = [f for f in result.findings if f.kind == "damping_difference"]
        assert (f.property, f.accepted) == ("dynamics.damping", accepted)


def test_the_note_says_which_of_its_inertial_mujocos_compiler_changed():
    def part(axes: bool, centre: bool):
        return dataclasses.make_dataclass("Part", ["snapped", "snapped_com"])(axes, centre)

    assert _snap_note([part(False, False)]) == ""
    assert _snap_note([part(True, False)]) == " (MuJoCo aligned its principal axes with the body frame)"
    assert _snap_note([part(False, True), part(False, False)]) == " (MuJoCo put its centre of mass at the body origin)"
    assert _snap_note([part(True, False), part(False, True)]) == (
        " (MuJoCo aligned its principal axes with the body frame and put its centre of mass at the body origin)"
    )
