"""The IK solver's parts: serial chains (from specs and URDFs) against the analytic FK and
Pinocchio, joint limits and whole-turn wrapping, the seed table, batched against per-target
solving, and FK -> IK -> FK through a chain read from a generated URDF (real pin)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify.backends import ModelSources, build_backend
from kinverify.errors import InputError
from kinverify.generate import generate_urdf
from kinverify.ik import FrameModel, IKOptions, SeedTable, SerialChain, residuals, solve_lm
from kinverify.ik.batch import _Limits, spd_solve
from kinverify.model.kinematics import frame_poses, geometric_jacobians
from kinverify.model.specfile import spec_from_dict
from kinverify.testing import strategies as kst
from tests.paths import REAL_ROBOTS

TOL = 1e-6


@settings(max_examples=30, deadline=None)
@given(kst.arm_specs(min_joints=1, max_joints=8, trees=True), kst.data())
def test_chain_fk_and_jacobian_equal_the_analytic_ones_for_every_frame(spec, data):
    """Serial arms and trees: a frame on a branch is moved by its own branch's joints only."""
    q = data.draw(kst.configuration_batches(spec, 1, 6))
    poses = frame_poses(spec, q)
    jac = geometric_jacobians(spec, poses)
    urdf = generate_urdf(spec)
    for f, frame in enumerate(spec.frame_names):
        from_spec, from_urdf = SerialChain.from_spec(spec, frame), SerialChain.from_urdf(urdf, "world", frame)
        assert from_spec.names == from_urdf.names  # the same path, from the base to the frame
        for chain, cols in ((from_spec, slice(None)), (from_urdf, [spec.joint_names.index(n) for n in from_urdf.names])):
            rot, p, j = chain.fk_jac(q[:, cols])
            np.testing.assert_allclose(rot, poses[:, f, :3, :3], atol=1e-12)
            np.testing.assert_allclose(p, poses[:, f, :3, 3], atol=1e-12)
            np.testing.assert_allclose(j, jac[:, f][:, :, cols], atol=1e-12)


@pytest.mark.skipif(not (REAL_ROBOTS / "panda" / "panda_erd.urdf").is_file(), reason="no ../shared/real-robots")
def test_chain_from_the_panda_urdf_matches_pinocchio():
    from kinverify.backends.pinocchio_ import PinocchioBackend

    text = (REAL_ROBOTS / "panda" / "panda_erd.urdf").read_text()
    chain = SerialChain.from_urdf(text, "panda_link0", "panda_link8")
    assert chain.names == [f"panda_joint{i}" for i in range(1, 8)]  # the mimic finger is not on the chain
    pin = PinocchioBackend.from_urdf(text, chain.names, ["panda_link8"])
    q = np.random.default_rng(0).uniform(chain.lower, chain.upper, (20, 7))
    ev = pin.evaluate(q)
    rot, p, jac = chain.fk_jac(q)
    np.testing.assert_allclose(p, ev.poses[:, 0, :3, 3], atol=1e-12)
    np.testing.assert_allclose(rot, ev.poses[:, 0, :3, :3], atol=1e-12)
    np.testing.assert_allclose(jac, ev.jacobians[:, 0], atol=1e-12)


CLASH = """<robot name="clash">
  <link name="base"/><link name="arm"/><link name="tip"/><link name="finger"/>
  <joint name="arm" type="revolute"><parent link="base"/><child link="arm"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="tip_joint" type="fixed"><parent link="arm"/><child link="tip"/><origin xyz="0.4 0 0" rpy="0 0.3 0"/></joint>
  <joint name="finger_joint" type="prismatic"><parent link="tip"/><child link="finger"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="0.1" effort="1" velocity="1"/><mimic joint="arm"/></joint>
</robot>"""


def test_urdf_chain_looks_up_links_not_joints_and_refuses_what_it_cannot_solve():
    from kinverify.backends.pinocchio_ import PinocchioBackend

    # a joint named like a link: the frame is the link's (Pinocchio has a frame for each)
    chain = SerialChain.from_urdf(CLASH, "base", "arm")
    pin = PinocchioBackend.from_urdf(CLASH, ["arm", "finger_joint"], ["arm", "tip"])
    q = np.array([[0.7, 0.0], [-0.4, 0.0]])
    np.testing.assert_allclose(chain.poses(q[:, :1]), pin.poses(q)[:, 0], atol=1e-12)
    np.testing.assert_allclose(SerialChain.from_urdf(CLASH, "base", "tip").poses(q[:, :1]), pin.poses(q)[:, 1], atol=1e-12)
    with pytest.raises(InputError, match="no link 'tip_joint' .a joint has that name"):
        SerialChain.from_urdf(CLASH, "base", "tip_joint")  # a joint, not a link
    with pytest.raises(InputError, match="mimics"):
        SerialChain.from_urdf(CLASH, "base", "finger")
    with pytest.raises(InputError, match="not below"):
        SerialChain.from_urdf(CLASH, "tip", "arm")


