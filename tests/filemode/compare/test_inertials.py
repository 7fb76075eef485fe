"""Rigid bodies' inertials compared: each decision of kinverify.filemode.compare.inertials pinned on
small hand-built descriptions (a base and two links), their expected values worked out by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kinverify.filemode.align.attribution import Attribution
from kinverify.filemode.align.match import Matching
from kinverify.filemode.align.result import Alignment, JointMap
from kinverify.filemode.compare.context import FileModeInfo
from kinverify.filemode.compare.inertials import (
    ROOT,
    Difference,
    Group,
    GroupResult,
    Inertial,
    Part,
    _axis_name,
    _base_body,
    _moved_by,
    _owner_key,
    analyse,
    carry_to_joints,
    combine,
    describe_tensors,
    difference,
    groups,
    principal,
    rounded_side,
    uniform_mass_ratio,
)
from kinverify.filemode.read.model import BodyInertial, JointDesc, ModelDesc, inertial_world
from kinverify.filemode.read.precision import Floors

DEFAULTS = (1e-6, 1e-6, 1e-7)


# --- hand-built descriptions ----------------------------------------------------------------------


def rot_z(angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def pose(xyz=(0.0, 0.0, 0.0), rz: float = 0.0) -> np.ndarray:
    t = np.eye(4)
    t[:3, :3] = rot_z(rz)
    t[:3, 3] = xyz
    return t


def body(name, owner, mass, com=(0.0, 0.0, 0.0), inertia=(0.01, 0.02, 0.03), at=None, **kw) -> BodyInertial:
    """A body whose inertial is stated in its frame, placed at ``at`` (its frame's world pose)."""
    local = np.diag(np.asarray(inertia, dtype=float)) if np.ndim(inertia) == 1 else np.asarray(inertia, dtype=float)
    com_w, inertia_w = inertial_world(pose() if at is None else at, np.asarray(com, dtype=float), local)
    return BodyInertial(owner, mass, com_w, inertia_w, name, np.asarray(com, dtype=float), local, **kw)


def joint(name, parent, child, parent_frame) -> JointDesc:
    return JointDesc(name, "revolute", parent, child, parent_frame, np.array([0.0, 0.0, 1.0]), np.zeros(3), -1.0, 1.0)


FRAMES = {"base": (pose(), None, 0), "link1": (pose((0, 0, 0.2)), "j1", 1), "link2": (pose((0, 0, 0.5), 0.5), "j2", 2)}


def model(kind, bodies, joints=None, frames=None, **kw) -> ModelDesc:
    frames = dict(FRAMES if frames is None else frames)
    joints = [joint("j1", None, "link1", "base"), joint("j2", "j1", "link2", "link1")] if joints is None else joints
    return ModelDesc(
        kind,
        kind,
        joints,
        {n: p for n, (p, _, _) in frames.items()},
        {n: o for n, (_, o, _) in frames.items()},
        {n: d for n, (_, _, d) in frames.items()},
        bodies,
        **kw,
    )


def arm_bodies(**mass) -> list[BodyInertial]:
    return [
        body("base", None, mass.get("base", 4.0), (0, 0, 0.05), (0.04, 0.04, 0.02)),
        body("link1", "j1", mass.get("link1", 2.0), (0, 0, 0.1), (0.02, 0.02, 0.01), FRAMES["link1"][0]),
        body("link2", "j2", mass.get("link2", 1.0), (0.1, 0, 0), (0.005, 0.01, 0.012), FRAMES["link2"][0]),
    ]


def arm(kind="urdf", **kw) -> ModelDesc:
    return model(kind, arm_bodies())


def info_of(u, m, joints=(("j1", "j1"), ("j2", "j2")), frames=None, floors=None, **kw) -> FileModeInfo:
    frames = [(f, f) for f in u.frames if f in m.frames] if frames is None else frames
    matching = Matching(
        [(a, b, "name") for a, b in joints],
        [j.name for j in u.joints if j.name not in {a for a, _ in joints}],
        [j.name for j in m.joints if j.name not in {b for _, b in joints}],
        [(a, b, "name") for a, b in frames],
    )
    alignment = Alignment(np.eye(4), [JointMap(a, b, "revolute") for a, b in joints], {}, [a for a, _ in joints])
    return FileModeInfo(u, m, matching, alignment, floors or Floors(), poses_u=dict(u.frames), poses_m=dict(m.frames), **kw)


def by_key(results) -> dict[str, GroupResult]:
    return {r.group.key: r for r in results}


# --- combine, difference ----------------------------------------------------------------------------


def test_combine_adds_masses_and_carries_each_inertia_to_the_common_centre():
    # two 1 kg points at the origin and at (2, 2, 0), plus a stated diag(1, 2, 3) at the first:
    # centre (1, 1, 0); Ixx = Σ m (y² + z²) = 2, Ixy = -Σ m x y = -2, Izz = Σ m (x² + y²) = 4
    total = combine([(1.0, np.zeros(3), np.diag([1.0, 2.0, 3.0])), (1.0, np.array([2.0, 2.0, 0.0]), np.zeros((3, 3)))])
    assert total.mass == 2.0
    np.testing.assert_allclose(total.com, [1.0, 1.0, 0.0])
    np.testing.assert_allclose(total.inertia, np.diag([1.0, 2.0, 3.0]) + [[2.0, -2.0, 0.0], [-2.0, 2.0, 0.0], [0.0, 0.0, 4.0]])


def test_combine_weights_the_centre_by_mass():
    total = combine([(1.0, np.zeros(3), np.zeros((3, 3))), (3.0, np.array([4.0, 0.0, 0.0]), np.zeros((3, 3)))])
    np.testing.assert_allclose(total.com, [3.0, 0.0, 0.0])
    np.testing.assert_allclose(total.inertia, np.diag([0.0, 12.0, 12.0]))  # 1·3² + 3·1²


def test_combine_of_nothing_massive_is_empty():
    for parts in ([], [(0.0, np.ones(3), np.eye(3))]):
        total = combine(parts)
        assert total.mass == 0.0
        np.testing.assert_array_equal(total.com, np.zeros(3))
        np.testing.assert_array_equal(total.inertia, np.zeros((3, 3)))


def test_difference_of_mass_centre_and_tensor():
    a = Inertial(1.0, np.array([0.0, 0.0, 0.0]), np.diag([2.0, 1.0, 1.0]))
    b = Inertial(3.0, np.array([3.0, 4.0, 0.0]), np.diag([1.0, 4.0, 1.0]))
    d = difference(a, b)
    assert (d.mass, d.com, d.tensor) == pytest.approx((2.0, 5.0, 3.0), rel=1e-12)  # eigenvalues of a - b: 1, -3, 0


def test_no_centre_of_mass_difference_when_one_side_weighs_nothing():
    heavy = Inertial(1.0, np.array([1.0, 0.0, 0.0]), np.eye(3))
    empty = Inertial()
    assert difference(heavy, empty).com == 0.0
    assert difference(empty, heavy).com == 0.0
    assert difference(empty, heavy).mass == 1.0


def test_within_needs_every_difference_within_its_tolerance_bound_included():
    d = Difference(1.0, 2.0, 3.0)
    assert d.within(1.0, 2.0, 3.0)
    assert not d.within(0.9, 2.0, 3.0)
    assert not d.within(1.0, 1.9, 3.0)
    assert not d.within(1.0, 2.0, 2.9)


# --- which rigid body a body belongs to ---------------------------------------------------------


def chain(held=()) -> ModelDesc:
    joints = [joint("j1", None, "link1", "base"), joint("j2", "j1", "link2", "link1"), joint("j3", "j2", "link3", "link2")]
    return model("urdf", [], joints, held=list(held))


def test_a_body_belongs_to_its_nearest_matched_joint_or_the_base():
    desc = chain()
    assert _owner_key(desc, "j3", {"j1": "J1"}) == "J1"
    assert _owner_key(desc, "j1", {"j1": "J1", "j3": "J3"}) == "J1"
    assert _owner_key(desc, "j3", {"j1": "J1", "j3": "J3"}) == "J3"
    assert _owner_key(desc, "j2", {}) == ROOT
    assert _owner_key(desc, None, {"j1": "J1"}) == ROOT


def test_a_body_is_moved_by_its_nearest_unmatched_joint_unless_held():
    assert _moved_by(chain(), "j3", {"j1": "J1"}) == "j3"
    assert _moved_by(chain(), "j3", {"j3": "J3"}) is None
    assert _moved_by(chain(held=["j3"]), "j3", {"j1": "J1"}) == "j2"  # a held joint moves nothing
    assert _moved_by(chain(held=["j3", "j2"]), "j3", {"j1": "J1"}) is None
    assert _moved_by(chain(), None, {}) is None
    assert _moved_by(chain(), "ghost", {}) is None  # not a joint of the file


def test_the_base_body_is_the_massive_unmoved_body_nearest_the_root():
    frames = {"world": (pose(), None, 0), "mount": (pose(), None, 1), "base": (pose(), None, 2), "link1": (pose(), "j1", 0)}
    bodies = [
        body("world", None, 0.0),  # massless
        body("base", None, 3.0),
        body("mount", None, 1.0),
        body("link1", "j1", 5.0),  # moves
        body("stray", None, 9.0),  # no frame
    ]
    assert _base_body(model("urdf", bodies, frames=frames)) == "mount"
    assert _base_body(model("urdf", bodies[:1] + bodies[3:], frames=frames)) is None


# --- groups -------------------------------------------------------------------------------------


def test_groups_pair_each_matched_joint_and_the_base():
    u, m = arm(), arm("mjcf")
    grps = groups(u, m, [("j1", "j1"), ("j2", "j2")], [(f, f) for f in FRAMES], dict(u.frames), dict(m.frames), False)
    assert [(g.key, g.urdf_link, g.mjcf_link, g.fixed_base_root) for g in grps] == [
        (ROOT, "base", "base", True),
        ("j1", "link1", "link1", False),
        ("j2", "link2", "link2", False),
    ]
    assert [[p.name for p in g.urdf] for g in grps] == [["base"], ["link1"], ["link2"]]
    assert all(p.twin == p.name and p.moved_by is None and p.unset_twin is None for g in grps for p in g.urdf + g.mjcf)
    floating = groups(u, m, [("j1", "j1"), ("j2", "j2")], [], dict(u.frames), dict(m.frames), True)
    assert not floating[0].fixed_base_root


def test_groups_name_joints_by_the_urdf_and_links_by_each_file():
    u = arm()
    frames_m = {"b0": FRAMES["base"], "b1": (FRAMES["link1"][0], "m1", 1), "b2": (FRAMES["link2"][0], "m2", 2)}
    bodies_m = [body("b0", None, 4.0), body("b1", "m1", 2.0), body("b2", "m2", 1.0)]
    m = model("mjcf", bodies_m, [joint("m1", None, "b1", "b0"), joint("m2", "m1", "b2", "b1")], frames_m)
    pairs = [("base", "b0"), ("link1", "b1"), ("link2", "b2")]
    grps = groups(u, m, [("j1", "m1"), ("j2", "m2")], pairs, dict(u.frames), dict(m.frames), False)
    assert [(g.key, g.urdf_link, g.mjcf_link) for g in grps] == [
        (ROOT, "base", "b0"),
        ("j1", "link1", "b1"),
        ("j2", "link2", "b2"),
    ]
    assert [[p.twin for p in g.mjcf] for g in grps] == [["base"], ["link1"], ["link2"]]
    assert [[p.twin for p in g.urdf] for g in grps] == [["b0"], ["b1"], ["b2"]]


def test_the_base_is_named_after_the_same_named_root_body_nearest_the_root():
    # both files have a massless "world" root frame (depth 0) and a "base" body: the base group is
    # named after the shallowest root frame in both files that carries a body in either
    frames = {"world": (pose(), None, 0), **{k: (p, o, d + 1) for k, (p, o, d) in FRAMES.items()}}
    u = model("urdf", arm_bodies(), frames=frames)
    m = model("mjcf", arm_bodies(), frames=frames)
    (root, *_) = groups(u, m, [("j1", "j1")], [], dict(u.frames), dict(m.frames), False)
    assert (root.urdf_link, root.mjcf_link) == ("base", "base")
    # a root frame that carries a body in one file only names it too
    m.bodies.append(body("world", None, 0.5))
    (root, *_) = groups(u, m, [("j1", "j1")], [], dict(u.frames), dict(m.frames), False)
    assert (root.urdf_link, root.mjcf_link) == ("world", "world")


def test_the_base_falls_back_to_each_files_massive_base_body_then_a_root_frame_pair():
    u = arm()
    frames_m = {"b0": FRAMES["base"], "b1": (FRAMES["link1"][0], "j1", 1), "b2": (FRAMES["link2"][0], "j2", 2)}
    m = model("mjcf", [body("b0", None, 4.0), body("b1", "j1", 2.0)], frames=frames_m)
    (root, *_) = groups(u, m, [("j1", "j1")], [("base", "b0")], dict(u.frames), dict(m.frames), False)
    assert (root.urdf_link, root.mjcf_link) == ("base", "b0")
    # the MJCF's base body massless: its name comes from the root frame pair
    m2 = model("mjcf", [body("b0", None, 0.0), body("b1", "j1", 2.0)], frames=frames_m)
    pairs = [("link1", "b1"), ("base", "b1"), ("link1", "b0"), ("base", "b0")]  # the first with both on the base
    (root, *_) = groups(u, m2, [("j1", "j1")], pairs, dict(u.frames), dict(m2.frames), False)
    assert (root.urdf_link, root.mjcf_link) == ("base", "b0")
    (root, *_) = groups(u, m2, [("j1", "j1")], [], dict(u.frames), dict(m2.frames), False)
    assert (root.urdf_link, root.mjcf_link) == ("base", "(base)")  # said so in its label
    u.bodies[0].mass = 0.0  # neither base weighs anything: the root frame pair names both
    (root, *_) = groups(u, m2, [("j1", "j1")], [("link1", "b0"), ("base", "b0")], dict(u.frames), dict(m2.frames), False)
    assert (root.urdf_link, root.mjcf_link) == ("base", "b0")


def test_groups_place_each_inertial_through_its_frames_pose():
    # link2's frame is turned 0.5 rad about z at (0, 0, 0.5): its com (0.1, 0, 0) lands at
    # 0.1·(cos 0.5, sin 0.5, 0) + (0, 0, 0.5), its inertia turned with it
    u, m = arm(), arm("mjcf")
    grps = groups(u, m, [("j1", "j1"), ("j2", "j2")], [], dict(u.frames), {}, False)
    (p,) = grps[2].urdf
    np.testing.assert_allclose(p.com, [0.1 * math.cos(0.5), 0.1 * math.sin(0.5), 0.5], atol=1e-15)
    r = rot_z(0.5)
    np.testing.assert_allclose(p.inertia, r @ np.diag([0.005, 0.01, 0.012]) @ r.T, atol=1e-15)
    # no pose for a body: its world inertial as read
    m.bodies[2].com = np.array([7.0, 8.0, 9.0])
    (q,) = grps[2].mjcf
    np.testing.assert_allclose(q.com, u.bodies[2].com)  # placed from the world inertial read (the same here)
    grps = groups(u, m, [("j1", "j1"), ("j2", "j2")], [], {}, {}, False)
    np.testing.assert_allclose(grps[2].mjcf[0].com, [7.0, 8.0, 9.0])


def test_a_body_on_a_joint_one_file_lacks_is_moved_by_it_and_has_no_twin():
    u = arm()
    u.joints.append(joint("prop_joint", "j2", "prop", "link2"))
    u.frames["prop"] = pose((0, 0, 0.6))
    u.frame_owner["prop"], u.frame_depth["prop"] = "prop_joint", 3
    u.bodies.append(body("prop", "prop_joint", 0.1, at=u.frames["prop"]))
    m = arm("mjcf")
    m.joints.append(joint("prop_joint", "j2", "prop", "link2"))
    m.frames["prop"], m.frame_owner["prop"], m.frame_depth["prop"] = pose((0, 0, 0.6)), "j2", 3
    m.bodies.append(body("prop", "j2", 0.1, at=m.frames["prop"]))
    grps = groups(u, m, [("j1", "j1"), ("j2", "j2")], [(f, f) for f in u.frames], dict(u.frames), dict(m.frames), False)
    prop_u, prop_m = grps[2].urdf[1], grps[2].mjcf[1]
    assert (prop_u.name, prop_u.moved_by, prop_u.twin) == ("prop", "prop_joint", None)
    assert (prop_m.name, prop_m.moved_by, prop_m.twin) == ("prop", None, None)  # its twin is moved by a joint
    assert grps[2].urdf[0].twin == "link2" and grps[2].mjcf[0].twin == "link2"
    # the other way round: the MJCF's prop is on a joint the URDF lacks
    grps = groups(m, u, [("j1", "j1"), ("j2", "j2")], [(f, f) for f in u.frames], dict(m.frames), dict(u.frames), False)
    prop_u, prop_m = grps[2].urdf[1], grps[2].mjcf[1]
    assert (prop_m.moved_by, prop_m.twin) == ("prop_joint", None) and (prop_u.moved_by, prop_u.twin) == (None, None)


def test_twins_on_different_joints_are_not_one_body():
    u, m = arm(), arm("mjcf")
    m.bodies[2].owner = "j1"  # the MJCF's link2 moves with j1: not the URDF's link2's body
    grps = groups(u, m, [("j1", "j1"), ("j2", "j2")], [(f, f) for f in FRAMES], dict(u.frames), dict(m.frames), False)
    assert grps[2].urdf[0].twin is None
    assert [(p.name, p.twin) for p in grps[1].mjcf] == [("link1", "link1"), ("link2", None)]


def test_a_twin_that_states_no_inertial_is_kept_as_unset():
    u, m = (
        arm(),
        arm(
            "mjcf",
        ),
    )
    m.bodies.pop(2)
    m.no_inertial = {"link2"}
    u2 = arm()
    u2.bodies.pop(1)
    u2.no_inertial = {"link1"}
    grps = groups(u, m, [("j1", "j1"), ("j2", "j2")], [(f, f) for f in FRAMES], dict(u.frames), dict(m.frames), False)
    (p,) = grps[2].urdf
    assert (p.twin, p.unset_twin) == (None, "link2")
    assert grps[1].urdf[0].unset_twin is None  # its twin states one
    grps = groups(u2, arm("mjcf"), [("j1", "j1"), ("j2", "j2")], [(f, f) for f in FRAMES], dict(u2.frames), dict(m.frames), False)
    (q,) = grps[1].mjcf
    assert (q.twin, q.unset_twin) == (None, "link1")
    # no inertial but not stated as such (absent from the file): not unset
    m.no_inertial = set()
    grps = groups(u, m, [("j1", "j1"), ("j2", "j2")], [(f, f) for f in FRAMES], dict(u.frames), dict(m.frames), False)
    assert grps[2].urdf[0].unset_twin is None


def test_each_files_body_flags_travel_with_its_part():
    u, m = arm(), arm("mjcf")
    u.bodies[1].mass_known = False
    m.bodies[1].mass_known = False
    m.bodies[1].com_known = False
    m.bodies[1].snapped, m.bodies[1].snapped_com = 0.25, 0.003
    grps = groups(u, m, [("j1", "j1"), ("j2", "j2")], [(f, f) for f in FRAMES], dict(u.frames), dict(m.frames), False)
    (pu,), (pm,) = grps[1].urdf, grps[1].mjcf
    assert (pu.known, pu.com_known, pu.snapped) == (False, True, 0.0)
    u.bodies[2].com_known = False  # a USD first side states a mass with no centre of mass
    grps = groups(u, m, [("j1", "j1"), ("j2", "j2")], [(f, f) for f in FRAMES], dict(u.frames), dict(m.frames), False)
    assert [p.com_known for g in grps for p in g.urdf] == [True, True, False]
    assert (pm.known, pm.com_known, pm.snapped, pm.snapped_com) == (False, False, 0.25, 0.003)
    assert (pm.mass, pu.mass) == (2.0, 2.0)
    assert [(g.key, [p.known for p in g.mjcf]) for g in grps] == [(ROOT, [True]), ("j1", [False]), ("j2", [True])]


def test_a_group_with_no_body_in_either_file_is_left_out():
    u, m = arm(), arm("mjcf")
    u.bodies.pop(2)
    m.bodies.pop(2)
    grps = groups(u, m, [("j1", "j1"), ("j2", "j2")], [], dict(u.frames), dict(m.frames), False)
    assert [g.key for g in grps] == [ROOT, "j1"]


def test_group_totals_and_twinless_parts():
    a = Part("a", 1.0, np.zeros(3), np.zeros((3, 3)), "x")
    b = Part("b", 1.0, np.array([2.0, 0.0, 0.0]), np.zeros((3, 3)), None)
    c = Part("c", 0.0, np.zeros(3), np.zeros((3, 3)), None)
    g = Group("j1", "l", "l", [a, b, c], [a], False)
    assert g.total("urdf").mass == 2.0 and g.total("mjcf").mass == 1.0
    assert g.total("urdf", [b]).mass == 1.0
    assert g.twinless("urdf") == [b] and g.twinless("mjcf") == []


# --- reading the numbers ------------------------------------------------------------------------


def test_the_rounded_reading_is_the_one_written_with_fewer_digits():
    assert rounded_side(0.5, 0.5001) == "URDF"
    assert rounded_side(0.5001, 0.5) == "MJCF"
    assert rounded_side(0.25, 1.5) == "both files"  # leading zeros are no digits
    assert rounded_side(-0.5, 0.25) == "URDF"  # nor is the sign
    assert rounded_side(1e-05, 0.1234) == "MJCF"  # "1e-05" is 5 characters, no point


def test_principal_moments_ascend_with_their_axes():
    w, v = principal(np.diag([3.0, 1.0, 2.0]))
    np.testing.assert_allclose(w, [1.0, 2.0, 3.0])
    np.testing.assert_allclose(np.abs(v), [[0, 0, 1], [1, 0, 0], [0, 1, 0]])


def test_an_axis_is_named_in_a_frames_axes_when_it_lies_along_one():
    assert _axis_name(np.array([0.0, 1.0, 0.0]), None) == "y"
    assert _axis_name(np.array([0.0, 0.0, -1.0]), None) == "z"
    assert _axis_name(np.array([0.0, 1.0, 0.0]), pose(rz=math.pi / 2)) == "x"
    assert _axis_name(np.array([0.6, 0.8, 0.0]), None) == "[0.6, 0.8, 0]"
    assert _axis_name(np.array([0.6, 0.8, 0.0]), pose(rz=math.pi / 2)) == "[0.8, -0.6, 0]"
    off = 1e-7  # within a millionth of an axis: named after it
    assert _axis_name(np.array([math.sqrt(1 - off**2), off, 0.0]), None) == "x"
    tilt = 2e-3  # 1 - cos ≈ 2e-6: not along it
    assert _axis_name(np.array([math.cos(tilt), math.sin(tilt), 0.0]), None).startswith("[")


def test_tensors_turned_a_quarter_turn_have_the_same_moments_on_swapped_axes():
    a = np.diag([1.0, 2.0, 3.0])
    b = np.diag([2.0, 1.0, 3.0])  # a turned 90° about z
    d = describe_tensors(a, b, None, 0.0)
    assert d["urdf_principal"] == pytest.approx([1.0, 2.0, 3.0]) and d["mjcf_principal"] == pytest.approx([1.0, 2.0, 3.0])
    assert d["same_moments"] is True
    assert [x["angle_deg"] for x in d["axes"]] == pytest.approx([90.0, 90.0, 0.0], abs=1e-9)
    assert [x["defined"] for x in d["axes"]] == [True, True, True]
    assert [(x["urdf_axis"], x["mjcf_axis"]) for x in d["axes"]] == [("x", "y"), ("y", "x"), ("z", "z")]
    assert [x["moment_urdf"] for x in d["axes"]] == pytest.approx([1.0, 2.0, 3.0])
    assert [x["moment_mjcf"] for x in d["axes"]] == pytest.approx([1.0, 2.0, 3.0])
    assert d["largest_axis_angle_deg"] == pytest.approx(90.0)
    assert d["turned"] == ["moment 1 along x (URDF) vs y (MJCF)", "moment 2 along y (URDF) vs x (MJCF)"]
    # named in a link frame turned 90° about z
    d = describe_tensors(a, b, pose(rz=math.pi / 2), 0.0)
    assert [(x["urdf_axis"], x["mjcf_axis"]) for x in d["axes"]] == [("y", "x"), ("x", "y"), ("z", "z")]


def test_the_angle_between_principal_axes_is_measured():
    a = np.diag([1.0, 2.0, 3.0])
    r = rot_z(math.radians(30))
    d = describe_tensors(a, r @ a @ r.T, None, 0.0)
    assert [x["angle_deg"] for x in d["axes"]] == pytest.approx([30.0, 30.0, 0.0], abs=1e-9)
    assert d["largest_axis_angle_deg"] == pytest.approx(30.0, rel=1e-9)
    assert len(d["turned"]) == 2
    r = rot_z(math.radians(0.5))  # half a degree is a turn
    assert len(describe_tensors(a, r @ a @ r.T, None, 0.0)["turned"]) == 2


def test_moments_are_the_same_within_the_moment_tolerance():
    a, b = np.diag([1.0, 2.0, 3.0]), np.diag([1.0, 2.0, 3.5])
    assert describe_tensors(a, b, None, 0.5)["same_moments"] is True
    assert describe_tensors(a, b, None, 0.49)["same_moments"] is False
    assert describe_tensors(a, a * (1 + 1e-14), None, 0.0)["same_moments"] is True  # double precision of the value


def test_an_axis_of_nearly_equal_moments_is_not_defined():
    # moments 1 and 1.001 of a tensor of scale 2: their axes are not defined, swapping them is nothing
    a, b = np.diag([1.0, 1.001, 2.0]), np.diag([1.001, 1.0, 2.0])
    d = describe_tensors(a, b, None, 0.0)
    assert [x["defined"] for x in d["axes"]] == [False, False, True]
    assert d["largest_axis_angle_deg"] == 0.0 and d["turned"] == []
    d = describe_tensors(np.diag([1.0, 1.5, 2.0]), np.diag([1.5, 1.0, 2.0]), None, 0.0)  # gap 0.25 of the scale
    assert [x["defined"] for x in d["axes"]] == [True, True, True] and d["largest_axis_angle_deg"] == pytest.approx(90.0)


def test_the_scale_is_the_larger_of_the_two_tensors():
    # moments 1 and 1.001 of a tensor of scale 2: not defined, however small the other tensor is
    d = describe_tensors(np.diag([1.0, 1.001, 2.0]), np.diag([0.1, 0.2, 0.3]), None, 0.0)
    assert [x["defined"] for x in d["axes"]] == [False, False, True]
    d = describe_tensors(np.diag([0.1, 0.2, 0.3]), np.diag([1.0, 1.001, 2.0]), None, 0.0)
    assert [x["defined"] for x in d["axes"]] == [True, True, True]  # 0.1 apart of 2


def test_small_tensors_are_scaled_by_their_own_size():
    # moments of a few grams·m²: 5e-4 apart of 2e-3 is a quarter of the scale, the axes defined
    a, b = np.diag([0.001, 0.0015, 0.002]), np.diag([0.0015, 0.001, 0.002])
    d = describe_tensors(a, b, None, 0.0)
    assert [x["defined"] for x in d["axes"]] == [True, True, True] and d["largest_axis_angle_deg"] == pytest.approx(90.0)


def test_empty_tensors_describe_as_nothing():
    d = describe_tensors(np.zeros((3, 3)), np.zeros((3, 3)), None, 0.0)
    assert d["same_moments"] is True and d["largest_axis_angle_deg"] == 0.0 and d["turned"] == []
    assert [x["defined"] for x in d["axes"]] == [False, False, False]


def test_a_negative_moment_sets_the_scale_by_its_size():
    # moments -4 and 1 (not physical, but read): scale 4, so moments 1 and 1.002 are 5e-4 apart
    # relative to it, their axes not defined
    a, b = np.diag([-4.0, 1.0, 1.002]), np.diag([-4.0, 1.002, 1.0])
    assert [x["defined"] for x in describe_tensors(a, b, None, 0.0)["axes"]] == [True, False, False]
    assert [x["defined"] for x in describe_tensors(b * 0 + np.diag([0.5, 1.0, 1.002]), a, None, 0.0)["axes"]] == [
        True,
        False,
        False,
    ]


# --- a result's reading ---------------------------------------------------------------------------


def result(u_mass=1.0, m_mass=1.0, tol=(0.1, 0.1, 0.1), diff=(0.0, 0.0, 0.0), fixed=False, names=("l", "l")):
    g = Group("j", names[0], names[1], [], [], fixed)
    return GroupResult(g, Inertial(u_mass), Inertial(m_mass), Difference(*diff), tol, "agree")


def test_a_result_is_labelled_by_its_links():
    assert result(names=("l", "l")).label == "l"
    assert result(names=("l", "b")).label == "l / b"


def test_a_ratio_is_the_difference_over_its_tolerance():
    r = result(tol=(0.5, 0.0, 0.0), diff=(0.2, 0.3, 0.0))
    assert r.ratio(0) == pytest.approx(0.4)
    assert r.ratio(1) == math.inf
    assert r.ratio(2) == 0.0
    assert result(tol=(1.0, 2.0, 4.0), diff=(1.0, 1.0, 1.0)).ratio(2) == pytest.approx(0.25)


def test_a_mass_ratio_shared_by_every_moving_body_is_a_units_mistake():
    assert uniform_mass_ratio([result(1.0, 1000.0), result(2.0, 2000.0)]) == pytest.approx(1000.0)
    assert uniform_mass_ratio([result(1.0, 1.02), result(2.0, 2.04)]) == pytest.approx(1.02)
    assert uniform_mass_ratio([result(1.0, 1.005), result(2.0, 2.01)]) is None  # within 1 %: not units
    assert uniform_mass_ratio([result(1.0, 1000.0)]) is None  # one body says nothing
    assert uniform_mass_ratio([result(1.0, 1000.0), result(2.0, 2000.0 * (1 + 2e-6))]) is None
    assert uniform_mass_ratio([result(1.0, 1000.0), result(2.0, 2000.0 * (1 + 5e-7))]) == pytest.approx(1000.0)
    spread = [result(1.0, 1000.0), result(1.0, 1000.0 * (1 + 9e-7)), result(1.0, 1000.0 * (1 - 9e-7))]
    assert uniform_mass_ratio(spread) == pytest.approx(1000.0)  # each within a millionth of the first
    # the welded base and massless bodies are left out
    assert uniform_mass_ratio([result(1.0, 1000.0), result(2.0, 2000.0), result(3.0, 3.0, fixed=True)]) == pytest.approx(1000.0)
    assert uniform_mass_ratio([result(1.0, 1000.0), result(0.0, 5.0), result(2.0, 2000.0)]) == pytest.approx(1000.0)
    assert uniform_mass_ratio([result(1.0, 1000.0), result(5.0, 0.0), result(2.0, 2000.0)]) == pytest.approx(1000.0)
    assert uniform_mass_ratio([result(1.0, 1000.0), result(5.0, 0.0)]) is None


# --- carried to the joints ------------------------------------------------------------------------


def test_the_mjcf_parts_are_carried_into_the_frame_their_joint_hangs_from():
    u, m = arm(), arm("mjcf")
    info = info_of(u, m)
    carry = pose((0.0, 0.0, 0.1), math.pi / 2)
    info.alignment.attribution = {"j1": Attribution("j1", carry), "j2": Attribution("j2", np.eye(4) + 1e-16)}
    grps = groups(u, m, info.joint_pairs, info.frame_pairs, info.poses_u, info.poses_m, False)
    before = [(p.com.copy(), p.inertia.copy()) for g in grps for p in g.mjcf]
    carry_to_joints(grps, info)
    (p1,) = grps[1].mjcf
    np.testing.assert_allclose(p1.com, rot_z(math.pi / 2) @ before[1][0] + [0.0, 0.0, 0.1], atol=1e-15)
    np.testing.assert_allclose(p1.inertia, np.diag([0.02, 0.02, 0.01]), atol=1e-15)  # symmetric about z
    assert grps[1].seated == pytest.approx((math.pi / 2, 0.1))
    np.testing.assert_array_equal(grps[2].mjcf[0].com, before[2][0])  # a carry within 1e-15 of none
    np.testing.assert_array_equal(grps[0].mjcf[0].com, before[0][0])  # no attribution
    assert grps[2].seated == (0.0, 0.0) and grps[0].seated == (0.0, 0.0)
    np.testing.assert_array_equal(grps[1].urdf[0].com, u.bodies[1].com)  # the URDF's stay


def test_a_turned_carry_turns_the_inertia():
    u, m = arm(), arm("mjcf")
    info = info_of(u, m)
    info.alignment.attribution = {"j2": Attribution("j2", pose(rz=math.pi / 2))}
    grps = groups(u, m, info.joint_pairs, info.frame_pairs, info.poses_u, info.poses_m, False)
    i0 = grps[2].mjcf[0].inertia.copy()
    carry_to_joints(grps, info)
    r = rot_z(math.pi / 2)
    np.testing.assert_allclose(grps[2].mjcf[0].inertia, r @ i0 @ r.T, atol=1e-15)
    assert grps[2].seated == pytest.approx((math.pi / 2, 0.0))
    # a carry of 1e-14 m is one
    info.alignment.attribution = {"j2": Attribution("j2", pose((1e-14, 0.0, 0.0)))}
    carry_to_joints(grps, info)
    assert grps[2].seated == pytest.approx((0.0, 1e-14))


# --- analyse: the verdict of each rigid body ---------------------------------------------------------


def analysed(u, m, defaults=DEFAULTS, **kw) -> dict[str, GroupResult]:
    return by_key(analyse(info_of(u, m, **kw), defaults))


def test_identical_files_agree_with_the_default_tolerances():
    res = analysed(arm(), arm("mjcf"))
    assert [(k, r.status) for k, r in res.items()] == [(ROOT, "agree"), ("j1", "agree"), ("j2", "agree")]
    assert all(r.tol == pytest.approx(DEFAULTS) for r in res.values())
    r = res["j2"]
    assert (r.urdf.mass, r.mjcf.mass) == (1.0, 1.0) and r.diff == Difference(0.0, 0.0, 0.0)
    assert r.extra == [] and r.moved == [] and r.without_extra is None
    assert r.tensors["same_moments"] is True and r.tensors["urdf_principal"] == pytest.approx([0.005, 0.01, 0.012])


def test_a_heavier_body_differs_by_its_mass():
    m = arm("mjcf")
    m.bodies[1].mass = 2.5
    res = analysed(arm(), m)
    assert [r.status for r in res.values()] == ["agree", "differs", "agree"]
    r = res["j1"]
    assert (r.urdf.mass, r.mjcf.mass) == (2.0, 2.5)
    assert r.diff.mass == pytest.approx(0.5) and r.diff.com == 0.0
    assert r.diff.tensor == 0.0  # one part: its inertia about its own centre is the one stated
    assert r.extra == [] and r.without_extra is None


def test_a_centre_of_mass_moved_in_its_links_frame_is_seen_in_the_world():
    m = arm("mjcf")
    m.bodies[2].com_local = np.array([0.1, 0.02, 0.0])  # 2 cm along link2's own y
    r = analysed(arm(), m)["j2"]
    assert r.status == "differs" and r.diff.com == pytest.approx(0.02, rel=1e-12)
    np.testing.assert_allclose(r.mjcf.com - r.urdf.com, 0.02 * rot_z(0.5)[:, 1], atol=1e-15)


def test_tolerances_rise_with_the_written_precision():
    # floors: link1's frame 1 mm and 2 mrad, masses relative 1e-3, centres of mass 0.5 mm, inertial
    # axes 1 mrad; link1 one part (no lever)
    floors = Floors(frames={"link1": (1e-3, 2e-3)}, relative=1e-3, com=5e-4, inertial_angle=1e-3)
    r = analysed(arm(), arm("mjcf"), floors=floors)["j1"]
    com_floor = 5e-4 + 1e-3 + 2e-3 * 0.0
    norm = 0.02
    tensor = (1e-3 + 2 * (1e-3 + 2e-3)) * norm + 2 * 2.0 * (0.0 + 5e-4) * com_floor
    assert r.tol == pytest.approx((1e-3 * 2.0, com_floor, tensor), rel=1e-12)
    assert r.status == "agree"  # nothing differs at all
    # the tensor floor is relative to the larger of the two tensors
    m = arm("mjcf")
    m.bodies[1].inertia_local = np.diag([0.02, 0.03, 0.01])
    r = analysed(arm(), m, floors=floors)["j1"]
    assert r.tol[2] == pytest.approx((1e-3 + 2 * (1e-3 + 2e-3)) * 0.03 + 2 * 2.0 * 5e-4 * com_floor, rel=1e-12)
    r = analysed(m, arm(), floors=floors)["j1"]
    assert r.tol[2] == pytest.approx((1e-3 + 2 * (1e-3 + 2e-3)) * 0.03 + 2 * 2.0 * 5e-4 * com_floor, rel=1e-12)
    # a default above the floor wins
    r = analysed(arm(), arm("mjcf"), defaults=(1.0, 1.0, 1.0), floors=floors)["j1"]
    assert r.tol == (1.0, 1.0, 1.0)


def test_a_lever_raises_the_centre_of_mass_floor_by_the_frames_turn():
    # link1 has a second part 0.3 m from the body's centre: a frame turned by 2 mrad moves it
    u, m = arm(), arm("mjcf")
    for d in (u, m):
        d.frames["tool"], d.frame_owner["tool"], d.frame_depth["tool"] = pose((0.0, 0.0, 0.2)), "j1", 2
        d.bodies.append(body("tool", "j1", 2.0, (0.3, 0.0, 0.1), (0.0, 0.0, 0.0), d.frames["tool"]))
    floors = Floors(frames={"link1": (1e-3, 2e-3), "tool": (3e-3, 1e-3)}, com=5e-4)
    r = analysed(u, m, floors=floors)["j1"]
    lever = 0.15  # two 2 kg parts at x = 0 and x = 0.3: each 0.15 m from their centre
    com_floor = 5e-4 + 3e-3 + 2e-3 * lever  # the largest position and rotation floors of its frames
    norm = float(np.abs(np.linalg.eigvalsh(r.urdf.inertia)).max())
    tensor = (2 * 2e-3) * norm + 2 * 4.0 * (lever + 5e-4) * com_floor
    assert r.tol == pytest.approx((DEFAULTS[0], com_floor, tensor), rel=1e-12)


def test_a_property_the_user_set_takes_no_floor():
    floors = Floors(frames={"link1": (1e-3, 2e-3)}, relative=1e-3, com=5e-4, inertial_angle=1e-3)
    every = frozenset({"inertia.mass", "inertia.com", "inertia.tensor"})
    r = analysed(arm(), arm("mjcf"), floors=floors, user_tolerances=every)["j1"]
    assert r.tol == DEFAULTS
    r = analysed(arm(), arm("mjcf"), floors=floors, user_tolerances=frozenset({"inertia.com"}))["j1"]
    # the centre-of-mass floor is zero, so the tensor's lever term is too
    assert r.tol == pytest.approx((2e-3, DEFAULTS[1], (1e-3 + 2 * 3e-3) * 0.02), rel=1e-12)


def test_within_the_written_precision_only_is_rounding_in_file_mode():
    m = arm("mjcf")
    m.bodies[1].mass = 2.001  # 5e-4 relative: within the floor of 1e-3, not the default 1e-6
    floors = Floors(relative=1e-3)
    r = analysed(arm(), m, floors=floors)["j1"]
    assert r.status == "rounding" and r.diff.mass == pytest.approx(1e-3)
    assert r.tol[0] == pytest.approx(2.001e-3)  # relative to the heavier
    assert analysed(arm(), m, floors=floors, file_mode=False)["j1"].status == "agree"
    m.bodies[1].mass = 2.003
    assert analysed(arm(), m, floors=floors)["j1"].status == "differs"


def test_a_mass_from_an_absent_mesh_is_unknown_either_way():
    m = arm("mjcf")
    m.bodies[1].mass, m.bodies[1].mass_known = 7.0, False
    r = analysed(arm(), m)["j1"]
    assert r.status == "unknown" and r.diff.mass == pytest.approx(5.0) and r.tol == DEFAULTS
    u = arm()
    u.bodies[2].mass_known = False
    assert analysed(u, arm("mjcf"))["j2"].status == "unknown"  # even when they agree


def test_a_mass_whose_place_is_unknown_is_compared_by_its_mass_alone():
    m = arm("mjcf")
    m.bodies[1].com_known = False
    m.bodies[1].com_local = np.array([0.5, 0.0, 0.0])
    r = analysed(arm(), m)["j1"]
    assert r.status == "agree" and r.tol[1:] == (math.inf, math.inf) and r.diff.com == pytest.approx(math.hypot(0.5, 0.1))
    m.bodies[1].mass = 3.0
    assert analysed(arm(), m)["j1"].status == "differs"
    # its mass within the written precision only: rounding, by the mass's own default
    m.bodies[1].mass = 2.0002
    assert analysed(arm(), m, defaults=(1e-6, 1e-3, 1e-7), floors=Floors(relative=1e-3))["j1"].status == "rounding"
    u = arm()
    u.bodies[2].com_known = False
    u.bodies[2].com_local = np.array([0.0, 0.3, 0.0])
    assert analysed(u, arm("mjcf"))["j2"].status == "agree"


def test_mujocos_snapped_centre_of_mass_widens_the_centre_tolerance_by_its_share_of_the_mass():
    u, m = arm(), arm("mjcf")
    for d in (u, m):
        d.frames["tool"], d.frame_owner["tool"], d.frame_depth["tool"] = pose((0.0, 0.0, 0.2)), "j1", 2
        d.bodies.append(body("tool", "j1", 6.0, (0.0, 0.0, 0.0), (0.01, 0.01, 0.01), d.frames["tool"]))
    m.bodies[1].snapped_com = 4e-3  # 2 kg of 8
    m.bodies[1].com_local = np.array([0.0, 0.0, 0.1 - 4e-3])
    r = analysed(u, m, defaults=(1e-6, 1e-6, 1.0))["j1"]
    assert r.tol[1] == pytest.approx(DEFAULTS[1] + 4e-3 * 2.0 / 8.0, rel=1e-12)
    # what MuJoCo moved is no rounding of the file's digits: agree
    assert r.diff.com == pytest.approx(1e-3, rel=1e-9) and r.status == "agree"
    m.bodies[1].com_local = np.array([0.0, 0.0, 0.1 - 4.1e-3])
    assert analysed(u, m, defaults=(1e-6, 1e-6, 1.0))["j1"].status == "differs"


def test_a_light_bodys_snapped_centre_of_mass_is_its_share_of_a_light_body():
    u, m = arm(), arm("mjcf")
    u.bodies[2].mass = m.bodies[2].mass = 0.5
    m.bodies[2].snapped_com = 2e-3
    assert analysed(u, m)["j2"].tol[1] == pytest.approx(DEFAULTS[1] + 2e-3, rel=1e-12)


def test_mujocos_snapped_axes_widen_the_tensor_tolerance_by_the_turn_of_their_spread():
    m = arm("mjcf")
    m.bodies[2].snapped = 0.01  # link2's moments 0.005 .. 0.012: a spread of 0.007
    r = analysed(arm(), m)["j2"]
    assert r.tol[2] == pytest.approx(DEFAULTS[2] + 2 * 0.01 * 0.007, rel=1e-9)
    # a difference within it is MuJoCo's: agree, not rounding (the exact tolerance has it too)
    m.bodies[2].inertia_local = np.diag([0.005, 0.01, 0.012 + 1e-4])
    r = analysed(arm(), m)["j2"]
    assert r.diff.tensor == pytest.approx(1e-4, rel=1e-6) and r.status == "agree"
    m.bodies[2].inertia_local = np.diag([0.005, 0.01, 0.012 + 2e-4])
    assert analysed(arm(), m)["j2"].status == "differs"


def with_tool(d: ModelDesc, mass: float = 0.5, name: str = "tool") -> ModelDesc:
    d.frames[name], d.frame_owner[name], d.frame_depth[name] = pose((0.0, 0.0, 0.6)), "j2", 3
    d.bodies.append(body(name, "j2", mass, (0.0, 0.0, 0.02), (1e-4, 1e-4, 1e-4), d.frames[name]))
    return d


def test_a_part_with_no_twin_explains_the_difference_when_only_one_file_has_it():
    r = analysed(with_tool(arm()), arm("mjcf"))["j2"]
    assert r.status == "explained"
    assert [p.name for p in r.extra] == ["tool"]
    assert r.without_extra == Difference(0.0, 0.0, 0.0)
    assert r.diff.mass == pytest.approx(0.5) and r.urdf.mass == pytest.approx(1.5)
    r = analysed(arm(), with_tool(arm("mjcf")))["j2"]
    assert r.status == "explained" and [p.name for p in r.extra] == ["tool"]


def test_parts_with_no_twin_in_both_files_explain_nothing():
    r = analysed(with_tool(arm()), with_tool(arm("mjcf"), 0.7, "flange"))["j2"]
    assert r.status == "differs" and r.extra == [] and r.without_extra is None


def test_a_part_with_no_twin_that_does_not_account_for_the_difference_explains_nothing():
    m = arm("mjcf")
    m.bodies[2].mass = 1.2
    r = analysed(with_tool(arm()), m)["j2"]
    assert r.status == "differs" and r.extra == []
    assert r.without_extra is None


def test_a_twin_that_states_no_inertial_makes_the_difference_unset():
    u, m = arm(), arm("mjcf")
    m.bodies.pop(2)
    m.no_inertial = {"link2"}
    r = analysed(u, m)["j2"]
    assert r.status == "unset" and [p.unset_twin for p in r.extra] == ["link2"]
    assert r.without_extra == Difference(0.0, 0.0, 0.0)
    r = analysed(m, u)["j2"]  # the URDF's the unset one: its rigid body has no URDF part
    assert r.status == "unset" and r.tol == DEFAULTS and (r.urdf.mass, r.mjcf.mass) == (0.0, 1.0)


def test_an_unset_twin_and_a_part_with_none_explain_together():
    u, m = with_tool(arm()), arm("mjcf")
    m.bodies.pop(2)
    m.no_inertial = {"link2"}
    r = analysed(u, m)["j2"]
    assert r.status == "explained" and sorted(p.name for p in r.extra) == ["link2", "tool"]


def test_the_stated_parts_are_compared_without_the_unset_one():
    # link2 and a fixed tool on it; the MJCF leaves the tool's inertial unset and its link2 is heavier:
    # the finding is link2's own difference, by the stated values alone
    u, m = with_tool(arm()), with_tool(arm("mjcf"))
    m.bodies.pop()
    m.no_inertial = {"tool"}
    m.bodies[2].mass = 1.3
    r = analysed(u, m)["j2"]
    assert r.status == "differs"
    assert (r.urdf.mass, r.mjcf.mass) == pytest.approx((1.0, 1.3)) and r.diff.mass == pytest.approx(0.3)
    # when the stated ones agree, the unset one is the whole difference
    m.bodies[2].mass = 1.0
    r = analysed(u, m)["j2"]
    assert r.status == "unset" and (r.urdf.mass, r.mjcf.mass) == pytest.approx((1.5, 1.0))


def test_the_stated_parts_are_compared_alone_only_when_each_has_its_twin():
    u, m = with_tool(arm()), with_tool(arm("mjcf"))
    m.bodies.pop()
    m.no_inertial = {"tool"}
    m.bodies[2].mass = 1.3
    marker = with_tool(arm(), 0.0, "marker").bodies[-1]  # massless, no twin: states nothing
    marker.inertia_local = marker.inertia = np.zeros((3, 3))
    u.bodies.append(marker)
    u.frames["marker"], u.frame_owner["marker"], u.frame_depth["marker"] = pose((0.0, 0.0, 0.6)), "j2", 3
    assert analysed(u, m)["j2"].urdf.mass == pytest.approx(1.0)
    with_tool(u, 0.2, "lamp")  # a twinless stated part
    r = analysed(u, m)["j2"]
    assert (r.urdf.mass, r.mjcf.mass) == pytest.approx((1.7, 1.3)) and r.status == "differs"


def prop(d: ModelDesc, owner: str = "prop_joint", mass: float = 0.1) -> ModelDesc:
    d.joints.append(joint("prop_joint", "j2", "prop", "link2"))
    d.frames["prop"], d.frame_owner["prop"], d.frame_depth["prop"] = pose((0.0, 0.0, 0.6)), owner, 3
    d.bodies.append(body("prop", owner, mass, (0.0, 0.0, 0.01), (1e-5, 1e-5, 1e-5), d.frames["prop"]))
    return d


def test_what_a_joint_in_one_file_only_moves_is_left_out_as_that_joints():
    r = analysed(prop(arm()), arm("mjcf"))["j2"]
    assert r.status == "agree" and [p.name for p in r.moved] == ["prop"]
    assert r.diff == Difference(0.0, 0.0, 0.0) and r.urdf.mass == 1.0
    assert r.extra == []
    r = analysed(arm(), prop(arm("mjcf")))["j2"]
    assert r.status == "agree" and [p.name for p in r.moved] == ["prop"]


def test_a_moved_part_is_kept_where_the_bodies_agree_with_it():
    r = analysed(prop(arm(), mass=1e-8), arm("mjcf"), defaults=(1e-6, 1.0, 1.0))["j2"]
    assert r.status == "agree" and r.moved == [] and r.urdf.mass == pytest.approx(1.0 + 1e-8)


def test_a_massless_moved_part_stays():
    r = analysed(prop(arm(), mass=0.0), arm("mjcf"))["j2"]
    assert r.moved == []


def test_with_the_moved_part_left_out_a_remaining_difference_is_the_bodys():
    m = arm("mjcf")
    m.bodies[2].mass = 1.4
    r = analysed(prop(arm()), m)["j2"]
    assert r.status == "differs" and [p.name for p in r.moved] == ["prop"]
    assert (r.urdf.mass, r.mjcf.mass) == pytest.approx((1.0, 1.4))
    assert r.extra == [] and r.without_extra is None  # the moved part is that joint's, not an extra one


def test_the_tensors_are_described_in_the_urdf_links_frame():
    m = arm("mjcf")
    m.bodies[2].inertia_local = np.diag([0.01, 0.005, 0.012])  # link2's moments swapped about its z
    r = analysed(arm(), m)["j2"]
    assert r.status == "differs"
    assert [(x["urdf_axis"], x["mjcf_axis"]) for x in r.tensors["axes"]] == [("x", "y"), ("y", "x"), ("z", "z")]
    assert r.tensors["same_moments"] is True and r.tensors["largest_axis_angle_deg"] == pytest.approx(90.0)


def test_the_mjcfs_poses_are_brought_through_the_alignment_in_file_mode():
    # the MJCF mounts everything 1 m along x in its world: the alignment's T says so
    m = arm("mjcf")
    shift = pose((1.0, 0.0, 0.0))
    for name in m.frames:
        m.frames[name] = shift @ m.frames[name]
    info = info_of(arm(), m)
    info.alignment.T = shift
    res = by_key(analyse(info, DEFAULTS))
    assert [r.status for r in res.values()] == ["agree", "agree", "agree"]
    info.file_mode = False
    res = by_key(analyse(info, DEFAULTS))
    assert res["j1"].status == "differs" and res["j1"].diff.com == pytest.approx(1.0)


def test_the_carry_is_applied_in_file_mode_only():
    m = arm("mjcf")
    m.bodies[2].com_local = np.array([0.1, 0.05, 0.0])
    info = info_of(arm(), m)
    # a carry that takes the MJCF's link2 centre back onto the URDF's: 5 cm along link2's -y
    back = pose(tuple(-0.05 * rot_z(0.5)[:, 1]))
    info.alignment.attribution = {"j2": Attribution("j2", back)}
    assert by_key(analyse(info, DEFAULTS))["j2"].status == "agree"
    info.file_mode = False
    assert by_key(analyse(info, DEFAULTS))["j2"].status == "differs"
