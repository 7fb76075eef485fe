"""Rigid bodies compared where they are: each decision pinned by a pair built for it. Link frames
turned (as UR-style files turn them by rpy in the URDF, by quaternions in the MJCF) never move an
inertial; a body whose joint an upstream difference displaces is compared in the frame it hangs from;
what a joint in one file only moves is said once, with that joint; a mass from an absent mesh is
not compared; an inertial one file leaves unset is a warning."""

from __future__ import annotations

import math

import pytest

import tests.filemode.pairs as P
from kinverify.filemode.pipeline import verify_files
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import spec_from_dict
from kinverify.run import VerifyOptions
from tests.filemode.findings.test_alignment import quadruped

FAST = VerifyOptions(
    samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], extra={"dynamics_samples": 12}, suites=P.NO_PICTURES
)


def serious(result) -> list:
    return sorted((f.kind, f.subject) for f in result.findings if f.severity != "info" and not P.ignored_by_drake(f))


def run(tmp_path, urdf, mjcf, options=FAST):
    return verify_files(*P.write_pair(tmp_path, urdf, mjcf), options)


def moved_com(mjcf: str, body: str, dx: float) -> str:
    return P.sub_once(
        rf'(<body name="{body}".*?<inertial pos=")([^"]*)(")',
        lambda m: m[1] + P.nums(lambda v: [v[0] + dx, v[1], v[2]])(m[2]) + m[3],
        mjcf,
    )


def test_link_frames_turned_and_an_axis_upstream_moved_leave_each_centre_of_mass_its_own(tmp_path):
    """The MJCF turns panda_link5's and panda_link6's frames about their joints (a choice), moves
    joint 3's frame and axis 1 mm (a difference upstream of every wrist body) and moves panda_link6's
    centre of mass 2 cm along its own x (a difference of that body): one finding of the moved frame,
    one centre-of-mass finding of 2 cm, nothing on the other bodies the frame carries."""
    urdf, mjcf = P.moved_axis(*P.generated_pair("panda"))
    mjcf = moved_com(mjcf, "panda_link6", 0.02)  # before turning the frame: 2 cm along the link's own x
    mjcf = P.reframed_body(P.reframed_body(mjcf, "panda_link5", math.pi / 2), "panda_link6", -math.pi / 3)
    result = run(tmp_path, urdf, mjcf)
    assert serious(result) == [("com_difference", "panda_link6"), ("joint_origin_moved", "panda_joint3")]
    (com,) = [f for f in result.findings if f.kind == "com_difference"]
    assert com.magnitude == pytest.approx(0.02, abs=1e-9)


def test_a_part_a_joint_in_one_file_only_moves_is_said_once(tmp_path):
    """The URDF carries a small propeller on a joint the MJCF does not have, on panda_link7: one
    extra_parts finding with its mass, and panda_link7 itself agrees."""
    urdf, mjcf = P.generated_pair("panda")
    prop = (
        '<link name="prop"><inertial><origin xyz="0 0 0.01"/><mass value="0.004"/>'
        '<inertia ixx="1e-7" iyy="1e-7" izz="1e-7" ixy="0" ixz="0" iyz="0"/></inertial></link>'
        '<joint name="prop_joint" type="continuous"><parent link="panda_link7"/><child link="prop"/>'
        '<origin xyz="0 0 0.05"/><axis xyz="0 0 1"/></joint></robot>'
    )
    result = run(tmp_path, P.sub_once(r"</robot>", prop, urdf), mjcf)
    assert serious(result) == [("extra_parts", "prop_joint")]
    (extra,) = [f for f in result.findings if f.kind == "extra_parts"]
    assert extra.values["links"] == [{"name": "prop", "mass": 0.004, "body": "panda_link7", "how": "moved by prop_joint"}]


def link4_from_absent_mesh(mjcf: str, mass: str = "") -> str:
    """panda_link4 with no <inertial>, its geom an absent mesh (stating ``mass`` when given), and
    MuJoCo's default that a body without <inertial> weighs its geoms."""
    mjcf = P.sub_once(r'(<body name="panda_link4"[^>]*>.*?)<inertial [^>]*/>', lambda m: m[1], mjcf)
    mjcf = P.sub_once(
        r'(<body name="panda_link4"[^>]*>.*?)<geom name="panda_link4_geom"[^>]*/>',
        lambda m: m[1] + f'<geom name="panda_link4_mesh" type="mesh" mesh="link4"{mass}/>',
        mjcf,
    )
    mjcf = P.sub_once(r"<worldbody>", '<asset><mesh name="link4" file="absent/link4.stl"/></asset><worldbody>', mjcf)
    return mjcf.replace(' inertiafromgeom="false"', "")