def _one_joint(lower: float, upper: float) -> FrameModel:
    spec = spec_from_dict(
        {
            "name": "wheel",
            "joints": [
                {
                    "name": "j",
                    "type": "revolute",
                    "axis": [0, 0, 1],
                    "limits": {"lower": lower, "upper": upper, "unit": "rad"},
                    "link": {"name": "l"},
                }
            ],
            "tools": [{"name": "tip", "parent": "l", "xyz": [0.5, 0, 0]}],
        }
    )
    sources = ModelSources.from_spec(spec)
    return FrameModel(build_backend("analytic", sources), "tip", sources.revolute), spec


@pytest.mark.parametrize("batch", [True, False])
def test_a_revolute_joint_spanning_a_whole_turn_wraps_across_its_limit(batch):
    """From just inside +π the target at −π + 0.2 lies 0.4 rad ahead, across the limit: the step
    goes there by a whole turn (same pose) and converges in the first attempt; clipping at +π
    instead would stall against the limit and need a restart."""
    model, spec = _one_joint(-math.pi, math.pi)
    target = model.poses(np.array([[-math.pi + 0.2]]))
    sol = solve_lm(
        model, target, spec.lower, spec.upper, True, IKOptions(max_restarts=0), q0=np.array([[math.pi - 0.2]]), batch=batch
    )
    assert sol.success[0] and sol.restarts[0] == 0 and sol.iterations[0] <= 6
    assert sol.q[0, 0] == pytest.approx(-math.pi + 0.2, abs=1e-9)


def test_wrapping_moves_revolute_joints_by_whole_turns_only_when_that_lands_inside():
    lower, upper = np.array([-math.pi, -0.1, -math.pi, 0.0]), np.array([math.pi, 6.0, math.pi, 1.0])
    limits = _Limits(lower, upper, np.array([True, True, False, False]))  # the last two: prismatic
    x = np.array([[math.pi + 0.3], [-0.5], [math.pi + 0.3], [1.5]])
    q, clipped = limits.wrapclip(x)
    np.testing.assert_allclose(q[:, 0], [-math.pi + 0.3, 2 * math.pi - 0.5, math.pi, 1.0])
    np.testing.assert_array_equal(clipped[:, 0] != 0, [False, False, True, True])
    q, clipped = limits.wrapclip(np.array([[math.pi + 0.3], [-0.2], [0.0], [0.5]]))  # −0.2 + 2π is beyond 6.0
    assert q[1, 0] == -0.1 and clipped[1, 0] != 0


def test_spd_solve_small_and_large_batches():
    rng = np.random.default_rng(3)
    for m in (5, 400):  # LAPACK below the threshold, the vectorised LDLᵀ above
        j = rng.normal(size=(6, 7, m))
        a = np.einsum("akm,bkm->abm", j, j) + 1e-3 * np.eye(6)[:, :, None]
        b = rng.normal(size=(6, m))
        x = spd_solve(a, b)
        np.testing.assert_allclose(np.einsum("abm,bm->am", a, x), b, atol=1e-9)


def test_seed_table_candidates_are_inside_the_limits_and_ranked_nearest_first():
    model, spec = _one_joint(-2.0, 2.5)
    table = SeedTable(model.soa, spec.lower, spec.upper, samples=500, k=8)
    assert ((table.q >= spec.lower) & (table.q <= spec.upper)).all()
    target = model.poses(np.array([[1.0]]))[0]
    candidates, order = table.ranked(target)
    d = np.linalg.norm(model.poses(candidates[order])[:, :3, 3] - target[:3, 3], axis=1)
    assert (np.diff(d) >= -1e-12).all() and d[0] < 0.05
    np.testing.assert_array_equal(table.query(target[None], 2)[0], candidates[order[2]])


def test_batched_and_per_target_solvers_take_the_same_steps():
    """One row per target, no restarts: the batched iteration is the per-target one, vectorised."""
    spec = spec_from_dict(PANDA_LIKE)
    sources = ModelSources.from_spec(spec)
    model = FrameModel(build_backend("analytic", sources), "tool", sources.revolute)
    rng = np.random.default_rng(5)
    q_true = rng.uniform(spec.lower, spec.upper, (40, spec.dof))
    q0 = np.clip(q_true + rng.normal(0, 0.2, q_true.shape), spec.lower, spec.upper)
    targets = model.poses(q_true)
    opts = IKOptions(max_restarts=0)
    batch, each = (solve_lm(model, targets, spec.lower, spec.upper, False, opts, q0=q0, batch=b) for b in (True, False))
    np.testing.assert_array_equal(batch.success, each.success)
    np.testing.assert_array_equal(batch.iterations, each.iterations)
    np.testing.assert_allclose(batch.q, each.q, atol=1e-9)
    assert batch.success.mean() > 0.8


