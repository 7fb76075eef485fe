"""Damped least squares / Levenberg-Marquardt IK on any :class:`FrameModel`, with random restarts.

Each iteration solves ``(JᵀJ + λI) dq = Jᵀe`` for the pose error ``e`` of
:func:`~kinverify.ik.frame_model.pose_errors` (position only: the 3 linear rows), projects
``q + dq`` onto the joint limits (clip) and accepts the step only if the squared error drops
(λ ÷ 10), else rejects it (λ × 10). An attempt that runs ``max_iter`` iterations or whose λ
exceeds ``stuck_damping`` (a local minimum, often against a limit) restarts from a uniform
random configuration inside the limits, up to ``max_restarts`` times or the time budget. An attempt
counts as stalled after ``max_iter`` iterations without halving its error (near a singularity LM
converges linearly: it is kept going while it keeps halving, up to ``max_attempt_iter``).

Rows are solved in lock-step: the analytic backend evaluates every active row in one numpy call,
so many targets (and their restarts) are solved at once (``batch=True``). Other backends solve
one target per call so each solve gets its own wall-clock time.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from kinverify.ik.frame_model import FrameModel, pose_error_single, pose_errors, residuals


_STREAM = 0x1C  # separates IK starts from uniform_configurations(seed)


@dataclass(frozen=True)
class IKOptions:
    tol_pos: float = 1e-12  # m: stop when the position error is below this...
    tol_rot: float = 1e-12  # rad: ...and the rotation error below this (full-pose targets)
    max_iter: int = 30  # an attempt ends after this many iterations without halving its error...
    max_attempt_iter: int = 300  # ...or after this many in all (slow but steady near singularities)
    max_restarts: int = 100  # random restarts after the first attempt
    time_budget: float = 1.0  # s per target (a batch gets time_budget × rows)
    damping: float = 1e-3  # initial λ
    min_damping: float = 1e-12
    stuck_damping: float = 1e8
    seed: int = 0  # random restarts (and random first guesses) come from default_rng([seed, _STREAM])


@dataclass
class IKSolutions:
    """Per target: the solution (or, when not solved, the closest configuration found)."""

    solver: str
    backend: str
    frame: str
    position_only: bool
    q: np.ndarray  # (B, n)
    success: np.ndarray  # (B,) bool: within the solver's tolerance
    pos_error: np.ndarray  # (B,) m, from the solver backend's own FK
    rot_error: np.ndarray  # (B,) rad (0 for position-only)
    iterations: np.ndarray  # (B,) total over all attempts
    restarts: np.ndarray  # (B,)
    time_s: np.ndarray  # (B,) per solve; in a batch, the batch time / B
    seed_q: np.ndarray  # (B, n): first configuration of the last attempt
    batched: bool = False
    extra: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.q)

    def solved(self, tol_pos: float, tol_rot: float) -> np.ndarray:
        return (self.pos_error <= tol_pos) & (self.rot_error <= tol_rot)


def solve_lm(model: FrameModel, targets, lower, upper, position_only: bool = False,
             options: IKOptions | None = None, q0=None, batch: bool | None = None) -> IKSolutions:
    """Solve IK for ``targets`` ``(B, 4, 4)`` (position-only: only the translation is used).

    ``q0`` ``(B, n)``: first guesses (default uniform random inside the limits).
    """
    opts = options or IKOptions()
    targets = np.asarray(targets, dtype=float).reshape(-1, 4, 4)
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    rng = np.random.default_rng([opts.seed, _STREAM])  # not the stream sampling.py draws targets from
    b = len(targets)
    q0 = rng.uniform(lower, upper, (b, len(lower))) if q0 is None else np.asarray(q0, float).reshape(b, -1)
    batch = model.batched if batch is None else batch
    if batch:
        t0 = time.perf_counter()
        out = _lm_rows(model, targets, q0, lower, upper, position_only, opts, rng, t0 + opts.time_budget * max(b, 1))
        out["time_s"] = np.full(b, (time.perf_counter() - t0) / max(b, 1))
    else:
        rows = []
        for k in range(b):
            t0 = time.perf_counter()
            r = _lm_single(model, targets[k], q0[k], lower, upper, position_only, opts, rng, t0 + opts.time_budget)
            r["time_s"] = np.array([time.perf_counter() - t0])
            rows.append(r)
        out = {key: np.concatenate([r[key] for r in rows]) if rows else np.empty(0) for key in
               ("q", "success", "pos_error", "rot_error", "iterations", "restarts", "time_s", "seed_q")}
        if not rows:
            out["q"] = out["seed_q"] = np.empty((0, len(lower)))
    return IKSolutions("lm", model.name, model.frame, position_only, batched=batch, **out)


def _step(j, err, lam, eye):
    jt = np.swapaxes(j, -1, -2)
    return np.linalg.solve(jt @ j + lam[:, None, None] * eye, jt @ err[:, :, None])[..., 0]


def wrappable(lower, upper, model) -> np.ndarray:
    """Revolute joints whose range spans at least 2π: q ± 2π is the same pose."""
    revolute = np.asarray(getattr(model, "revolute", np.ones(len(lower), bool)))
    return revolute & (upper - lower >= 2 * np.pi)


def project(q, lower, upper, wrap) -> np.ndarray:
    """Onto the limits: a wrappable joint beyond a limit first moves by ∓2π (same pose), then clip."""
    if wrap.any():
        q = np.where(wrap & (q > upper), q - 2 * np.pi, q)
        q = np.where(wrap & (q < lower), q + 2 * np.pi, q)
    return np.clip(q, lower, upper)


def _lm_rows(model, targets, q, lower, upper, position_only, opts, rng, deadline) -> dict:
    b, n = q.shape
    wrap = wrappable(lower, upper, model)
    q = np.clip(q, lower, upper)
    seed_q = q.copy()
    poses, jac = model(q)
    err = pose_errors(poses, targets, position_only)
    cost = np.einsum("bi,bi->b", err, err)
    pos, rot = residuals(poses, targets, position_only)
    best_q, best_cost, best_pos, best_rot = q.copy(), cost.copy(), pos.copy(), rot.copy()
    lam = np.full(b, opts.damping)
    iters, attempt, restarts, stall = np.zeros(b, int), np.zeros(b, int), np.zeros(b, int), np.zeros(b, int)
    ref_cost = cost.copy()
    success = (pos <= opts.tol_pos) & (rot <= opts.tol_rot)
    done = success.copy()
    eye = np.eye(n)
    rows_j = slice(0, 3) if position_only else slice(0, 6)
    while not done.all():
        idx = np.flatnonzero(~done)
        j = jac[idx, rows_j]
        step = _step(j, err[idx], lam[idx], eye)
        # Joints the step would push through a limit they cannot wrap past are frozen, and the
        # step is recomputed for the others (an active-set projection; plain clipping stalls).
        over = ~wrap & (((q[idx] + step) > upper) | ((q[idx] + step) < lower))
        if over.any():
            step = np.where(over.any(axis=1)[:, None], _step(j * ~over[:, None, :], err[idx], lam[idx], eye), step)
        qn = project(q[idx] + step, lower, upper, wrap)
        pn, jn = model(qn)
        en = pose_errors(pn, targets[idx], position_only)
        cn = np.einsum("bi,bi->b", en, en)
        better = cn < cost[idx]
        acc = idx[better]
        q[acc], poses[acc], jac[acc], err[acc], cost[acc] = qn[better], pn[better], jn[better], en[better], cn[better]
        lam[acc] = np.maximum(lam[acc] / 10, opts.min_damping)
        lam[idx[~better]] *= 10
        iters[idx] += 1
        attempt[idx] += 1
        halved = cost[idx] < 0.25 * ref_cost[idx]
        ref_cost[idx[halved]] = cost[idx[halved]]
        stall[idx] = np.where(halved, 0, stall[idx] + 1)
        pos_i, rot_i = residuals(poses[idx], targets[idx], position_only)
        improved = cost[idx] < best_cost[idx]
        imp = idx[improved]
        best_q[imp], best_cost[imp], best_pos[imp], best_rot[imp] = q[imp], cost[imp], pos_i[improved], rot_i[improved]
        conv = (pos_i <= opts.tol_pos) & (rot_i <= opts.tol_rot)
        success[idx[conv]] = done[idx[conv]] = True
        ended = idx[~conv & ((stall[idx] >= opts.max_iter) | (attempt[idx] >= opts.max_attempt_iter)
                             | (lam[idx] > opts.stuck_damping))]
        if time.perf_counter() > deadline:
            done[idx] = True
            break
        again = ended[restarts[ended] < opts.max_restarts]
        done[ended[restarts[ended] >= opts.max_restarts]] = True
        if len(again):
            q[again] = seed_q[again] = rng.uniform(lower, upper, (len(again), n))
            poses[again], jac[again] = model(q[again])
            err[again] = pose_errors(poses[again], targets[again], position_only)
            cost[again] = np.einsum("bi,bi->b", err[again], err[again])
            lam[again], attempt[again], stall[again], ref_cost[again] = opts.damping, 0, 0, cost[again]
            restarts[again] += 1
    q_out = np.where(success[:, None], q, best_q)
    pos_out = np.where(success, residuals(poses, targets, position_only)[0], best_pos)
    rot_out = np.where(success, residuals(poses, targets, position_only)[1], best_rot)
    return {"q": q_out, "success": success, "pos_error": pos_out, "rot_error": rot_out, "iterations": iters,
            "restarts": restarts, "seed_q": seed_q}


def _lm_single(model, target, q, lower, upper, position_only, opts, rng, deadline) -> dict:
    """The same iteration as :func:`_lm_rows` for one target, with per-call overhead kept small."""
    n = len(q)
    wrap = wrappable(lower, upper, model)
    rows = 3 if position_only else 6
    eye = np.eye(n)
    q = seed_q = np.clip(q, lower, upper)
    pose, jac = model.single(q)
    err, pos, rot = pose_error_single(pose, target, position_only)
    cost = err @ err
    best = (cost, q, pos, rot)
    lam, iters, attempt, restarts, stall, ref_cost = opts.damping, 0, 0, 0, 0, cost
    success = pos <= opts.tol_pos and rot <= opts.tol_rot
    while not success:
        j = jac[:rows]
        step = np.linalg.solve(j.T @ j + lam * eye, j.T @ err)
        trial = q + step
        over = ~wrap & ((trial > upper) | (trial < lower))
        if over.any():
            jm = j * ~over
            step = np.linalg.solve(jm.T @ jm + lam * eye, jm.T @ err)
        qn = project(q + step, lower, upper, wrap)
        pn, jn = model.single(qn)
        en, pn_pos, pn_rot = pose_error_single(pn, target, position_only)
        cn = en @ en
        iters += 1
        attempt += 1
        stall += 1
        if cn < cost:
            q, jac, err, cost, pos, rot = qn, jn, en, cn, pn_pos, pn_rot
            lam = max(lam / 10, opts.min_damping)
            if cost < best[0]:
                best = (cost, q, pos, rot)
            success = pos <= opts.tol_pos and rot <= opts.tol_rot
            if cost < 0.25 * ref_cost:
                ref_cost, stall = cost, 0
        else:
            lam *= 10
        if success:
            break
        if stall >= opts.max_iter or attempt >= opts.max_attempt_iter or lam > opts.stuck_damping:
            if restarts >= opts.max_restarts or time.perf_counter() > deadline:
                break
            q = seed_q = rng.uniform(lower, upper)
            pose, jac = model.single(q)
            err, pos, rot = pose_error_single(pose, target, position_only)
            cost, lam, attempt, stall = err @ err, opts.damping, 0, 0
            ref_cost = cost
            restarts += 1
            success = pos <= opts.tol_pos and rot <= opts.tol_rot
        elif time.perf_counter() > deadline:
            break
    if not success:
        _, q, pos, rot = best
    return {"q": q[None], "success": np.array([success]), "pos_error": np.array([pos]), "rot_error": np.array([rot]),
            "iterations": np.array([iters]), "restarts": np.array([restarts]), "seed_q": seed_q[None]}
