"""Matching decisions, each pinned by a pair built for it: joints by the number in their name (the
last one), the fingers of a hand by their place in the tree when the names say nothing, and names
alike across kinds (a link and a site) taken for no twins."""

from __future__ import annotations

import re

import pytest

from kinverify.filemode.align.match import match_joints, resolve_couplings
from kinverify.filemode.pipeline import verify_files
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.filemode.read.model import Coupling
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