def test_a_mass_that_came_from_an_absent_mesh_is_not_compared(tmp_path):
    """The MJCF's panda_link4 has no <inertial>: MuJoCo would take its mass from its mesh, which is
    absent. Its mass is not known, so it is not compared: a warning, and the verdict passes."""
    urdf, mjcf = P.generated_pair("panda")
    mjcf = link4_from_absent_mesh(mjcf)
    result = run(tmp_path, urdf, mjcf)
    assert serious(result) == [("mass_unknown", "panda_link4")] and result.passed


def test_an_inertial_one_file_leaves_unset_is_a_warning(tmp_path):
    """The URDF's panda_link6 states no <inertial> (massless by default); the MJCF states one."""
    urdf, mjcf = P.generated_pair("panda")
    urdf = P.sub_once(r'(<link name="panda_link6">.*?)<inertial>.*?</inertial>', lambda m: m[1], urdf)
    result = run(
        tmp_path,
        urdf,
        mjcf,
        VerifyOptions(samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics", "inertia"]),
    )
    (unset,) = [f for f in result.findings if f.kind == "inertial_unset"]
    assert unset.severity == "warning" and unset.values["unset_in"] == "URDF" and unset.subject == "panda_link6"
    assert serious(result) == [("inertial_unset", "panda_link6")] and result.passed


def test_a_base_whose_mass_sits_on_a_fixed_child_link_is_one_body(tmp_path):
    """The URDF's floating trunk states no inertial; its mass sits on a fixed child link
    (trunk_inertia), as Spot's URDF does. The MJCF's trunk is 20 % heavier: one mass_difference on
    the trunk, not two extra parts (one in each file) that hide it."""
    spec = quadruped()
    urdf = generate_urdf(spec_from_dict(spec))
    inertial = P.re.search(r'<link name="trunk">\s*(<inertial>.*?</inertial>)', urdf, P.re.S)[1]
    urdf = urdf.replace(inertial, "", 1)
    urdf = P.sub_once(
        r"</robot>",
        f'<link name="trunk_inertia">{inertial}</link><joint name="trunk_inertia_fixed" '
        'type="fixed"><parent link="trunk"/><child link="trunk_inertia"/></joint></robot>',
        urdf,
    )
    spec["base"]["link"]["mass"] = 7.2
    mjcf = generate_mjcf(spec_from_dict(spec))
    result = run(
        tmp_path,
        urdf,
        mjcf,
        VerifyOptions(samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics", "inertia"]),
    )
    assert serious(result) == [("mass_difference", "trunk")]
    (f,) = [f for f in result.findings if f.kind == "mass_difference"]
    assert (f.values["urdf"]["mass"], f.values["mjcf"]["mass"]) == pytest.approx((6.0, 7.2))


def test_a_mesh_that_states_its_mass_keeps_the_mass_compared(tmp_path):
    """The MJCF's panda_link4 has no <inertial>; its absent mesh geom states mass="4": the body's
    mass is known (and differs from the URDF's 3.59 kg), its centre of mass and inertia are not."""
    urdf, mjcf = P.generated_pair("panda")
    mjcf = link4_from_absent_mesh(mjcf, ' mass="4"')
    result = run(
        tmp_path,
        urdf,
        mjcf,
        VerifyOptions(samples=8, fd_samples=4, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics", "inertia"]),
    )
    assert serious(result) == [("mass_difference", "panda_link4")]
    (f,) = [f for f in result.findings if f.kind == "mass_difference"]
    assert f.values["mjcf"]["mass"] == pytest.approx(4.0) and "not compared" in f.message


def test_a_body_on_a_joint_one_file_lacks_is_that_joints_even_where_a_first_joint_hangs_from_it(tmp_path):
    """The MJCF hangs panda_link1 (and joint 1) from a 10 kg suspension on a slide joint the URDF
    lacks. The URDF's joint 1 hangs from panda_link0, the MJCF's from the suspension: those two are
    not one frame, and the suspension is no twin of the base. The 10 kg are the extra part; the
    base agrees."""
    urdf, mjcf = P.generated_pair("panda")
    result = run(tmp_path, urdf, P.suspended(mjcf, "panda_link1", 10.0))
    pairs = [tuple(p[:2]) for p in result.model_info["frame_pairs"]]
    assert ("panda_link0", "suspension") not in pairs
    (extra,) = [f for f in result.findings if f.kind == "extra_parts"]
    assert extra.values["file"] == "MJCF" and extra.values["mass_kg"] == pytest.approx(10.0)
    assert [p["name"] for p in extra.values["links"]] == ["suspension"]
    assert not [f for f in result.findings if f.kind in ("mass_difference", "com_difference", "inertia_difference")]
