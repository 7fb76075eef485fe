"""Behaviour-level difference of two model versions (``kinverify diff``): frames compared at the old
spec's seeded samples, the configuration where a frame moved (or turned) most, workspace reach of
both versions, and the versions that cannot be compared at the same configurations."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from kinverify import load_spec
from kinverify.pipeline.sampling import spec_samples
from kinverify.regression.modeldiff import ReachChange, diff_models, frame_changes, reach

MODELS = Path(__file__).resolve().parents[2] / "models"
ARM3 = load_spec(MODELS / "arm3.toml")


def turned_axis(spec, index: int):
    """``spec`` with joint ``index``'s axis reversed: its child frame turns the other way, in place."""
    joints = list(spec.joints)
    joints[index] = replace(joints[index], axis=tuple(-a for a in joints[index].axis))
    return replace(spec, joints=tuple(joints))


def test_a_model_against_itself_is_identical():
    d = diff_models(ARM3, ARM3, samples=4)
    assert d.identical and d.params == [] and d.notes == [] and d.samples == len(spec_samples(ARM3, 4, 0))
    assert [f.frame for f in d.frames] == list(ARM3.frame_names)
    assert all((f.position, f.rotation, f.jacobian_linear, f.jacobian_angular) == (0, 0, 0, 0) for f in d.frames)
    ((frame, old, new),) = [(r.frame, r.old, r.new) for r in d.reach]
    assert frame == "end_effector" and old == new == reach(ARM3)["end_effector"] and d.reach[0].change == 0


def test_the_reach_is_the_farthest_tool_position_from_the_base():
    # arm3 stretched upwards: base link at z 0.42, tool 0.1 + 0.3 + 0.25 + 0.05 above it
    assert reach(ARM3, samples=10) == {"end_effector": pytest.approx(0.7, abs=1e-12)}


def test_frames_are_compared_at_the_old_specs_seeded_samples():
    longer = replace(
        ARM3, joints=(*ARM3.joints[:2], replace(ARM3.joints[2], origin=replace(ARM3.joints[2].origin, xyz=(0, 0, 0.26))))
    )
    d = diff_models(ARM3, longer, samples=6, seed=3)
    assert d.frames == frame_changes(ARM3, longer, spec_samples(ARM3, 6, 3))
    moved = {f.frame: f.position for f in d.frames if f.position > 0}
    assert moved == {"link3": pytest.approx(0.01, abs=1e-12), "end_effector": pytest.approx(0.01, abs=1e-12)}
    assert d.reach == [ReachChange("end_effector", reach(ARM3)["end_effector"], reach(longer)["end_effector"])]
    assert d.reach[0].change == pytest.approx(0.01, abs=1e-9)


def test_a_frame_that_only_turns_is_reported_where_it_turns_most():
    # joint3's axis reversed: link3 sits on that axis (it does not move) and turns by 2 q3; the
    # reported configuration is where it turns most, not the first sample
    d = diff_models(ARM3, turned_axis(ARM3, 2), samples=8)
    link3 = next(f for f in d.frames if f.frame == "link3")
    assert link3.position == pytest.approx(0, abs=1e-12) and link3.rotation > 1
    turn = abs(2 * link3.q[2]) % (2 * math.pi)
    assert min(turn, 2 * math.pi - turn) == pytest.approx(link3.rotation, abs=1e-9)
    assert link3.jacobian_linear == pytest.approx(0, abs=1e-12) and link3.jacobian_angular > 1


@pytest.mark.parametrize(
    ("new", "what"),
    [
        ("scara.toml", "joint count changed (3 -> 4)"),
        ("space_arm.toml", "the base floats in one version only"),
    ],
)
def test_versions_with_other_coordinates_are_not_compared_frame_by_frame(new, what):
    other = load_spec(MODELS / new)
    d = diff_models(ARM3, other, samples=4)
    assert d.notes == [f"{what}: FK and Jacobians cannot be compared at the same configurations"]
    assert d.frames == [] and d.samples == 0 and not np.array_equal(ARM3.lower, other.lower[: ARM3.nq])
    tools = list(other.tool_names)
    assert [r.frame for r in d.reach] == ["end_effector", *tools]
    assert d.reach[0].new is None and d.reach[-1].old is None and d.reach[-1].new == reach(other)[tools[-1]]


def test_limits_changed_are_said():
    first = ARM3.joints[0]
    narrower = replace(ARM3, joints=(replace(first, limits=replace(first.limits, upper=1.0)), *ARM3.joints[1:]))
    assert diff_models(ARM3, narrower, samples=4).notes == [
        "joint limits changed: FK and Jacobians are compared inside the old limits"
    ]