PANDA_LIKE = {
    "name": "six",
    "joints": [
        {
            "name": f"j{i}",
            "type": "revolute",
            "xyz": xyz,
            "rpy": rpy,
            "axis": [0, 0, 1],
            "limits": {"lower": -2.9, "upper": 2.9, "unit": "rad"},
            "link": {"name": f"l{i}"},
        }
        for i, (xyz, rpy) in enumerate(
            [
                ([0, 0, 0.33], [0, 0, 0]),
                ([0, 0, 0], [-1.5708, 0, 0]),
                ([0, -0.32, 0], [1.5708, 0, 0]),
                ([0.08, 0, 0], [1.5708, 0, 0]),
                ([-0.08, 0.38, 0], [-1.5708, 0, 0]),
                ([0, 0, 0], [1.5708, 0, 0]),
            ]
        )
    ],
    "tools": [{"name": "tool", "parent": "l5", "xyz": [0.09, 0, 0.1]}],
}


@settings(max_examples=15, deadline=None)
@given(kst.arm_specs(min_joints=1, max_joints=7), st.integers(0, 2**16), kst.data())
def test_fk_ik_fk_through_a_chain_read_from_the_generated_urdf(spec, seed, data):
    """Random reachable targets on random arms, solved on the URDF chain and confirmed by
    Pinocchio on the same URDF (position only below 6 joints, as the suite does)."""
    q_true = data.draw(kst.configuration_batches(spec, 1, 5))
    urdf = generate_urdf(spec)
    frame = spec.frame_names[-1]
    chain = SerialChain.from_urdf(urdf, "world", frame)
    model = FrameModel.from_chain(chain, frame=frame)
    q = q_true[:, : chain.dof]
    targets = model.poses(q)
    position_only = chain.dof < 6
    lo, hi = chain.lower, chain.upper
    sol = solve_lm(model, targets, lo, hi, position_only, IKOptions(seed=seed, max_restarts=300, time_budget=math.inf))
    assert sol.solved(TOL, TOL).all(), (sol.pos_error, sol.rot_error)
    assert ((sol.q >= lo) & (sol.q <= hi)).all()
    from kinverify.backends.pinocchio_ import PinocchioBackend

    pin = PinocchioBackend.from_urdf(urdf, chain.names, [frame])
    pos, rot = residuals(pin.poses(sol.q)[:, 0], targets, position_only)
    assert (pos < TOL).all() and (rot < TOL).all()


@pytest.mark.parametrize("batch", [True, False])
def test_a_seeded_start_takes_the_nearer_of_the_guess_and_the_best_stored_seed(batch):
    spec = spec_from_dict(PANDA_LIKE)
    sources = ModelSources.from_spec(spec)
    model = FrameModel(build_backend("analytic", sources), "tool", sources.revolute)
    q_true = np.random.default_rng(11).uniform(spec.lower, spec.upper, (30, spec.dof))
    targets = model.poses(q_true)
    # the guess is the answer: kept (two evaluations to compare, one to see it is solved)
    sol = solve_lm(model, targets, spec.lower, spec.upper, False, IKOptions(start="seeded"), q0=q_true, batch=batch)
    assert (sol.iterations == 3).all() and (sol.restarts == 0).all()
    np.testing.assert_allclose(sol.q, q_true, atol=1e-12)
    # a guess far from every target: the first attempt starts at the target's best seed when that is nearer
    far = np.clip(q_true + 2.0, spec.lower, spec.upper)
    opts = IKOptions(start="seeded", max_restarts=0)
    sol = solve_lm(model, targets, spec.lower, spec.upper, False, opts, q0=far, batch=batch)
    table, _ = model.seed_table(spec.lower, spec.upper, False, opts.seed_samples)
    best = table.query(targets, 0)

    def energy(q):
        pos, rot = residuals(model.poses(q), targets, False)
        return pos**2 + rot**2

    nearer = energy(best) < energy(far)
    assert nearer.mean() > 0.5
    np.testing.assert_array_equal(sol.seed_q[nearer], best[nearer])
    np.testing.assert_array_equal(sol.seed_q[~nearer], far[~nearer])
