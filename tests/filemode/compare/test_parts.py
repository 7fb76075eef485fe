"""What one file has and the other lacks, each said once: the decisions of
kinverify.filemode.compare.parts pinned on hand-built descriptions (tests/filemode/compare/test_inertials.py's
arm: a base and two links), compared by the inertials module as file mode compares them."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kinverify.filemode.compare.inertials import ROOT, Difference, Group, GroupResult, Inertial, Part, analyse
from kinverify.filemode.compare.parts import _is_world, _moved_by, frame_twins, part_findings, total_mass_finding
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.precision import Floors
from tests.filemode.compare.test_inertials import (
    DEFAULTS,
    FRAMES,
    arm,
    body,
    info_of,
    joint,
    pose,
    prop,
    with_tool,
)

TOL_MASS = 1e-6
CHECKS = [["inertia.mass", "rigid bodies"], ["inertia.com", "rigid bodies"], ["inertia.tensor", "rigid bodies"]]


def findings_of(u, m, **kw) -> list:
    info = info_of(u, m, **kw)
    return part_findings(info, analyse(info, DEFAULTS), TOL_MASS)


def spinner(d, names=("prop",), mass=0.1):
    """A joint only this file has, on link2, moving ``names`` (each ``mass`` kg, fixed together)."""
    d.joints.append(joint("prop_joint", "j2", names[0], "link2"))
    for k, name in enumerate(names):
        d.frames[name], d.frame_owner[name], d.frame_depth[name] = pose((0.0, 0.01 * k, 0.6)), "prop_joint", 3
        d.bodies.append(body(name, "prop_joint", mass, (0.0, 0.0, 0.01), (1e-5, 1e-5, 1e-5), d.frames[name]))
    return d


# --- extra parts --------------------------------------------------------------------------------


def test_a_part_on_a_joint_one_file_lacks_is_said_once_with_that_joint():
    (f,) = findings_of(prop(arm()), arm("mjcf"))
    assert (f.kind, f.severity, f.subject_type, f.subject) == ("extra_parts", "error", "joint", "prop_joint")
    assert (f.magnitude, f.unit) == (pytest.approx(0.1), "kg")
    assert f.values["file"] == "URDF" and f.values["joints"] == ["prop_joint"] and f.values["groups"] == ["j2"]
    assert f.values["links"] == [{"name": "prop", "mass": 0.1, "body": "link2", "how": "moved by prop_joint"}]
    assert f.values["mass_kg"] == pytest.approx(0.1)
    assert f.values["checks"] == CHECKS
    assert f.message == (
        "the URDF has parts the MJCF lacks: joint prop_joint; link prop (0.1 kg, moved by prop_joint): 0.1 kg in all, "
        "left out when comparing the rigid bodies they join (link2) (not compared; held at zero)"
    )


def test_the_mjcfs_extra_joint_is_said_by_the_mjcf():
    (f,) = findings_of(arm(), prop(arm("mjcf")))
    assert f.values["file"] == "MJCF" and f.subject == "prop_joint"
    assert f.message.startswith("the MJCF has parts the URDF lacks: joint prop_joint; link prop (0.1 kg, moved by prop_joint)")


def test_a_joint_one_file_lacks_that_moves_no_mass_counts_joints():
    u = arm()
    u.joints.append(joint("probe", "j2", "probe_link", "link2"))
    (f,) = findings_of(u, arm("mjcf"))
    assert (f.kind, f.subject, f.magnitude, f.unit) == ("extra_parts", "probe", 1.0, "joints")
    assert f.values["links"] == [] and f.values["mass_kg"] == 0 and f.values["groups"] == []
    assert f.message == "the URDF has parts the MJCF lacks: joint probe (not compared; held at zero)"
    u.joints.append(joint("probe2", "j2", "probe_link2", "link2"))
    (f,) = findings_of(u, arm("mjcf"))
    assert (f.subject, f.magnitude) == ("probe, probe2", 2.0)
    assert f.message.startswith("the URDF has parts the MJCF lacks: joints probe, probe2 (not")


def test_a_fixed_part_one_file_has_is_named_by_its_link():
    (f,) = findings_of(with_tool(arm()), arm("mjcf"))
    assert (f.kind, f.subject_type, f.subject, f.magnitude) == ("extra_parts", "link", "tool", pytest.approx(0.5))
    assert f.values["links"] == [{"name": "tool", "mass": 0.5, "body": "link2", "how": "fixed to link2"}]
    assert f.values["joints"] == [] and f.values["groups"] == ["j2"]
    assert f.message == (
        "the URDF has parts the MJCF lacks: link tool (0.5 kg, fixed to link2): 0.5 kg in all, "
        "left out when comparing the rigid bodies they join (link2)"
    )


def test_several_parts_add_up_and_many_are_listed_briefly():
    (f,) = findings_of(spinner(arm(), ("r1", "r2")), arm("mjcf"))
    assert f.magnitude == pytest.approx(0.2) and f.subject == "prop_joint"
    assert "links r1 (0.1 kg, moved by prop_joint), r2 (0.1 kg, moved by prop_joint): 0.2 kg in all" in f.message
    (f,) = findings_of(spinner(arm(), ("r1", "r2", "r3", "r4", "r5")), arm("mjcf"))
    assert "links r1 (0.1 kg), r2 (0.1 kg), r3 (0.1 kg), r4 (0.1 kg), r5 (0.1 kg): 0.5 kg in all" in f.message
    assert f.values["links"][4] == {"name": "r5", "mass": 0.1, "body": "link2", "how": "moved by prop_joint"}
    (f,) = findings_of(spinner(arm(), ("r1", "r2", "r3", "r4")), arm("mjcf"))  # four: each said in full
    assert "r4 (0.1 kg, moved by prop_joint): 0.4 kg in all" in f.message
    # many parts, but a fixed one keeps saying how it is fixed
    u = with_tool(spinner(arm(), ("r1", "r2", "r3", "r4")))
    (f,) = findings_of(u, arm("mjcf"))
    assert "r4 (0.1 kg), tool (0.5 kg, fixed to link2)" in f.message


def test_parts_on_several_bodies_name_each_body_once_in_order():
    u = with_tool(arm())
    u.frames["cam"], u.frame_owner["cam"], u.frame_depth["cam"] = pose((0.0, 0.0, 0.3)), "j1", 2
    u.bodies.insert(2, body("cam", "j1", 0.25, (0.0, 0.0, 0.0), (1e-5, 1e-5, 1e-5), u.frames["cam"]))
    (f,) = findings_of(u, arm("mjcf"))
    assert f.values["groups"] == ["j1", "j2"] and f.subject == "cam, tool"
    assert "0.75 kg in all, left out when comparing the rigid bodies they join (link1, link2)" in f.message


def test_parts_with_no_twin_in_a_body_that_still_differs_are_no_extra_parts():
    m = arm("mjcf")
    m.bodies[2].mass = 1.2
    fs = findings_of(with_tool(arm()), m)
    assert [f.kind for f in fs] == []


# --- unset inertials, unknown masses --------------------------------------------------------------


def test_an_inertial_the_urdf_leaves_unset_is_said_by_the_urdf():
    u = arm()
    u.bodies.pop(2)
    u.no_inertial = {"link2"}
    (f,) = findings_of(u, arm("mjcf"))
    assert (f.kind, f.severity, f.subject, f.magnitude, f.unit) == ("inertial_unset", "warning", "link2", 1.0, "kg")
    assert f.values["unset_in"] == "URDF" and f.values["checks"] == CHECKS
    assert f.values["links"] == [{"name": "link2", "other": "link2", "mass": 1.0, "body": "link2"}]
    assert f.message == (
        "the URDF leaves the inertial of 1 link unset (massless by default); the MJCF states it: link2 (1 kg in the MJCF)"
    )


def test_inertials_the_mjcf_leaves_unset_are_said_by_the_mjcf():
    m = arm("mjcf")
    del m.bodies[1:]
    m.no_inertial = {"link1", "link2"}
    (f,) = findings_of(arm(), m)
    assert f.values["unset_in"] == "MJCF" and f.subject == "link1, link2" and f.magnitude == pytest.approx(3.0)
    assert f.message.startswith("the MJCF leaves the inertial of 2 links unset")
    assert "the URDF states it: link1 (2 kg in the URDF), link2 (1 kg in the URDF)" in f.message


def test_a_mass_from_an_absent_mesh_is_said_not_compared():
    m = arm("mjcf")
    m.bodies[1].mass_known = False
    (f,) = findings_of(arm(), m)
    assert (f.kind, f.severity, f.subject) == ("mass_unknown", "warning", "link1")
    assert f.message.startswith("1 rigid body not compared: part of the mass comes from mesh files that are absent")
    assert f.message.endswith("<inertial>): link1 (MJCF)")
    assert f.values["bodies"] == ["link1"] and f.values["parts"] == [["MJCF", "link1"]] and f.values["checks"] == CHECKS
    u = arm()
    u.bodies[2].mass_known = False
    (f,) = findings_of(u, m)
    assert f.message.startswith("2 rigid bodies not compared") and f.message.endswith("link1 (MJCF), link2 (URDF)")
    assert f.subject == "link1, link2"


def test_a_body_is_moved_by_its_nearest_unmatched_ancestor_joint():
    d = spinner(arm(), ("r1",))
    d.joints.append(joint("tip", "prop_joint", "r9", "r1"))
    d.bodies.append(body("r9", "tip", 0.1))
    assert _moved_by(d, ["prop_joint"]) == {"r1": "prop_joint", "r9": "prop_joint"}
    assert _moved_by(d, ["prop_joint", "tip"]) == {"r1": "prop_joint", "r9": "tip"}
    assert _moved_by(d, []) == {}


# --- lumped links ---------------------------------------------------------------------------------


def merged_tool(d):
    """The MJCF's link2 with the URDF's tool (0.5 kg) merged into it."""
    u = with_tool(arm())
    parts = [b for b in u.bodies if b.name in ("link2", "tool")]
    mass = sum(b.mass for b in parts)
    com = sum(b.mass * b.com for b in parts) / mass
    inertia = sum(
        b.inertia + b.mass * (np.dot(b.com - com, b.com - com) * np.eye(3) - np.outer(b.com - com, b.com - com)) for b in parts
    )
    frame = d.frames["link2"]
    rot = frame[:3, :3]
    d.bodies[2] = body("link2", "j2", mass, rot.T @ (com - frame[:3, 3]), rot.T @ inertia @ rot, frame)
    return d


def test_a_fixed_link_one_file_keeps_apart_and_the_other_merges_is_lumped():
    (f,) = findings_of(with_tool(arm()), merged_tool(arm("mjcf")))
    assert (f.kind, f.severity, f.subject, f.magnitude, f.unit) == ("lumped_links", "info", "tool", 0.5, "kg")
    assert f.values == {"file": "URDF", "links": [{"name": "tool", "mass": 0.5, "body": "link2"}]}
    assert f.message == (
        "the URDF keeps as separate fixed links what the MJCF merges into one body (the rigid bodies agree): tool (0.5 kg) in link2"
    )
    (f,) = findings_of(merged_tool(arm()), with_tool(arm("mjcf")))
    assert f.values["file"] == "MJCF" and f.message.startswith("the MJCF keeps as separate fixed links what the URDF merges")


def test_a_fixed_link_lumped_within_the_written_precision_is_lumped_too():
    m = merged_tool(arm("mjcf"))
    m.bodies[2].mass *= 1 + 1e-4  # within a relative floor of 1e-3: rounding
    (f,) = findings_of(with_tool(arm()), m, floors=Floors(relative=1e-3))
    assert (f.kind, f.subject) == ("lumped_links", "tool")


def test_a_link_welded_to_the_world_is_not_lumped():
    u = pedestal(arm())
    m = arm("mjcf")
    m.bodies[0] = body("base", None, 7.0, (0.0, 0.0, (4.0 * 0.05 - 3.0 * 0.1) / 7.0), (0.0, 0.0, 0.0))
    info = info_of(u, m)
    results = analyse(info, (1e-6, 1e-6, 1.0))
    assert results[0].status == "agree" and results[0].group.fixed_base_root
    assert part_findings(info, results, TOL_MASS) == []


def test_a_same_named_link_on_both_sides_is_not_lumped():
    # both files have the tool, not paired as frames: its twin is the same-named body of the same rigid body
    u, m = with_tool(arm()), with_tool(arm("mjcf"))
    assert findings_of(u, m, frames=[(f, f) for f in FRAMES]) == []


def test_a_massless_or_twinned_link_is_not_lumped_nor_one_a_joint_moves():
    assert findings_of(with_tool(arm(), 0.0), arm("mjcf")) == []
    assert [f.kind for f in findings_of(prop(arm()), arm("mjcf"))] == ["extra_parts"]


# --- the welded base --------------------------------------------------------------------------------


def pedestal(d, mass=3.0):
    d.frames["pedestal"], d.frame_owner["pedestal"], d.frame_depth["pedestal"] = pose((0.0, 0.0, -0.1)), None, 1
    d.bodies.append(body("pedestal", None, mass, (0.0, 0.0, 0.0), (0.01, 0.01, 0.01), d.frames["pedestal"]))
    return d


def test_bodies_welded_to_the_world_in_one_file_only_are_world_parts():
    (f,) = findings_of(pedestal(arm()), arm("mjcf"))
    assert (f.kind, f.severity, f.subject, f.magnitude, f.unit) == ("world_parts", "info", "pedestal", 3.0, "kg")
    assert f.values == {"links": [{"file": "URDF", "name": "pedestal", "mass": 3.0}]}
    assert f.message == (
        "bodies welded to the world of this fixed-base robot in one file only: pedestal (3 kg, URDF): "
        "part of the world, they cannot move the robot"
    )
    (f,) = findings_of(arm(), pedestal(arm("mjcf"), 2.0))
    assert f.values["links"] == [{"file": "MJCF", "name": "pedestal", "mass": 2.0}]


def test_a_floating_base_part_is_an_extra_part():
    info = info_of(pedestal(arm()), arm("mjcf"), floating=True)
    (f,) = part_findings(info, analyse(info, DEFAULTS), TOL_MASS)
    assert f.kind == "extra_parts" and f.values["links"][0]["how"] == "fixed to base"


def test_a_welded_base_that_differs_is_a_warning_that_moves_nothing():
    m = arm("mjcf")
    m.bodies[0].mass = 4.5
    (f,) = findings_of(arm(), m)
    assert (f.kind, f.severity, f.subject, f.magnitude, f.unit) == ("base_inertial_difference", "warning", "base", 0.5, "kg")
    assert f.values["urdf"] == 4.0 and f.values["mjcf"] == 4.5 and f.values["com_m"] == 0.0
    assert "the base (base, welded to the world) weighs 4 kg in the URDF and 4.5 kg in the MJCF" in f.message
    assert "centres of mass 0 m apart" in f.message and "changes no joint force" in f.message
    m.bodies[0].com_local = np.array([0.0, 0.0, 0.08])
    (f,) = findings_of(arm(), m)
    assert "centres of mass 0.03 m apart" in f.message and f.values["com_m"] == pytest.approx(0.03)
    # the same mass, another inertia: the tensor's difference is its size
    m = arm("mjcf")
    m.bodies[0].inertia_local = np.diag([0.04, 0.04, 0.05])
    (f,) = findings_of(arm(), m)
    assert (f.magnitude, f.unit) == (pytest.approx(0.03), "kg·m²")
    assert f.values["inertia_kgm2"] == pytest.approx(0.03)
    assert "ΔI 0.03 kg·m²" in f.message


def test_a_welded_base_mass_within_the_mass_tolerance_is_sized_by_its_tensor():
    m = arm("mjcf")
    m.bodies[0].mass = 4.0 + 1e-7
    m.bodies[0].inertia_local = np.diag([0.04, 0.04, 0.05])
    info = info_of(arm(), m)
    (f,) = part_findings(info, analyse(info, DEFAULTS), 1e-6)
    assert (f.magnitude, f.unit) == (pytest.approx(0.03), "kg·m²")
    (f,) = part_findings(info, analyse(info, DEFAULTS), 1e-8)
    assert (f.magnitude, f.unit) == (pytest.approx(1e-7), "kg")


def test_a_units_mistake_is_not_said_again_by_the_base():
    u = arm()
    for b in u.bodies:
        b.mass *= 1000.0  # grams: every moving body 1000 times heavier
    assert findings_of(u, arm("mjcf")) == []
    u.bodies[2].mass = 999.0  # not uniform: the base's difference is said
    assert "base_inertial_difference" in [f.kind for f in findings_of(u, arm("mjcf"))]


def test_a_welded_base_within_the_written_precision_says_nothing():
    m = arm("mjcf")
    m.bodies[0].mass = 4.001
    assert findings_of(arm(), m, floors=Floors(relative=1e-3)) == []
    assert [f.kind for f in findings_of(arm(), m)] == ["base_inertial_difference"]


def test_a_welded_base_that_agrees_or_is_unknown_says_nothing():
    m = arm("mjcf")
    m.bodies[0].mass, m.bodies[0].mass_known = 9.0, False
    assert [f.kind for f in findings_of(arm(), m)] == ["mass_unknown"]
    u = arm()
    u.bodies.pop(0)
    u.no_inertial = {"base"}
    assert [f.kind for f in findings_of(u, arm("mjcf"))] == ["inertial_unset"]


# --- the total mass -------------------------------------------------------------------------------


def total(u_mass: float, m_mass: float, findings=(), relative=0.0, tol=1e-6):
    u, m = arm(), arm("mjcf")
    u.bodies[0].mass, m.bodies[0].mass = u_mass - 3.0, m_mass - 3.0
    return total_mass_finding(info_of(u, m, floors=Floors(relative=relative)), list(findings), tol)


def test_the_total_mass_difference_is_said_with_its_causes():
    extra = finding("extra_parts", "x", {"file": "MJCF"}, link="tool")
    f = total(7.0, 7.5, [extra, finding("com_difference", "y", link="link1")])
    assert (f.kind, f.severity, f.magnitude, f.unit) == ("total_mass", "info", pytest.approx(0.5), "kg")
    assert f.message == "total mass 7 kg (URDF), 7.5 kg (MJCF): +0.5 kg, from extra_parts (link tool)"
    assert f.values == {"urdf": 7.0, "mjcf": 7.5, "difference_kg": pytest.approx(0.5), "causes": ["extra_parts"]}
    f = total(7.5, 7.0)
    assert f.message == "total mass 7.5 kg (URDF), 7 kg (MJCF): -0.5 kg" and f.values["causes"] == []
    kinds = ["mass_difference", "mass_units", "world_parts", "base_inertial_difference"]
    f = total(7.0, 8.0, [finding(k, "z", link="base") for k in kinds])
    assert f.values["causes"] == kinds


def test_the_total_mass_within_its_tolerance_is_nothing():
    assert total(7.0, 7.5, tol=0.5) is None
    assert total(7.0, 7.5, tol=0.49) is not None
    assert total(7.0, 7.5, relative=0.5 / 7.5) is None  # relative to the heavier
    assert total(7.0, 7.5, relative=0.5 / 7.5 * 0.99) is not None


def test_a_total_mass_difference_of_world_parts_only_is_said_already():
    world = finding("world_parts", "w", link="pedestal")
    assert total(7.0, 10.0, [world]) is None
    f = total(7.0, 10.0, [world, finding("extra_parts", "x", link="tool")])
    assert f.values["causes"] == ["world_parts", "extra_parts"]


# --- frames with no same-named twin ----------------------------------------------------------------


def frame(d, name, at, owner="j2", depth=3, kind=None):
    d.frames[name], d.frame_owner[name], d.frame_depth[name] = at, owner, depth
    if kind:
        d.frame_kind[name] = kind
    return d


def tol(_frame):
    return 1e-6, 1e-6


def twins(u, m, **kw):
    return frame_twins(info_of(u, m, **kw), tol)


TCP = pose((0.0, 0.0, 0.7), 0.3)


def test_a_frame_at_the_same_place_under_another_name_is_its_twin():
    fs, pairs = twins(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "grip", TCP, kind="site"))
    assert pairs == [("tcp", "grip", "same place (no same-named twin)")]
    (f,) = fs
    assert (f.kind, f.severity, f.subject_type, f.subject, f.other) == ("frame_twin", "info", "frame", "tcp", "grip")
    assert f.message == "URDF frame tcp (no same-named MJCF frame) is the MJCF's site grip"
    assert (f.magnitude, f.unit) == (pytest.approx(0.0, abs=1e-15), "m")
    assert f.values["mjcf_frame"] == "grip" and f.values["rotation_rad"] == pytest.approx(0.0, abs=1e-12)
    fs, _ = twins(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "grip", TCP))
    assert fs[0].message.endswith("is the MJCF's frame grip")


def test_a_frame_near_another_is_not_its_twin_and_says_how_far():
    there = TCP @ pose((0.003, 0.004, 0.0), 0.2)
    fs, pairs = twins(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "grip", there, kind="site"))
    assert pairs == []
    (f,) = fs
    assert f.magnitude == pytest.approx(0.005, rel=1e-9) and f.values["rotation_rad"] == pytest.approx(0.2, rel=1e-9)
    assert f.message.startswith("URDF frame tcp (no same-named MJCF frame) is not the MJCF's site grip: nearest, 0.005 m away")
    assert f.message.endswith("in grip's axes) and turned 11.46°")
    rel = np.linalg.inv(there) @ TCP
    assert f.values["xyz"] == pytest.approx(rel[:3, 3].tolist(), abs=1e-12)
    assert str(np.round(rel[:3, 3], 6).tolist()) in f.message
    # moved only: no turn said
    fs, _ = twins(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "grip", TCP @ pose((0.005, 0.0, 0.0))))
    assert fs[0].message.endswith("(xyz [-0.005, 0.0, 0.0] in grip's axes)")
    # turned only: not the same either
    fs, pairs = twins(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "grip", TCP @ pose(rz=1e-3)))
    assert (
        pairs == [] and "is not the MJCF's frame grip: nearest, 0 m away" in fs[0].message and "turned 0.0573°" in fs[0].message
    )


def test_a_frame_with_nothing_near_has_no_twin():
    fs, pairs = twins(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "grip", TCP @ pose((0.0, 0.0, 0.02))))
    assert pairs == []
    assert fs[0].message == (
        "URDF frame tcp (no same-named MJCF frame) has no twin in the MJCF (the nearest MJCF frame on its body, grip, is 0.02 m away)"
    )
    fs, _ = twins(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "grip", TCP @ pose((0.0, 0.0, 0.0099))))
    assert "is not the MJCF's frame grip" in fs[0].message


def test_the_nearest_frame_on_the_same_body_is_chosen():
    m = frame(frame(arm("mjcf"), "far", TCP @ pose((0.002, 0.0, 0.0))), "near", TCP @ pose((0.001, 0.0, 0.0)))
    frame(m, "other_body", TCP, owner="j1")  # at the very place, but on link1's body
    (f,), _ = twins(frame(arm(), "tcp", TCP), m)
    assert f.other == "near" and f.magnitude == pytest.approx(0.001)
    # at the same distance, the less turned one
    m = frame(frame(arm("mjcf"), "a", TCP @ pose((0.001, 0.0, 0.0), 0.1)), "b", TCP @ pose((0.001, 0.0, 0.0), 0.05))
    (f,), _ = twins(frame(arm(), "tcp", TCP), m)
    assert f.other == "b"


def test_a_frame_already_matched_is_named_but_not_paired_again():
    u = frame(frame(arm(), "tcp", TCP), "tcp2", TCP)
    m = frame(frame(arm("mjcf"), "grip", TCP), "tip", TCP)
    fs, pairs = twins(u, m, frames=[(f, f) for f in FRAMES] + [("tcp2", "tip")])
    # "tip" is matched: "grip", equally near and not matched, is tcp's twin
    assert pairs == [("tcp", "grip", "same place (no same-named twin)")] and [f.subject for f in fs] == ["tcp"]
    fs, pairs = twins(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "tip", TCP), frames=[(f, f) for f in FRAMES] + [("x", "tip")])
    assert pairs == [] and fs[0].message.endswith("is the MJCF's frame tip")


def test_one_mjcf_frame_is_the_twin_of_one_urdf_frame_only():
    u = frame(frame(arm(), "tcp", TCP), "tcp_copy", TCP)
    fs, pairs = twins(u, frame(arm("mjcf"), "grip", TCP))
    assert pairs == [("tcp", "grip", "same place (no same-named twin)")]
    assert [(f.subject, f.other) for f in fs] == [("tcp", "grip"), ("tcp_copy", "grip")]


def test_frames_that_are_compared_otherwise_are_skipped():
    u = frame(arm(), "tcp", TCP, owner="ghost_joint")  # on a joint the MJCF lacks
    assert twins(u, frame(arm("mjcf"), "grip", TCP)) == ([], [])
    u = arm()  # a link with mass: compared as a rigid body
    u.frames["tcp"], u.frame_owner["tcp"], u.frame_depth["tcp"] = TCP, "j2", 3
    u.bodies.append(body("tcp", "j2", 0.1, at=TCP))
    assert twins(u, frame(arm("mjcf"), "grip", TCP)) == ([], [])
    # same-named frames are matched already
    assert twins(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "tcp", TCP)) == ([], [])
    # nothing of the MJCF on its body
    m = arm("mjcf")
    m.frames.pop("link2"), m.frame_owner.pop("link2"), m.frame_depth.pop("link2")
    m.bodies.pop(2)
    assert twins(frame(arm(), "tcp", TCP), m, frames=[("base", "base"), ("link1", "link1")]) == ([], [])


def test_a_frame_on_the_base_looks_among_the_base_frames():
    u = frame(arm(), "mount", pose((0.0, 0.0, 0.01)), owner=None, depth=1)
    m = frame(frame(arm("mjcf"), "mount_site", pose((0.0, 0.0, 0.01)), owner=None, depth=1), "up", pose((0.0, 0.0, 0.01)), "j1")
    (f,), pairs = twins(u, m)
    assert pairs == [("mount", "mount_site", "same place (no same-named twin)")]


def test_a_frame_on_a_joint_mapped_to_another_name_looks_on_the_mjcf_joint():
    m = frame(arm("mjcf"), "grip", TCP, owner="q2")
    m.frame_owner["link2"] = "q2"
    m.joints[1].name = "q2"
    (f,), pairs = twins(frame(arm(), "tcp", TCP), m, joints=[("j1", "j1"), ("j2", "q2")])
    assert f.other == "grip" and pairs == [("tcp", "grip", "same place (no same-named twin)")]


def test_the_mjcfs_frames_are_brought_through_the_alignment():
    shift = pose((1.0, 0.0, 0.0), 0.4)
    m = frame(arm("mjcf"), "grip", shift @ TCP)
    info = info_of(frame(arm(), "tcp", TCP), m)
    info.alignment.T = shift
    (f,), pairs = frame_twins(info, tol)
    assert pairs == [("tcp", "grip", "same place (no same-named twin)")] and f.magnitude == pytest.approx(0.0, abs=1e-12)


def test_the_tolerance_is_the_frames_own():
    there = TCP @ pose((0.0, 0.0, 2e-6))
    seen = []

    def loose(name):
        seen.append(name)
        return 3e-6, 1e-6

    fs, pairs = frame_twins(info_of(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "grip", there)), loose)
    assert seen == ["tcp"] and len(pairs) == 1
    assert twins(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "grip", there))[1] == []
    fs, pairs = frame_twins(info_of(frame(arm(), "tcp", TCP), frame(arm("mjcf"), "grip", TCP @ pose(rz=2e-6))), loose)
    assert pairs == [] and fs[0].message.endswith("and turned 0.0001146°")


def test_the_world_frame_is_no_frame_of_the_robot():
    world = frame(arm(), "world", pose(), owner=None, depth=0)
    assert _is_world(world, "world", pose())
    assert _is_world(frame(arm(), "world", pose(), owner=None, depth=1), "world", pose())
    assert not _is_world(frame(arm(), "world", pose(), owner=None, depth=2), "world", pose())
    assert not _is_world(world, "world", pose((1e-9, 0.0, 0.0)))
    assert _is_world(world, "world", pose((1e-13, 0.0, 0.0)))
    assert not _is_world(frame(arm(), "world", pose(), owner="j1", depth=0), "world", pose())
    assert not _is_world(arm(), "base", pose())  # a link with mass
    m = frame(arm("mjcf"), "origin", pose(), owner=None, depth=1)
    assert twins(world, m) == ([], [])
    # a massless root link away from the origin is a frame of the robot
    fs, _ = twins(frame(arm(), "world", pose((0.0, 0.0, 0.001)), owner=None, depth=0), m)
    assert [f.subject for f in fs] == ["world"]


def test_a_group_result_built_by_hand_reads_like_an_analysed_one():
    # part_findings reads only what GroupResult says: a hand-built explained base on a floating robot
    p = Part("skid", 2.0, np.zeros(3), np.zeros((3, 3)), None)
    g = Group(ROOT, "base", "base", [p], [], False)
    r = GroupResult(g, Inertial(2.0), Inertial(), Difference(2.0, 0.0, 0.0), (1e-6, 1e-6, 1e-6), "explained", extra=[p])
    info = info_of(arm(), arm("mjcf"))
    (f,) = part_findings(info, [r], TOL_MASS)
    assert f.values["links"] == [{"name": "skid", "mass": 2.0, "body": "base", "how": "fixed to base"}]
    assert math.isclose(f.magnitude, 2.0)
