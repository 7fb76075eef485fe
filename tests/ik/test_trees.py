"""IK on trees: a frame on a branch is solved on its own branch's joints (random tree arms, FK ->
IK -> FK confirmed by Pinocchio), the shipped gripper's fingertip on every backend, the reach
bound of a branch, and a solver that solves almost nothing is a warning finding."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify import load_spec
from kinverify.backends import ModelSources, backend_info, build_backend
from kinverify.ik import FrameModel, IKOptions, reach_bound, residuals, solve_lm
from kinverify.pipeline.sampling import Samples
from kinverify.run import VerifyOptions, verify_spec
from kinverify.suites.base import VerifyContext
from kinverify.suites.ik import IKSuite
from kinverify.testing import strategies as kst
from tests.paths import MODELS

GRIPPER = load_spec(MODELS / "gripper.toml")
TOL = 1e-6


@settings(max_examples=25, deadline=None)
@given(kst.arm_specs(min_joints=2, max_joints=6, trees=True), kst.data())
def test_fk_ik_fk_on_any_frame_of_a_random_tree(spec, data):
    """A frame on a branch (its path skips an earlier joint) when the tree has one, else any frame
    but the base."""
    frames = spec.frame_names[1:]
    frame = data.draw(st.sampled_from([f for f in frames if _on_a_branch(spec, f)] or frames))
    q_true = data.draw(kst.configuration_batches(spec, 1, 3))
    sources = ModelSources.from_spec(spec)
    model = FrameModel(build_backend("analytic", sources), frame, sources.revolute)
    position_only = spec.dof < 6
    targets = model.poses(q_true)
    sol = solve_lm(
        model, targets, spec.lower, spec.upper, position_only, IKOptions(seed=1, max_restarts=300, time_budget=math.inf)
    )
    assert sol.solved(TOL, TOL).all(), (frame, sol.pos_error, sol.rot_error, q_true)
    assert ((sol.q >= spec.lower) & (sol.q <= spec.upper)).all()
    off_branch = ~_path(spec, frame)
    np.testing.assert_array_equal(sol.q[:, off_branch], sol.seed_q[:, off_branch])  # other branches are left alone
    pin = build_backend("pinocchio-urdf", sources)
    pos, rot = residuals(pin.poses(sol.q)[:, pin.frames.index(frame)], targets, position_only)
    assert (pos < TOL).all() and (rot < TOL).all()


def _path(spec, frame: str) -> np.ndarray:
    """``(dof,)`` bool: the joints that move ``frame``."""
    link = frame if frame in spec.link_names else next(t.parent for t in spec.tools if t.name == frame)
    return spec.ancestors()[spec.link_index(link)]


def _on_a_branch(spec, frame: str) -> bool:
    on = np.flatnonzero(_path(spec, frame))
    return bool(len(on)) and not _path(spec, frame)[: on[-1]].all()


def test_every_backend_solves_the_gripper_fingertip_and_no_warning_stands():
    result = verify_spec(GRIPPER, VerifyOptions(samples=0, suites=["ik"], extra={"ik_targets": 20}))
    rates = {c.backends[0]: c.max_error for c in result.checks if c.property == "ik.failure_rate"}
    drake = {"drake-urdf", "drake-mjcf", "drake-sdf"} if backend_info("drake-sdf").available else set()
    assert set(rates) == {"analytic", "pinocchio-urdf", "pinocchio-mjcf", "mujoco", "mujoco-urdf"} | drake
    assert all(r == 0.0 for r in rates.values()), rates
    assert all(c.frame == "fingertip_right" for c in result.checks)
    assert all(c.passed for c in result.checks) and not result.findings


def test_the_reach_bound_of_a_fingertip_counts_its_own_finger_only():
    centre, radius = reach_bound(GRIPPER, "fingertip_right")
    np.testing.assert_allclose(centre, [0, 0, 0.1])  # shoulder_yaw's origin
    path = 0.25 + 0.35 + 0.22 + math.hypot(0.01, 0.04) + 0.04 + 0.06  # offsets, the finger's travel, the tool
    assert math.isclose(radius, path, rel_tol=1e-12)


class _Starved(IKSuite):
    """The suite with one solver given no iterations on ``analytic``: it solves (almost) nothing."""

    def solve(self, backend, model, targets, lower, upper, position_only, options):
        if backend.name == "analytic":
            options = IKOptions(seed=options.seed, max_restarts=0, max_evaluations=1, start="given")
        return super().solve(backend, model, targets, lower, upper, position_only, options)


def test_a_solver_that_solves_almost_nothing_is_a_warning_finding():
    sources = ModelSources.from_spec(GRIPPER)
    options = VerifyOptions(samples=0, extra={"ik_targets": 8}, backends=["analytic", "pinocchio-urdf"])
    backends = {n: build_backend(n, sources) for n in options.backends}
    ctx = VerifyContext(sources, backends, Samples(sources.lower, sources.upper, sources.revolute, 0, 0), options)
    out = _Starved().run(ctx)
    rate = {c.backends[0]: c.max_error for c in out.checks if c.property == "ik.failure_rate"}
    assert rate["analytic"] >= 0.5 and rate["pinocchio-urdf"] == 0.0
    [warning] = out.findings
    assert warning.severity == "warning" and warning.kind == "ik_solver_fails" and not warning.fails
    assert warning.subject == "fingertip_right" and warning.values["backends"] == ["analytic"]
    assert "analytic solves" in warning.message and "pinocchio-urdf 8 of 8" in warning.message
