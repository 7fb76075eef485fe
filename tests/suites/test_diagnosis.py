"""Diagnosis hints on real backends: a flipped joint axis, a changed joint origin, a scaled joint
(random specs from kinverify.strategies, the analytic FK and Pinocchio)."""

from __future__ import annotations

import copy

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify.testing import strategies as kst
from kinverify.backends import FunctionBackend, ModelSources
from kinverify.backends.analytic import AnalyticBackend
from kinverify.suites.diagnosis import diagnose_pair, spearman
from kinverify.model.kinematics import frame_poses
from kinverify.pipeline.sampling import sample_configurations
from kinverify.model.specfile import load_spec, spec_from_dict
from kinverify.run import VerifyOptions, verify
from tests.paths import MODELS

TOL = 1e-9


def _diagnose(spec, other):
    q = sample_configurations(spec.lower, spec.upper, [j.type == "revolute" for j in spec.joints], 40, 1)
    return diagnose_pair(AnalyticBackend(spec), other, q, spec.frame_names, list(spec.joint_names), TOL, TOL)


@settings(max_examples=25, deadline=None)
@given(kst.spec_dicts(max_joints=6), st.data())
def test_a_flipped_joint_axis_is_named(d, data):
    k = data.draw(st.integers(0, len(d["joints"]) - 1))
    broken = copy.deepcopy(d)
    broken["joints"][k]["axis"] = [-v for v in d["joints"][k]["axis"]]
    spec = spec_from_dict(d)
    found = _diagnose(spec, AnalyticBackend(spec_from_dict(broken)))
    assert found is not None and found["hint"] is not None
    assert found["hint"]["kind"] == "joint-sign-flip" and found["hint"]["joint"] == spec.joint_names[k]
    assert found["first_frame"] == spec.frame_names[k + 1]  # the link the joint moves
    assert found["worst"] and all(len(w["q"]) == spec.dof for w in found["worst"])


@settings(max_examples=25, deadline=None)
@given(kst.spec_dicts(max_joints=6), st.data())
def test_a_moved_joint_origin_is_a_constant_offset_of_the_right_size(d, data):
    k = data.draw(st.integers(0, len(d["joints"]) - 1))
    delta = np.array(data.draw(kst.vectors(-0.05, 0.05).filter(lambda v: np.linalg.norm(v) > 1e-3)))
    broken = copy.deepcopy(d)
    broken["joints"][k]["xyz"] = (np.array(d["joints"][k]["xyz"]) + delta).tolist()
    spec = spec_from_dict(d)
    found = _diagnose(spec, AnalyticBackend(spec_from_dict(broken)))
    assert found is not None and found["first_frame"] == spec.frame_names[k + 1]
    hint = found["hint"]
    assert hint["kind"] == "constant-offset"
    np.testing.assert_allclose(np.linalg.norm(hint["offset"]), np.linalg.norm(delta), rtol=1e-6)


def test_a_scaled_joint_is_an_error_growing_with_that_joint():
    spec = load_spec(MODELS / "arm3.toml")
    scale = np.array([1.0, 1.05, 1.0])
    geared = FunctionBackend("geared", lambda q: frame_poses(spec, q * scale)[..., :3, 3], spec.joint_names, spec.frame_names)
    found = _diagnose(spec, geared)
    assert found["hint"]["kind"] == "grows-with-joint" and found["hint"]["joint"] == "joint2"


def test_agreeing_backends_get_no_diagnosis_and_the_verify_section_says_so():
    spec = load_spec(MODELS / "arm3.toml")
    assert _diagnose(spec, AnalyticBackend(spec)) is None
    result = verify(ModelSources.from_spec(spec), VerifyOptions(samples=5, suites=["kinematics", "diagnosis"]))
    assert result.sections["diagnosis"].data["pairs"] == [] and "agrees" in result.sections["diagnosis"].summary


@given(st.lists(st.floats(-1e3, 1e3, allow_nan=False), min_size=3, max_size=30))
def test_spearman_of_a_sample_with_itself_and_its_reverse(x):
    x = np.array(x)
    if len(np.unique(x)) == len(x):  # no ties
        assert np.isclose(spearman(x, x), 1.0) and np.isclose(spearman(x, -x), -1.0)
    assert -1.0 - 1e-12 <= spearman(x, x[::-1]) <= 1.0 + 1e-12
