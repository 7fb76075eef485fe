"""Matching decisions, each pinned by a pair built for it: joints by the number in their name (the
last one), the fingers of a hand by their place in the tree when the names say nothing, and names
alike across kinds (a link and a site) taken for no twins."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from kinverify.errors import InputError, UnknownNameError
from kinverify.filemode.align.match import (
    Matching,
    _by_key,
    _descendants,
    _normalise,
    _numbers,
    _strip_affix,
    match,
    match_couplings,
    match_frames,
    match_joints,
    resolve_couplings,
)
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.filemode.read.model import Coupling, JointDesc, ModelDesc
from kinverify.generate import generate_mjcf, generate_urdf
from kinverify.model.specfile import spec_from_dict
from kinverify.run import VerifyOptions
import tests.filemode.pairs as P
from tests.filemode.pairs import generated_pair, ignored_by_drake, sub_once, write_pair

FAST = VerifyOptions(
    samples=8,
    fd_samples=4,
    backends=["pinocchio-urdf", "mujoco"],
    extra={"dynamics_samples": 12},
    suites=["kinematics", "limits", "inertia"],
)


def serious(result) -> list:
    return [(f.kind, f.subject) for f in result.findings if f.severity != "info" and not ignored_by_drake(f)]


def renamed(text: str, names: dict[str, str]) -> str:
    """Every joint name attribute and reference renamed (``name="joint2"``, ``joint="joint2"``)."""
    for old, new in names.items():
        text = re.sub(rf'(name|joint)="{old}"', rf'\1="{new}"', text)
    return text


def test_joint_names_carrying_two_numbers_are_matched_by_the_last(tmp_path):
    urdf, mjcf = generated_pair("arm3")
    urdf = renamed(urdf, {f"joint{k}": f"arm1_joint{k}" for k in (1, 2, 3)})  # "1" of arm1 is not the joint's number
    mjcf = renamed(mjcf, {f"joint{k}": f"j{k}" for k in (1, 2, 3)})
    result = verify_files(*write_pair(tmp_path, urdf, mjcf), FAST)
    pairs = [tuple(p[:2]) for p in result.model_info["joint_pairs"]]
    assert pairs == [("arm1_joint1", "j1"), ("arm1_joint2", "j2"), ("arm1_joint3", "j3")]
    assert result.passed, serious(result)


def hand() -> dict:
    """A wrist and a palm carrying two fingers and a thumb, two joints each (a tree)."""

    def finger(name, xyz, axis):
        return [
            {
                "name": f"{name}_base",
                "type": "revolute",
                "parent": "palm",
                "xyz": xyz,
                "axis": axis,
                "limits": {"lower": -1.0, "upper": 1.0, "unit": "rad"},
                "link": {"name": f"{name}_1", "mass": 0.02},
            },
            {
                "name": f"{name}_tip",
                "type": "revolute",
                "parent": f"{name}_1",
                "xyz": [0.0, 0.0, 0.04],
                "axis": axis,
                "limits": {"lower": 0.0, "upper": 1.5, "unit": "rad"},
                "link": {"name": f"{name}_2", "mass": 0.01},
            },
        ]

    joints = [
        {
            "name": "wrist",
            "type": "revolute",
            "xyz": [0.0, 0.0, 0.1],
            "axis": [0.0, 0.0, 1.0],
            "limits": {"lower": -3.0, "upper": 3.0, "unit": "rad"},
            "link": {"name": "palm", "mass": 0.3},
        }
    ]
    joints += finger("index", [0.03, 0.02, 0.05], [1.0, 0.0, 0.0]) + finger("ring", [0.03, -0.02, 0.05], [1.0, 0.0, 0.0])
    joints += finger("thumb", [-0.02, 0.01, 0.03], [0.0, 1.0, 1.0])
    return {"name": "hand", "base": {"link": {"name": "base"}}, "joints": joints}


def test_a_hands_fingers_are_matched_by_their_place_in_the_tree(tmp_path):
    """The URDF numbers its joints "0"..."6" in an order that is not the MJCF's, and no name says
    which finger is which: their place in the tree (the joint they hang from, how their axis
    lines lie to each other and to their parent's) does, as for the LEAP hand."""
    spec = spec_from_dict(hand())
    urdf, mjcf = generate_urdf(spec), generate_mjcf(spec)
    order = ["ring_tip", "thumb_base", "index_tip", "wrist", "ring_base", "thumb_tip", "index_base"]
    urdf = renamed(urdf, {name: str(k) for k, name in enumerate(order)})
    result = verify_files(*write_pair(tmp_path, urdf, mjcf), FAST)
    pairs = {a: b for a, b, *_ in result.model_info["joint_pairs"]}
    assert pairs == {str(k): name for k, name in enumerate(order)}
    assert result.passed, serious(result)


def test_a_site_named_like_a_link_elsewhere_is_no_twin_to_blame(tmp_path):
    """A URDF link ``panda_head`` fixed 0.1 m above panda_link7 and an MJCF site ``head`` 0.6 m above
    it on the same body: the names are alike once the prefix the URDF puts on every name is dropped,
    the places are not. No error: a name alike across kinds is no proof of one frame."""
    urdf, mjcf = generated_pair("panda")
    urdf = sub_once(
        r"</robot>",
        '<link name="panda_head"/><joint name="panda_head_fixed" type="fixed">'
        '<parent link="panda_link7"/><child link="panda_head"/><origin xyz="0 0 0.1"/></joint></robot>',
        urdf,
    )
    mjcf = sub_once(r'(<body name="panda_link7"[^>]*>)', lambda m: m[1] + '<site name="head" pos="0 0 0.6" size="0.01"/>', mjcf)
    result = verify_files(*write_pair(tmp_path, urdf, mjcf), FAST)
    assert result.passed, serious(result)
    twin = [f for f in result.findings if f.subject == "panda_head"]
    assert [(f.kind, f.severity, f.other) for f in twin] == [("frame_twin", "info", "head")]
    assert abs(twin[0].magnitude - 0.5) < 1e-9


def test_a_joint_renamed_under_a_joint_one_file_adds_is_matched_by_how_it_lies(tmp_path):
    """The MJCF names joint 7 wrist_roll and hangs its body from a 50 g slide the URDF lacks (as a
    mobile manipulator's MJCF hangs its fingers from a gripper slide). Under their nearest matched
    joint (joint 6), panda_joint7 and wrist_roll lie on its axis alike: one joint; the slide and
    its body are the extra part."""
    urdf, mjcf = P.generated_pair("panda")
    mjcf = P.suspended(mjcf.replace('"panda_joint7"', '"wrist_roll"'), "panda_link7", 0.05)
    result = verify_files(*write_pair(tmp_path, urdf, mjcf), FAST)
    pairs = {a: b for a, b, *_ in result.model_info["joint_pairs"]}
    assert pairs["panda_joint7"] == "wrist_roll"
    (extra,) = [f for f in result.findings if f.kind == "extra_parts"]
    assert extra.values["joints"] == ["suspension_joint"] and extra.values["mass_kg"] == pytest.approx(0.05)


def fingers() -> dict:
    """A wrist and two fingers of two joints each, on either side of the palm."""

    def finger(name, y):
        return [
            {
                "name": f"{name}_base",
                "type": "revolute",
                "parent": "palm",
                "xyz": [0.03, y, 0.05],
                "axis": [1.0, 0.0, 0.0],
                "limits": {"lower": -1.0, "upper": 1.0, "unit": "rad"},
                "link": {"name": f"{name}_1", "mass": 0.02},
            },
            {
                "name": f"{name}_tip",
                "type": "revolute",
                "parent": f"{name}_1",
                "xyz": [0.0, 0.0, 0.04],
                "axis": [1.0, 0.0, 0.0],
                "limits": {"lower": 0.0, "upper": 1.5, "unit": "rad"},
                "link": {"name": f"{name}_2", "mass": 0.01},
            },
        ]

    joints = [
        {
            "name": "wrist",
            "type": "revolute",
            "xyz": [0.0, 0.0, 0.1],
            "axis": [0.0, 0.0, 1.0],
            "limits": {"lower": -3.0, "upper": 3.0, "unit": "rad"},
            "link": {"name": "palm", "mass": 0.3},
        }
    ]
    return {
        "name": "fingers",
        "base": {"link": {"name": "base"}},
        "joints": joints + finger("index", 0.02) + finger("ring", -0.03),
    }


def test_a_number_two_urdf_joints_share_pairs_neither_with_the_one_mjcf_joint_carrying_it():
    """URDF finger1_joint1 and finger2_joint1 both end in 1, and only the MJCF's index_joint1 does:
    the number says nothing (two URDF joints share it), so each finger is paired by its place."""
    spec = spec_from_dict(fingers())
    urdf = renamed(
        generate_urdf(spec),
        {
            "index_base": "finger1_joint1",
            "index_tip": "finger1_joint2",
            "ring_base": "finger2_joint1",
            "ring_tip": "finger2_joint2",
        },
    )
    mjcf = renamed(generate_mjcf(spec), {"index_base": "index_joint1", "index_tip": "index_joint2"})
    pairs, free_u, free_m = match_joints(describe_urdf(urdf), describe_mjcf(mjcf))
    assert {a: b for a, b, _ in pairs} == {
        "wrist": "wrist",
        "finger1_joint1": "index_joint1",
        "finger1_joint2": "index_joint2",
        "finger2_joint1": "ring_base",
        "finger2_joint2": "ring_tip",
    }
    assert (free_u, free_m) == ([], [])
    assert {a: how for a, _, how in pairs}["finger2_joint1"] != "number in the name"


def test_a_leader_written_as_the_follower_of_its_follower_has_the_offset_taken_back():
    # a = 2 b + 0.3 with a first in the order: b is written in terms of a, b = (a - 0.3) / 2;
    # a chain c = -b + 0.1 then follows through b: c = -(a - 0.3) / 2 + 0.1
    a_b = Coupling("a", "b", 2.0, 0.3, "<mimic>")
    c_b = Coupling("c", "b", -1.0, 0.1, "<mimic>")
    out = resolve_couplings([a_b, c_b], ["a", "b", "c"])
    assert out["b"] == Coupling("b", "a", 0.5, pytest.approx(-0.15), "<mimic>")
    assert out["c"] == Coupling("c", "a", -0.5, pytest.approx(0.25), "<mimic>")


# --- each matching decision on descriptions built by hand (joints as axis lines, frames as poses) ---

Z3 = np.zeros(3)
EX, EY, EZ = np.eye(3)


def j(name, parent=None, axis=EZ, anchor=Z3, type="revolute", parent_frame=None) -> JointDesc:
    pf = parent_frame if parent_frame is not None else (f"{parent}_link" if parent else "base")
    return JointDesc(name, type, parent, f"{name}_link", pf, np.asarray(axis, float), np.asarray(anchor, float), -1.0, 1.0)


def d(joints, extra_frames=None, couplings=(), base="base") -> ModelDesc:
    """A description of ``joints`` with a ``base`` frame, a frame per joint (its child link, depth =
    chain depth) and ``extra_frames`` (name -> owner joint or None)."""
    frames, owner, depth = {base: np.eye(4)}, {base: None}, {base: 0}
    for x in joints:
        frames[x.child], owner[x.child] = np.eye(4), x.name
        up, k = x.parent, 1
        while up is not None:
            up, k = next(y.parent for y in joints if y.name == up), k + 1
        depth[x.child] = k
    for name, who in (extra_frames or {}).items():
        frames[name], owner[name], depth[name] = np.eye(4), who, 9
    return ModelDesc("urdf", "test", list(joints), frames, owner, depth, [], couplings=list(couplings))


def pairs_of(u, m, explicit=()) -> dict[str, tuple[str, str]]:
    pairs, _, _ = match_joints(u, m, explicit)
    return {a: (b, how) for a, b, how in pairs}


def test_matching_lookups():
    matching = Matching([("a", "x", "name"), ("b", "y", "name")], [], [], [], {"b": Coupling("b", "a", 1.0, 0.0, "<mimic>")})
    assert matching.independent == ["a"]
    assert (matching.mjcf_name("b"), matching.urdf_name("y"), matching.urdf_name("q")) == ("y", "b", None)


@pytest.mark.parametrize(
    ("names", "stripped"),
    [
        (["panda_joint1"], ["panda_joint1"]),
        (["panda_joint1", "panda_joint2"], ["joint1", "joint2"]),
        (["iiwa_joint_1", "iiwa_joint_2"], ["1", "2"]),
        (["r-arm-1", "r-arm-2"], ["1", "2"]),
        (["robot/arm/a", "robot/arm/b"], ["a", "b"]),  # up to the last separator of the common prefix
        (["ns:arm:a", "ns:arm:b"], ["a", "b"]),
        (["a_link", "b_link"], ["a", "b"]),
        (["x_a_link", "x_b_link"], ["a", "b"]),
        (["panda_", "panda_joint"], ["panda_", "joint"]),  # a name that is all prefix is kept whole
        (["joint1", "joint2"], ["joint1", "joint2"]),  # no separator: nothing to drop
        (["iiwa_a", "iiwa_b", "base"], ["a", "b", "base"]),  # most names share the prefix
        (["iiwa_a", "iiwa_b", "base", "foot"], ["iiwa_a", "iiwa_b", "base", "foot"]),  # half is not most
        (["iiwa_a", "iiwa_b", "kuka_c"], ["a", "b", "kuka_c"]),
        (["x_a", "y_b", "z_c"], ["x_a", "y_b", "z_c"]),
        (["a_x", "b_x", "c"], ["a", "b", "c"]),  # a suffix most names share
    ],
)
def test_strip_affix(names, stripped):
    assert _strip_affix(names) == stripped


def test_normalise_and_numbers():
    assert _normalise(["Panda_Joint-1", "Panda_Joint-2"]) == {"Panda_Joint-1": "1", "Panda_Joint-2": "2"}
    assert _normalise(["R_Hip.Yaw", "R_Knee"]) == {"R_Hip.Yaw": "hipyaw", "R_Knee": "knee"}
    assert _normalise(["a_--", "a_b"]) == {"a_--": "a_--", "a_b": "b"}  # nothing alphanumeric left: the name
    assert _numbers(["iiwa_joint_1", "arm1_j02", "j00", "hip"]) == {
        "iiwa_joint_1": "1",
        "arm1_j02": "2",
        "j00": "0",
        "hip": "~hip",
    }


def test_by_key_pairs_only_unique_keys():
    ku = {"a": "1", "b": "2", "c": "3", "c2": "3"}
    km = {"x": "1", "y": "2", "y2": "2", "z": "3"}
    assert _by_key(list(ku), list(km), ku, km) == [("a", "x")]


def test_descendants():
    assert _descendants(d([j("a"), j("b", "a"), j("c", "b"), j("e", "a"), j("f")])) == {"a": 3, "b": 1, "c": 0, "e": 0, "f": 0}


def test_joints_match_by_name_then_prefix_then_number_in_urdf_order():
    u = d([j("r_shoulder"), j("r_elbow", "r_shoulder"), j("r_wrist_3", "r_elbow")])
    m = d([j("r_shoulder"), j("Elbow", "r_shoulder"), j("j3", "Elbow")])
    pairs, free_u, free_m = match_joints(u, m)
    assert pairs == [
        ("r_shoulder", "r_shoulder", "name"),
        ("r_elbow", "Elbow", "name without prefix"),
        ("r_wrist_3", "j3", "number in the name"),
    ]
    assert (free_u, free_m) == ([], [])


def test_a_joint_paired_by_name_is_not_paired_again_by_its_place_in_the_tree():
    # the URDF's second joint at the base has nothing to pair with: the MJCF's only joint there is
    # already paired by name, and stays paired once
    u, m = d([j("shoulder"), j("mount_tilt")]), d([j("shoulder")])
    pairs, free_u, free_m = match_joints(u, m)
    assert pairs == [("shoulder", "shoulder", "name")] and (free_u, free_m) == (["mount_tilt"], [])


def test_given_joint_pairs_come_first():
    u, m = d([j("a"), j("b", "a")]), d([j("a"), j("b", "a")])
    assert pairs_of(u, m, ["a=b", "b=a"]) == {"a": ("b", "given"), "b": ("a", "given")}
    for bad in ("a", "=b", "a="):
        with pytest.raises(InputError, match="--joints: expected URDF_JOINT=MJCF_JOINT"):
            match_joints(u, m, [bad])
    with pytest.raises(UnknownNameError, match="unknown URDF joint 'q'"):
        match_joints(u, m, ["q=a"])
    with pytest.raises(UnknownNameError, match="unknown MJCF joint 'q'"):
        match_joints(u, m, ["a=q"])


def under_wrist(children_u, children_m):
    """A wrist on the base (matched by name) with unnamed children in each file."""
    return d([j("wrist"), *children_u]), d([j("wrist"), *children_m])


def test_siblings_paired_by_what_hangs_below_them():
    # alpha and beta lie alike on the wrist's axis (0.02 m to either side); alpha carries a joint
    u, m = under_wrist(
        [
            j("alpha", "wrist", EX, [0, 0.02, 0.1]),
            j("beta", "wrist", EX, [0, -0.02, 0.1]),
            j("tip", "alpha", EX, [0, 0.02, 0.15]),
        ],
        [
            j("gamma", "wrist", EX, [0, 0.02, 0.1]),
            j("delta", "wrist", EX, [0, -0.02, 0.1]),
            j("end", "delta", EX, [0, -0.02, 0.15]),
        ],
    )
    pairs = pairs_of(u, m)
    assert pairs["alpha"] == ("delta", "place in the tree") and pairs["beta"][0] == "gamma" and pairs["tip"][0] == "end"


def test_siblings_paired_by_their_distance_to_the_parent_axis():
    u, m = under_wrist(
        [j("alpha", "wrist", EX, [0, 0.02, 0.1]), j("beta", "wrist", EX, [0, -0.05, 0.1])],
        [j("gamma", "wrist", EX, [0, 0.05, 0.1]), j("delta", "wrist", EX, [0, -0.02, 0.1])],
    )
    assert {a: b for a, (b, _) in pairs_of(u, m).items()} == {"wrist": "wrist", "alpha": "delta", "beta": "gamma"}


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_siblings_paired_by_their_angle_to_the_parent_axis(sense):
    # the MJCF's axes may point the other way (a sign convention): the angle between lines counts, not its sense
    slant = np.array([0.0, 1.0, 1.0]) / math.sqrt(2)
    u, m = under_wrist(
        [j("alpha", "wrist", EX, [0, 0.02, 0.1]), j("beta", "wrist", slant, [0.02, 0, 0.1])],
        [j("gamma", "wrist", sense * slant, [0.02, 0, 0.1]), j("delta", "wrist", sense * EX, [0, 0.02, 0.1])],
    )
    assert {a: b for a, (b, _) in pairs_of(u, m).items()} == {"wrist": "wrist", "alpha": "delta", "beta": "gamma"}


def test_a_distance_to_the_parent_axis_weighs_against_the_siblings_spread():
    # alpha lies 2 cm from the wrist's axis at right angles, beta 5 cm at |cos| 0.2; the MJCF's gamma 5 cm at
    # right angles, delta 2 cm at 0.2. A 3 cm mismatch, against siblings 7 cm apart, outweighs 0.2 of a cosine
    tilted = np.array([math.sqrt(1 - 0.04), 0.0, 0.2])
    u, m = under_wrist(
        [j("alpha", "wrist", EX, [0, 0.02, 0.1]), j("beta", "wrist", tilted, [0, -0.05, 0.1])],
        [j("gamma", "wrist", EX, [0, -0.05, 0.1]), j("delta", "wrist", tilted, [0, 0.02, 0.1])],
    )
    assert {a: b for a, (b, _) in pairs_of(u, m).items()} == {"wrist": "wrist", "alpha": "delta", "beta": "gamma"}


def test_base_siblings_paired_by_the_distances_between_their_axes():
    u = d([j("a", None, EX, [0, 0, 0]), j("b", None, EX, [0, 0.05, 0]), j("c", None, EX, [0, 0, 0.03])])
    m = d([j("x", None, EX, [0, 0, 0.03]), j("y", None, EX, [0, 0.05, 0]), j("z", None, EX, [0, 0, 0])])
    assert {a: b for a, (b, _) in pairs_of(u, m).items()} == {"a": "z", "b": "y", "c": "x"}


@pytest.mark.parametrize("sense", [1.0, -1.0])
def test_base_siblings_paired_by_the_angles_between_their_axes(sense):
    c30 = np.array([math.cos(math.pi / 6), math.sin(math.pi / 6), 0.0])
    u = d([j("a", None, EX), j("b", None, EY), j("c", None, c30)])
    m = d([j("x", None, sense * c30), j("y", None, EX), j("z", None, EY)])
    assert {a: b for a, (b, _) in pairs_of(u, m).items()} == {"a": "y", "b": "z", "c": "x"}


def test_siblings_paired_by_type_and_never_across_types():
    u, m = under_wrist(
        [j("alpha", "wrist", EX, [0, 0.02, 0.1]), j("beta", "wrist", EX, [0, 0.02, 0.1], type="prismatic")],
        [j("gamma", "wrist", EX, [0, 0.02, 0.1], type="prismatic"), j("delta", "wrist", EX, [0, 0.02, 0.1])],
    )
    assert {a: b for a, (b, _) in pairs_of(u, m).items()} == {"wrist": "wrist", "alpha": "delta", "beta": "gamma"}
    u, m = under_wrist([j("alpha", "wrist", EX)], [j("gamma", "wrist", EX, type="prismatic")])
    pairs, free_u, free_m = match_joints(u, m)
    assert [p[:2] for p in pairs] == [("wrist", "wrist")] and (free_u, free_m) == (["alpha"], ["gamma"])


def test_mirror_image_siblings_keep_the_files_order():
    u, m = under_wrist(
        [j("alpha", "wrist", EX, [0, 0.02, 0.1]), j("beta", "wrist", EX, [0, -0.02, 0.1])],
        [j("gamma", "wrist", EX, [0, -0.02, 0.1]), j("delta", "wrist", EX, [0, 0.02, 0.1])],
    )
    assert {a: b for a, (b, _) in pairs_of(u, m).items()} == {"wrist": "wrist", "alpha": "gamma", "beta": "delta"}


def test_many_siblings_each_take_their_best_partner():
    # eight fingers at 1 ... 8 cm from the wrist's axis, the MJCF listing them in reverse (greedy pairing)
    u, m = under_wrist(
        [j(f"u{chr(97 + k)}", "wrist", EX, [0, 0.01 * (k + 1), 0.1]) for k in range(8)],
        [j(f"m{chr(97 + k)}", "wrist", EX, [0, 0.01 * (8 - k), 0.1]) for k in range(8)],
    )
    assert {a: b for a, (b, _) in pairs_of(u, m).items() if a != "wrist"} == {
        f"u{chr(97 + k)}": f"m{chr(97 + 7 - k)}" for k in range(8)
    }
    # one more in the MJCF: the URDF's all paired, the extra left
    m.joints.append(j("mz", "wrist", EX, [0, 0.5, 0.1]))
    pairs, free_u, free_m = match_joints(u, m)
    assert free_u == [] and free_m == ["mz"]


def test_a_joint_under_a_joint_one_file_adds_is_paired_when_it_lies_alike():
    # the MJCF hangs its joint from a slide the URDF lacks; under the wrist both lie alike (within 1 mm, 1e-3)
    def case(anchor, axis=EX):
        u = d([j("wrist"), j("alpha", "wrist", EX, [0, 0.02, 0.1])])
        m = d([j("wrist"), j("slide", "wrist", EZ, type="prismatic"), j("beta", "slide", axis, anchor)])
        return match_joints(u, m)

    pairs, free_u, free_m = case([0, 0.0209, 0.1])
    assert ("alpha", "beta", "place in the tree") in pairs and free_m == ["slide"]
    pairs, free_u, free_m = case([0, 0.0211, 0.1])
    assert free_u == ["alpha"] and free_m == ["slide", "beta"]
    tilted = [math.cos(0.02), 0.0, math.sin(0.02)]  # |cos| to the wrist's axis 0.02: off by more than 1e-3
    pairs, free_u, free_m = case([0, 0.02, 0.1], tilted)
    assert free_u == ["alpha"]
    slight = [math.cos(0.0009), 0.0, math.sin(0.0009)]
    assert ("alpha", "beta", "place in the tree") in case([0, 0.02, 0.1], slight)[0]


def test_mirror_twins_under_an_added_joint_go_by_the_closer_name():
    u = d([j("wrist"), j("left_f", "wrist", EX, [0, 0.02, 0.1]), j("right_f", "wrist", EX, [0, -0.02, 0.1])])
    m = d(
        [
            j("wrist"),
            j("slide", "wrist", EZ, type="prismatic"),
            j("rightfinger", "slide", EX, [0, -0.02, 0.1]),
            j("leftfinger", "slide", EX, [0, 0.02, 0.1]),
        ]
    )
    pairs = pairs_of(u, m)
    assert (pairs["left_f"][0], pairs["right_f"][0]) == ("leftfinger", "rightfinger")


def test_what_is_left_pairs_in_chain_order_while_types_and_axis_angles_agree():
    # the URDF's chain a -> b; the MJCF hangs both its joints on the base: b and y pair by chain order
    u = d([j("a", None, EZ, type="prismatic"), j("b", "a", EX), j("c", "b", EY)])
    m = d([j("x", None, EZ, type="prismatic"), j("y", None, EX, [0, 0, 0.3])])
    pairs, free_u, free_m = match_joints(u, m)
    assert ("b", "y", "chain order and axis") in pairs and (free_u, free_m) == (["c"], [])
    # both have parents: the angle to the parent axis must agree within 1e-3 of its cosine
    tilt = [0.0, math.sin(0.03), math.cos(0.03)]
    u = d([j("a"), j("b", "a", EY), j("c", "b", tilt)])
    m = d([j("x"), j("y", "x", EY), j("z", "x", [math.cos(0.03), 0.0, math.sin(0.03)], [0, 0.1, 0])])
    assert pairs_of(u, m)["c"] == ("z", "chain order and axis")
    m = d([j("x"), j("y", "x", EY), j("z", "x", [math.cos(0.0285), 0.0, math.sin(0.0285)], [0, 0.1, 0])])
    pairs, free_u, free_m = match_joints(u, m)
    assert (free_u, free_m) == (["c"], ["z"])


def test_chain_order_stops_at_the_first_type_that_differs():
    u = d([j("a", None, EZ, type="prismatic"), j("b", "a", EX, type="prismatic"), j("c", "b", EX)])
    m = d([j("x", None, EZ, type="prismatic"), j("y", None, EX, [0, 0, 0.3]), j("z", None, EX, [0, 0, 0.5])])
    pairs, free_u, free_m = match_joints(u, m)
    assert "b" in free_u and "c" in free_u


def test_resolve_couplings_group_root_and_skips():
    # b = 2 a + 0.1 (a mimic); e's leader is not compared
    couplings = [Coupling("b", "a", 2.0, 0.1, "<mimic>"), Coupling("e", "q", 1.0, 0.0, "<mimic>")]
    assert resolve_couplings(couplings, ["a", "b", "e"]) == {"b": Coupling("b", "a", 2.0, pytest.approx(0.1), "<mimic>", False)}
    assert resolve_couplings([Coupling("q", "a", 1.0, 0.0, "<mimic>")], ["a", "b"]) == {}
    assert resolve_couplings(couplings[::-1], ["a", "b", "e"]) == {
        "b": Coupling("b", "a", 2.0, pytest.approx(0.1), "<mimic>", False)
    }
    # the root is the first joint that is not a follower: with a a follower, b leads (a = (b - 0.1) / 2)
    out = resolve_couplings(couplings[:1], ["a", "b"], followers={"a"})
    assert out == {"a": Coupling("a", "b", 0.5, pytest.approx(-0.05), "<mimic>", False)}
    # a nonlinear coupling marks both its members' relations; another's source is its own
    out = resolve_couplings(
        [Coupling("a", "b", 2.0, 0.0, "<equality joint>", True), Coupling("c", "b", 3.0, 0.0, "<mimic>")], ["b", "a", "c"]
    )
    assert (out["a"].nonlinear, out["c"].nonlinear, out["c"].source) == (True, False, "<mimic>")
    # a leader written in terms of its follower takes the follower's source
    out = resolve_couplings([Coupling("b", "a", 2.0, 0.0, "<equality joint>")], ["b", "a"])
    assert out == {"a": Coupling("a", "b", 0.5, 0.0, "<equality joint>", False)}


def test_a_follower_held_at_its_offset_stays_coupled_and_ties_nothing_else():
    # d = 0·a + 0.2 (MuJoCo's polycoef "0.2 0 ..."): d is held, whichever joint comes first, and b = 2 a + 0.1
    # is still resolved (a group rooted at d once reached nothing and dropped both)
    held = Coupling("d", "a", 0.0, 0.2, "<equality joint>", nonlinear=True)
    mimic = Coupling("b", "a", 2.0, 0.1, "<mimic>")
    for order in (["a", "b", "d"], ["d", "a", "b"]):
        out = resolve_couplings([held, mimic], order)
        assert out == {
            "d": Coupling("d", "a", 0.0, 0.2, "<equality joint>", True),
            "b": Coupling("b", "a", 2.0, pytest.approx(0.1), "<mimic>", False),
        }


def test_match_couplings_the_urdf_s_own_then_the_mjcf_s_for_free_joints():
    u = d([j("a"), j("b", "a"), j("c", "b"), j("e", "c")], couplings=[Coupling("b", "a", 2.0, 0.0, "<mimic>")])
    m = d(
        [j("x"), j("y", "x"), j("z", "y"), j("w", "z")],
        couplings=[
            Coupling("y", "x", 3.0, 0.0, "<equality joint>"),  # b is the URDF's: its own stays
            Coupling("w", "z", -1.0, 0.5, "<equality joint>"),  # e and c are free in the URDF: taken
            Coupling("q", "x", 1.0, 0.0, "<equality joint>"),  # q is not matched
        ],
    )
    joints = [("a", "x", "given"), ("b", "y", "given"), ("c", "z", "given"), ("e", "w", "given")]
    out = match_couplings(u, m, joints)
    assert out == {
        "b": Coupling("b", "a", 2.0, 0.0, "<mimic>", False),
        "e": Coupling("e", "c", -1.0, 0.5, "<equality joint>", False),
    }
    # a URDF coupling between joints that are not matched is not taken
    u.couplings.append(Coupling("c", "zz", 1.0, 0.0, "<mimic>"))
    assert "c" not in match_couplings(u, m, joints)


def test_match_couplings_keeps_a_urdf_mimic_follower_a_follower():
    # the URDF's a = 2 b + 0.1 with a first in the chain: b stays the input, a its follower
    u = d([j("a"), j("b", "a")], couplings=[Coupling("a", "b", 2.0, 0.1, "<mimic>")])
    m = d([j("x"), j("y", "x")])
    out = match_couplings(u, m, [("a", "x", "given"), ("b", "y", "given")])
    assert out == {"a": Coupling("a", "b", 2.0, 0.1, "<mimic>", False)}


def test_match_couplings_an_mjcf_coupling_touching_a_urdf_coupled_joint_is_left_out():
    # the URDF couples b to a; the MJCF couples c to a (its follower free in the URDF, its leader not): the
    # URDF's group stands, c stays free
    u = d([j("a"), j("b", "a"), j("c", "b")], couplings=[Coupling("b", "a", 2.0, 0.0, "<mimic>")])
    m = d([j("x"), j("y", "x"), j("z", "y")], couplings=[Coupling("z", "x", 3.0, 0.0, "<equality joint>")])
    out = match_couplings(u, m, [("a", "x", "given"), ("b", "y", "given"), ("c", "z", "given")])
    assert out == {"b": Coupling("b", "a", 2.0, 0.0, "<mimic>", False)}


def test_match_frames_moving_frames_base_frames_and_names():
    u = d([j("a", parent_frame="base"), j("b", "a")], {"tool": "b", "cam": "a", "mount": None, "u_only": "b"})
    m = d([j("x", parent_frame="world"), j("y", "x")], {"tool": "y", "CAM": "x", "mount": None, "other": "y"}, base="world")
    joints = [("a", "x", "name"), ("b", "y", "name")]
    frames = match_frames(u, m, joints)
    assert frames == [
        ("base", "world", "a hangs from it"),
        ("a_link", "x_link", "moves with a"),
        ("b_link", "y_link", "moves with b"),
        ("tool", "tool", "same name"),
        ("mount", "mount", "same name"),
        ("cam", "CAM", "similar name"),
    ]


def test_match_frames_a_base_frame_the_other_file_names_otherwise_waits():
    # the URDF's first joint hangs from "base", the MJCF's from "world", and the MJCF has a frame "base" too
    u = d([j("a", parent_frame="base")])
    m = d([j("x", parent_frame="world")], {"base": None}, base="world")
    frames = match_frames(u, m, [("a", "x", "name")])
    assert ("base", "base", "same name") in frames and ("base", "world", "a hangs from it") not in frames
    # a first joint on a moving joint in one file is not on the base
    u = d([j("a", parent_frame="u_base")], {"u_base": None})
    m = d([j("w"), j("x", "w", parent_frame="m_base")], {"m_base": "w"}, base="world")
    frames = match_frames(u, m, [("a", "x", "name")])
    assert [f[2] for f in frames] == ["moves with a"]


def test_match_frames_a_frame_moving_with_another_joint_is_not_paired_by_name():
    u = d([j("a"), j("b", "a")], {"tool": "b", "flange": None})
    m = d([j("x"), j("y", "x")], {"tool": "x", "flange": "y"})
    frames = match_frames(u, m, [("a", "x", "name"), ("b", "y", "name")])
    assert not [f for f in frames if f[0] in ("tool", "flange")]


def test_match_frames_a_frame_paired_by_its_name_is_not_paired_again_by_a_similar_one():
    u = d([j("a"), j("b", "a")], {"Tool": "b"})
    m = d([j("x"), j("y", "x")], {"Tool": "y", "tool": "y"})
    frames = match_frames(u, m, [("a", "x", "name"), ("b", "y", "name")])
    assert [f for f in frames if "Tool" in f[:2] or "tool" in f[:2]] == [("Tool", "Tool", "same name")]
    frames = match_frames(m, u, [("x", "a", "name"), ("y", "b", "name")])
    assert [f for f in frames if "Tool" in f[:2] or "tool" in f[:2]] == [("Tool", "Tool", "same name")]


def test_match_frames_given_on_the_command_line():
    u, m = d([j("a")], {"tool": "a"}), d([j("x")], {"flange": "x"})
    frames = match_frames(u, m, [("a", "x", "name")], ["tool=flange"])
    assert ("tool", "flange", "given") in frames and len(frames) == 3
    for bad in ("tool", "=flange", "tool="):
        with pytest.raises(InputError, match="--frames: expected URDF_FRAME=MJCF_FRAME"):
            match_frames(u, m, [("a", "x", "name")], [bad])
    with pytest.raises(UnknownNameError, match="unknown URDF frame 'q'"):
        match_frames(u, m, [("a", "x", "name")], ["q=flange"])
    with pytest.raises(UnknownNameError, match="unknown MJCF frame 'q'"):
        match_frames(u, m, [("a", "x", "name")], ["tool=q"])
    # a given pair takes both frames: no name pairing of them after
    u, m = d([j("a")], {"tool": "a", "t2": "a"}), d([j("x")], {"tool": "x", "t2": "x"})
    frames = match_frames(u, m, [("a", "x", "name")], ["tool=t2"])
    assert ("tool", "t2", "given") in frames and not [f for f in frames if f[2] == "same name" and "tool" in f[:2]]


def test_match_refuses_files_it_cannot_compare():
    with pytest.raises(InputError, match="the URDF has no movable 1-DOF joints"):
        match(d([]), d([j("x")]))
    with pytest.raises(InputError, match="the MJCF has no movable hinge or slide joints"):
        match(d([j("a")]), d([]))
    with pytest.raises(InputError, match="no common joints: URDF has a; MJCF has x"):
        match(d([j("a", type="prismatic")]), d([j("x")]))
    result = match(d([j("a"), j("b", "a")], {"tool": "b"}), d([j("a"), j("b", "a")], {"tool": "b"}), frames=["a_link=b_link"])
    assert [p[:2] for p in result.joints] == [("a", "a"), ("b", "b")]
    assert ("a_link", "b_link", "given") in result.frames and result.couplings == {}
    assert (result.unmatched_urdf, result.unmatched_mjcf) == ([], [])
