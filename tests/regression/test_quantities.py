"""Baseline IK quantities: the fixed targets a new baseline stores (the end frame's pose at the last
configurations, starts 5 % of the way to the middle of the limits) and their solutions by a later
model (none when the frame or the joint count changed)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from kinverify import load_spec
from kinverify.errors import InputError
from kinverify.model.kinematics import frame_poses
from kinverify.pipeline.sampling import spec_samples
from kinverify.regression.quantities import IK_TARGETS, ik_fixed, ik_frame, ik_parse, ik_records

MODELS = Path(__file__).resolve().parents[2] / "models"
ARM3 = load_spec(MODELS / "arm3.toml")
Q = spec_samples(ARM3, 6, 0)  # the edge rows, then 6 uniform ones


def test_the_fixed_targets_are_the_end_frames_poses_at_the_last_configurations():
    fixed = ik_fixed(ARM3, Q)
    assert (fixed["frame"], fixed["position_only"]) == ("end_effector", True) and ik_frame(ARM3) == "end_effector"
    samples = [t["sample"] for t in fixed["targets"]]
    assert samples == list(range(len(Q) - IK_TARGETS, len(Q)))
    poses = frame_poses(ARM3, Q[samples])[:, ARM3.frame_names.index("end_effector")]
    np.testing.assert_array_equal(np.array([t["pose"] for t in fixed["targets"]]), poses)
    middle = (np.asarray(ARM3.lower) + np.asarray(ARM3.upper)) / 2
    np.testing.assert_allclose([t["start"] for t in fixed["targets"]], Q[samples] + 0.05 * (middle - Q[samples]))
    assert [t["sample"] for t in ik_fixed(ARM3, Q[:2])["targets"]] == [0, 1]  # fewer configurations than targets


def test_the_targets_are_reached_from_their_starts():
    fixed = ik_fixed(ARM3, Q)
    records = ik_records(ARM3, Q, fixed)
    samples = [t["sample"] for t in fixed["targets"]]
    assert [(r["property"], r["sample"]) for r in records] == [(p, s) for s in samples for p in ("ik.q", "ik.error")]
    errors = [r["value"] for r in records if r["property"] == "ik.error"]
    assert all(pos < 1e-9 for pos, _ in errors)
    solved = np.array([r["value"] for r in records if r["property"] == "ik.q"])
    reached = frame_poses(ARM3, solved)[:, ARM3.frame_names.index("end_effector"), :3, 3]
    np.testing.assert_allclose(reached, np.array([t["pose"] for t in fixed["targets"]])[:, :3, 3], atol=1e-9)


def test_no_ik_records_when_the_frame_or_the_joint_count_changed():
    fixed = ik_fixed(ARM3, Q)
    assert ik_records(ARM3, Q, {**fixed, "frame": "gone"}) == []
    scara = load_spec(MODELS / "scara.toml")
    assert ik_records(scara, Q, {**fixed, "frame": "flange"}) == []
    assert ik_records(ARM3, Q, {**fixed, "targets": []}) == []


def test_malformed_fixed_targets_are_refused():
    with pytest.raises(InputError, match="4x4 pose"):
        ik_parse({"frame": "f", "targets": [{"pose": [1, 2], "start": [0], "sample": 0}]})
    fixed = ik_fixed(ARM3, Q)
    with pytest.raises(InputError, match="name stored samples"):
        ik_parse(fixed, n_samples=len(Q) - 1)
