"""Spec dataclasses and the TOML loader: valid input, and every class of bad input named by
file and field path."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kinverify import SpecError, load_spec, spec_from_dict
from kinverify.model.kinematics import frame_poses, geometric_jacobians
from kinverify.model.spec import Inertial, Joint, Limits, Link, Origin

MODELS = ["models/arm3.toml", "models/ur5e.toml", "models/panda.toml", "models/scara.toml"]


def minimal(**joint_overrides) -> dict:
    joint = {
        "name": "j1",
        "type": "revolute",
        "axis": [0, 0, 1],
        "xyz": [0, 0, 0.1],
        "limits": {"lower": -90, "upper": 90, "unit": "deg"},
    }
    joint.update(joint_overrides)
    return {
        "name": "arm",
        "joints": [
            joint,
            {"name": "j2", "axis": [0, 1, 0], "xyz": [0, 0, 0.3], "limits": {"lower": -1, "upper": 1, "unit": "rad"}},
        ],
    }


@pytest.mark.parametrize("path", MODELS)
def test_shipped_models_load(path):
    spec = load_spec(path)
    assert spec.dof >= 3
    assert len(set(spec.frame_names)) == len(spec.frame_names)
    assert np.all(spec.lower < spec.upper)


def test_arm3_matches_the_seed_parameters():
    spec = load_spec("models/arm3.toml")
    assert spec.base_origin.xyz == (0.0, 0.0, 0.42)
    assert [j.origin.xyz[2] for j in spec.joints] == [0.1, 0.3, 0.25]
    assert spec.tools[0].origin.xyz == (0.0, 0.0, 0.05)
    np.testing.assert_allclose(np.degrees(spec.upper), [180, 90, 135])
    np.testing.assert_allclose(np.degrees(spec.lower), [-180, -90, -135])


def test_degrees_are_converted_and_axis_normalised():
    spec = spec_from_dict(minimal(axis=[0, 0, 2]))
    assert spec.joints[0].limits.upper == pytest.approx(math.pi / 2)
    assert spec.joints[0].axis == (0.0, 0.0, 1.0)


def test_inertia_derived_from_geometry_is_valid():
    spec = spec_from_dict(minimal())
    for link in [spec.base_link] + [j.link for j in spec.joints]:
        eig = np.linalg.eigvalsh(link.inertial.matrix)
        assert eig[0] > 0 and link.inertial.mass > 0


def test_spec_is_frozen_and_limits_read_only():
    spec = spec_from_dict(minimal())
    with pytest.raises(AttributeError):
        spec.name = "other"
    with pytest.raises(ValueError):
        spec.lower[0] = 0.0


BAD = [
    ({"joints": "nope"}, "joints", "expected an array of tables"),
    ({"bogus": 1}, "bogus", "unknown field"),
    ({"name": None}, "name", "missing required field"),
    (minimal(axis=[0, 0, 0])["joints"], "joints[0].axis", "non-zero"),
    (minimal(limits={"lower": 10, "upper": -10, "unit": "deg"})["joints"], "joints[0].limits.lower", "below upper"),
    (minimal(limits={"lower": -1, "upper": 1})["joints"], "joints[0].limits.unit", "missing"),
    (minimal(type="ball")["joints"], "joints[0].type", "unknown joint type"),
    (minimal(link={"name": "l1", "mass": -1})["joints"], "joints[0].link.mass", "positive"),
    (
        minimal(link={"name": "l1", "geometry": {"shape": "capsule", "radius": -0.1, "fromto": [0, 0, 0, 0, 0, 1]}})["joints"],
        "joints[0].link.geometry.radius",
        "positive",
    ),
    (
        minimal(link={"name": "l1", "inertial": {"mass": 1, "inertia": [1, 1, -1, 0, 0, 0]}})["joints"],
        "joints[0].link.inertial.inertia",
        "positive definite",
    ),
    (
        minimal(link={"name": "l1", "inertial": {"mass": 1, "inertia": [1, 1, 5, 0, 0, 0]}})["joints"],
        "joints[0].link.inertial.inertia",
        "triangle",
    ),
    (minimal(name="j2")["joints"], "joints[1].name", "duplicate"),
    (minimal(xyz=[0, float("nan"), 0])["joints"], "joints[0].xyz", "finite"),
    (minimal(xyz=[0, 1e300, 0])["joints"], "joints[0].xyz", "finite"),
    (minimal(xyz=[0, 0])["joints"], "joints[0].xyz", "3 numbers"),
    (minimal(xyz="up")["joints"], "joints[0].xyz", "3 numbers"),
]


@pytest.mark.parametrize("patch, field, words", BAD)
def test_bad_input_names_the_field(patch, field, words):
    data = minimal()
    if isinstance(patch, list):
        data["joints"] = patch
    else:
        data.update(patch)
        data = {k: v for k, v in data.items() if v is not None}
    with pytest.raises(SpecError) as info:
        spec_from_dict(data, "models/bad.toml")
    err = info.value
    assert err.field == field, str(err)
    assert words in str(err)
    assert str(err).startswith(f"models/bad.toml: {field}: ")
    assert "\n" not in str(err)


def test_malformed_toml_names_the_file(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("name = 'x'\n[[joints]\n")
    with pytest.raises(SpecError, match=r"broken.toml: malformed TOML"):
        load_spec(path)


def test_unknown_tool_parent_lists_links():
    data = minimal()
    data["tools"] = [{"name": "t", "parent": "nowhere"}]
    with pytest.raises(SpecError, match=r"tools\[0\].parent: unknown link 'nowhere'; available links: base, link1, link2"):
        spec_from_dict(data)


def test_reserved_names_are_refused():
    with pytest.raises(SpecError, match="reserved"):
        spec_from_dict(minimal(link={"name": "world"}))


def test_dataclasses_validate_when_built_in_python():
    link = Link("l", Inertial(1.0))
    with pytest.raises(SpecError, match="axis"):
        Joint("j", "revolute", Origin(), (0, 0, 0), Limits(-1, 1), link)
    with pytest.raises(SpecError, match="lower"):
        Limits(1.0, -1.0)


def test_dh_and_origin_forms_cannot_mix():
    data = {
        "name": "a",
        "dh": {"convention": "standard", "angle_unit": "deg"},
        "joints": [{"dh": {"a": 0.1}, "xyz": [0, 0, 1], "limits": {"lower": -1, "upper": 1, "unit": "rad"}}],
    }
    with pytest.raises(SpecError, match=r"joints\[0\].xyz: DH joints"):
        spec_from_dict(data)


def _tree(parents: list) -> dict:
    joints = [
        {
            "name": f"j{i}",
            "axis": [0, 0, 1],
            "xyz": [0, 0, 0.1],
            "limits": {"lower": -1, "upper": 1, "unit": "rad"},
            "link": {"name": f"l{i}", "mass": 1.0},
            **({"parent": p} if p else {}),
        }
        for i, p in enumerate(parents)
    ]
    return {"name": "tree", "joints": joints}


def test_a_joint_hangs_from_the_base_or_an_earlier_link():
    spec = spec_from_dict(_tree([None, None, "l0", "base"]))
    assert spec.parent_indices == (0, 1, 1, 0) and not spec.is_serial
    assert spec.ancestors().tolist() == [
        [False] * 4,
        [True, False, False, False],
        [True, True, False, False],
        [True, False, True, False],
        [False, False, False, True],
    ]
    assert spec_from_dict(_tree([None, "l0"])).is_serial  # naming the default parent keeps a chain
    with pytest.raises(SpecError, match=r"joints\[1\].parent: a later joint's link 'l2'"):
        spec_from_dict(_tree([None, "l2", None]))
    with pytest.raises(SpecError, match=r"joints\[1\].parent: unknown link 'nowhere'"):
        spec_from_dict(_tree([None, "nowhere"]))
    with pytest.raises(SpecError, match=r"joints\[1\].parent: expected a string"):
        spec_from_dict(_tree([None, 3]))


def test_a_dh_table_describes_a_chain_only():
    with pytest.raises(SpecError, match="dh: a DH table describes a serial chain"):
        spec_from_dict(
            {
                "name": "dh",
                "dh": {"convention": "standard", "angle_unit": "rad"},
                "joints": [
                    {"dh": {"a": 0.1, "alpha": 0, "d": 0, "theta": 0}, "limits": {"lower": -1, "upper": 1, "unit": "rad"}},
                    {
                        "dh": {"a": 0.1, "alpha": 0, "d": 0, "theta": 0},
                        "parent": "base",
                        "limits": {"lower": -1, "upper": 1, "unit": "rad"},
                    },
                ],
            }
        )


def test_the_gripper_fingers_are_branches_of_the_palm():
    spec = load_spec("models/gripper.toml")
    palm = spec.link_index("palm")
    fingers = [spec.joint_names.index(n) for n in ("finger_left", "finger_right")]
    assert [spec.parent_indices[k] for k in fingers] == [palm, palm]
    q = np.zeros(spec.dof)
    q[fingers] = 0.03
    poses = frame_poses(spec, q)[0]
    left, right = (poses[spec.frame_names.index(f), :3, 3] for f in ("fingertip_left", "fingertip_right"))
    assert np.linalg.norm(left - right) == pytest.approx(0.06 + 0.02, abs=1e-12)
    jac = geometric_jacobians(spec, frame_poses(spec, q))[0]
    tip = spec.frame_names.index("fingertip_left")
    assert np.all(jac[tip][:, fingers[1]] == 0) and np.any(jac[tip][:, fingers[0]] != 0)  # the other finger does not move it


@pytest.mark.parametrize(
    "override, field, words",
    [
        ({"xyz": [True, False, True]}, "joints[0].xyz", "expected numbers, got [true, false, true]"),
        ({"axis": ["0", "0", "1"]}, "joints[0].axis", "expected numbers, got ['0', '0', '1']"),
        ({"damping": True}, "joints[0].damping", "got a boolean (true): booleans are not numbers"),
        ({"limits": {"lower": False, "upper": 90, "unit": "deg"}}, "joints[0].limits.lower", "booleans are not numbers"),
    ],
)
def test_booleans_and_text_are_not_numbers(override, field, words):
    with pytest.raises(SpecError) as err:
        spec_from_dict(minimal(**override), file="arm.toml")
    assert err.value.field == field and words in str(err.value) and str(err.value).startswith("arm.toml: ")


def test_a_boolean_field_takes_only_booleans():
    assert spec_from_dict({**minimal(), "base": {"floating": True}}).floating
    with pytest.raises(SpecError, match=r"base.floating: expected true or false, got 1"):
        spec_from_dict({**minimal(), "base": {"floating": 1}})


def test_a_geometry_too_small_for_its_volume_is_a_spec_error():
    tiny = minimal(link={"geometry": {"shape": "capsule", "radius": 1e-320, "fromto": [0, 0, 0, 0, 0, 0.3]}})
    with pytest.raises(SpecError, match="too small or too large to derive a mass and inertia"):
        spec_from_dict(tiny)


def test_more_joints_than_the_documented_maximum_are_refused():
    from kinverify.pipeline.limits import MAX_JOINTS

    data = minimal()
    data["joints"] = [dict(data["joints"][1], name=f"j{i}") for i in range(MAX_JOINTS + 1)]
    with pytest.raises(SpecError, match=f"joints: {MAX_JOINTS + 1} joints, above the {MAX_JOINTS}"):
        spec_from_dict(data)
