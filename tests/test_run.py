"""The verify pipeline: shipped models agree; deliberately wrong models are caught and the first
disagreeing frame is named."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify import load_spec
from kinverify.testing import strategies as kst
from kinverify.backends import ModelSources, available_backends
from kinverify.backends.mujoco_ import MujocoBackend
from kinverify.backends.pinocchio_ import PinocchioBackend
from kinverify.run import VerifyOptions, model_info, verify, verify_spec


@pytest.mark.parametrize("path", ["models/arm3.toml", "models/ur5e.toml", "models/panda.toml", "models/scara.toml"])
def test_shipped_models_pass_below_1e9(path):
    result = verify_spec(load_spec(path), VerifyOptions(samples=100, fd_samples=30, suites=["kinematics"]))
    assert result.verdict == "pass", [c for c in result.failed][:3]
    fk = [c for c in result.checks if c.property == "fk.position"]
    assert {c.backends[1] for c in fk} >= {"pinocchio-urdf", "pinocchio-mjcf", "mujoco", "yourdfpy"}
    # the double-precision libraries agree below 1e-9 (the newton extra's float32 ones to their own floor)
    float32 = {n for n, info in available_backends().items() if info.extra == "newton"}
    assert max(c.max_error for c in fk if not set(c.backends) & float32) < 1e-9
    assert all(len(c.worst_q) == result.joint_names.__len__() for c in result.checks)


def flip_axis(urdf: str, joint: str) -> str:
    root = ET.fromstring(urdf)
    for j in root.iter("joint"):
        if j.get("name") == joint:
            axis = j.find("axis")
            axis.set("xyz", " ".join(repr(-float(v) + 0.0) for v in axis.get("xyz").split()))
    return ET.tostring(root, encoding="unicode")


def offset_body(mjcf: str, body: str, delta=(0.001, 0.0, 0.0)) -> str:
    root = ET.fromstring(mjcf)
    for b in root.iter("body"):
        if b.get("name") == body:
            pos = np.array([float(v) for v in b.get("pos").split()]) + delta
            b.set("pos", " ".join(repr(float(v)) for v in pos))
    return ET.tostring(root, encoding="unicode")


def _first_failure(spec, backend):
    options = VerifyOptions(samples=40, fd_samples=0, backends=["analytic"], suites=["kinematics"])
    result = verify(ModelSources.from_spec(spec), options, extra_backends=[backend])
    assert result.verdict == "fail"
    first = {c.property: c for c in result.first_failures()}
    return result, first


@settings(max_examples=15, deadline=None)
@given(kst.arm_specs(min_joints=2, max_joints=6, trees=True), st.data())
def test_flipped_axis_in_urdf_is_caught_at_its_link(spec, data):
    k = data.draw(st.integers(0, spec.dof - 1))
    mutated = flip_axis(ModelSources.from_spec(spec).urdf, spec.joints[k].name)
    backend = PinocchioBackend.from_urdf(mutated, spec.joint_names, spec.frame_names, name="pinocchio-urdf (mutated)")
    result, first = _first_failure(spec, backend)
    kind = "fk.rotation" if spec.joints[k].type == "revolute" else "fk.position"
    assert first[kind].frame == spec.joints[k].link.name
    assert first[kind].max_error > 1e-6


@settings(max_examples=15, deadline=None)
@given(kst.arm_specs(min_joints=2, max_joints=6, trees=True), st.data())
def test_1mm_origin_offset_in_mjcf_is_caught_at_its_link(spec, data):
    k = data.draw(st.integers(0, spec.dof - 1))
    mutated = offset_body(ModelSources.from_spec(spec).mjcf, spec.joints[k].link.name)
    backend = MujocoBackend.from_mjcf(mutated, spec.joint_names, spec.frame_names, name="mujoco (mutated)")
    result, first = _first_failure(spec, backend)
    check = first["fk.position"]
    assert check.frame == spec.joints[k].link.name
    assert check.max_error == pytest.approx(1e-3, rel=1e-6)
    assert check.backends == ("analytic", "mujoco (mutated)")


def test_failing_check_carries_a_reproducible_worst_configuration():
    spec = load_spec("models/arm3.toml")
    mutated = flip_axis(ModelSources.from_spec(spec).urdf, "joint2")
    backend = PinocchioBackend.from_urdf(mutated, spec.joint_names, spec.frame_names, name="mutant")
    result, first = _first_failure(spec, backend)
    check = first["fk.position"]
    assert check.frame == "link3"  # joint2 moves link2's frame in rotation only; positions differ from link3 on
    q = np.array([check.worst_q])
    ref = PinocchioBackend.from_urdf(ModelSources.from_spec(spec).urdf, spec.joint_names, ["link3"]).poses(q)
    bad = PinocchioBackend.from_urdf(mutated, spec.joint_names, ["link3"]).poses(q)
    assert np.linalg.norm(ref[0, 0, :3, 3] - bad[0, 0, :3, 3]) == pytest.approx(check.max_error, rel=1e-9)


def test_result_round_trips_through_its_dict():
    from kinverify.results import VerifyResult

    result = verify_spec(load_spec("models/scara.toml"), VerifyOptions(samples=10, fd_samples=5, suites=["kinematics"]))
    again = VerifyResult.from_dict(result.to_dict())
    assert again.to_dict() == result.to_dict()
    assert again.verdict == "pass"


def test_the_joint_table_of_a_floating_base_puts_each_axis_on_its_joint():
    """The six base coordinates come first in the table and have no axis; each joint's row has its own."""
    spec = load_spec("models/space_arm.toml")
    rows = model_info(ModelSources.from_spec(spec))["joints"]
    assert [r["name"] for r in rows] == list(spec.coordinate_names)
    assert [r.get("axis") for r in rows[:6]] == [None] * 6
    assert {r["name"]: r["axis"] for r in rows[6:]} == {j.name: list(j.axis) for j in spec.joints}
    assert len({tuple(j.axis) for j in spec.joints}) > 1  # a misplaced axis would show
