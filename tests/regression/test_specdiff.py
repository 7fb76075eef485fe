"""Parameter-level spec diff and the canonical spec form it is stored in."""

from __future__ import annotations

import copy
import tomllib

import pytest
from hypothesis import given, settings

from kinverify import spec_from_dict
from kinverify.testing import strategies as kst
from kinverify.model.canonical import spec_fingerprint, spec_from_canonical, spec_to_canonical
from kinverify.errors import InputError
from kinverify.regression.specdiff import ParamChange, diff_specs
from tests.paths import MODELS


def arm3_dict() -> dict:
    return tomllib.loads((MODELS / "arm3.toml").read_text())


def changed(edit) -> list:
    old = arm3_dict()
    new = copy.deepcopy(old)
    edit(new)
    return diff_specs(spec_from_dict(old), spec_from_dict(new))


@settings(max_examples=30, deadline=None)
@given(kst.arm_specs(max_joints=6))
def test_a_spec_equals_itself_and_its_canonical_round_trip(spec):
    assert diff_specs(spec, spec) == []
    back = spec_from_canonical(spec_to_canonical(spec))
    assert diff_specs(spec, back) == []
    assert spec_fingerprint(back) == spec_fingerprint(spec)


@settings(max_examples=30, deadline=None)
@given(kst.data())
def test_a_perturbation_is_one_change_of_the_right_size(data):
    spec = data.draw(kst.arm_specs(max_joints=5))
    scale = data.draw(kst.st.sampled_from([1e-3, 1e-2]))
    new = data.draw(kst.perturbed_specs(spec, scale))
    changes = diff_specs(spec, new)
    assert len(changes) == 1
    change = changes[0]
    assert change.kind == "changed" and change.field.split(".")[-1] in ("xyz", "rpy")
    assert scale / 2 * (1 - 1e-9) <= change.delta <= scale * (1 + 1e-9)
    assert spec_fingerprint(new) != spec_fingerprint(spec)


def test_each_kind_of_parameter_is_named():
    def limits(d):
        d["joints"][1]["limits"]["upper"] = 80

    def axis(d):
        d["joints"][2]["axis"] = [1.0, 0.0, 0.0]

    def inertia(d):
        d["joints"][0]["link"]["inertial"] = {"mass": 2.0, "com": [0, 0, 0.1], "inertia": [0.01, 0.01, 0.005, 0, 0, 0]}

    def damping(d):
        d["joints"][0]["damping"] = 0.5

    (c,) = changed(limits)
    assert (c.where, c.field) == ("joint joint2", "limits.upper")
    assert c.delta == pytest.approx(10 / 180 * 3.141592653589793)
    (c,) = changed(axis)
    assert (c.where, c.field, c.new) == ("joint joint3", "axis", (1.0, 0.0, 0.0))
    fields = {(c.where, c.field) for c in changed(inertia)}
    assert {("link link1", "inertial.mass"), ("link link1", "inertial.com"), ("link link1", "inertial.inertia")} <= fields
    (c,) = changed(damping)
    assert (c.where, c.field, c.old, c.new) == ("joint joint1", "damping", 0.1, 0.5)


def test_names_added_and_removed():
    def rename_tool(d):
        d["tools"][0]["name"] = "tcp"

    def add_joint(d):
        d["joints"].append(
            {
                "name": "wrist",
                "xyz": [0, 0, 0.05],
                "axis": [0, 0, 1],
                "limits": {"lower": -1, "upper": 1, "unit": "rad"},
                "link": {"name": "link4"},
            }
        )
        d["tools"][0]["parent"] = "link4"

    kinds = {(c.where, c.kind) for c in changed(rename_tool)}
    assert kinds == {("tool end_effector", "removed"), ("tool tcp", "added")}
    kinds = {(c.where, c.kind) for c in changed(add_joint)}
    assert {("joint wrist", "added"), ("link link4", "added")} <= kinds
    assert any(c.where == "tool end_effector" and c.field == "parent" for c in changed(add_joint))
    assert "added" in next(c for c in changed(add_joint) if c.where == "joint wrist").describe()


def test_a_broken_stored_spec_is_an_input_error():
    data = spec_to_canonical(spec_from_dict(arm3_dict()))
    del data["joints"][0]["axis"]
    with pytest.raises(InputError, match="malformed stored spec"):
        spec_from_canonical(data)
    data = spec_to_canonical(spec_from_dict(arm3_dict()))
    data["joints"][0]["limits"]["lower"] = 10.0
    with pytest.raises(InputError, match="invalid stored spec"):
        spec_from_canonical(data)


def test_a_change_reads_as_a_line():
    def axis(d):
        d["joints"][2]["axis"] = [1.0, 0.0, 0.0]

    (c,) = changed(axis)
    assert c.describe() == "joint joint3: axis [0, 1, 0] -> [1, 0, 0] (Δ 1.41421)"


def test_a_joint_removed_gravity_and_joint_order_changed():
    def remove_joint3(d):
        del d["joints"][2]
        d["tools"][0]["parent"] = "link2"

    def gravity(d):
        d["gravity"] = [0.0, 0.0, -9.80665]

    def swap(d):
        d["joints"][1], d["joints"][2] = d["joints"][2], d["joints"][1]

    assert ParamChange("joint joint3", "name", "removed", "joint3", None) in changed(remove_joint3)
    assert [(c.where, c.field, c.kind) for c in changed(gravity)] == [("arm", "gravity", "changed")]
    order = [c for c in changed(swap) if c.field == "joint order"]
    assert order == [ParamChange("arm", "joint order", "changed", ["joint1", "joint2", "joint3"], ["joint1", "joint3", "joint2"])]
