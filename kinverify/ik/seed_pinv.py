"""The seed tutorial's IK, reproduced as the baseline ``seed-pinv``.

Position only, from ``q0`` (the seed starts at ``q = 0``): up to 100 times, stop if
``‖target − p‖ < 1e-3``, else ``q += 0.1 · pinv(J_linear) (target − p)`` clipped to the limits.
``iterations`` counts the updates made before the stop (the seed's loop index at return).
Rows run in lock-step, so the analytic backend solves a whole batch per call.
"""

from __future__ import annotations

import time

import numpy as np

from kinverify.ik.frame_model import FrameModel, residuals
from kinverify.ik.lm import IKSolutions

STEP, TOL, MAX_ITER = 0.1, 1e-3, 100


def solve_seed_pinv(
    model: FrameModel,
    targets,
    lower,
    upper,
    q0=None,
    step: float = STEP,
    tol: float = TOL,
    max_iter: int = MAX_ITER,
    batch: bool | None = None,
) -> IKSolutions:
    targets = np.asarray(targets, dtype=float).reshape(-1, 4, 4)
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    b = len(targets)
    q0 = np.zeros((b, len(lower))) if q0 is None else np.asarray(q0, float).reshape(b, -1)
    batch = model.batched if batch is None else batch
    groups = [np.arange(b)] if batch else [np.array([k]) for k in range(b)]
    q, iters, times = q0.copy(), np.zeros(b, int), np.zeros(b)
    for rows in groups:
        t0 = time.perf_counter()
        q[rows], iters[rows] = _pinv_rows(model, targets[rows], q0[rows], lower, upper, step, tol, max_iter)
        times[rows] = (time.perf_counter() - t0) / len(rows)
    pos, _ = residuals(model.poses(q) if b else np.empty((0, 4, 4)), targets, True)
    return IKSolutions(
        "seed-pinv",
        model.name,
        model.frame,
        True,
        q,
        pos < tol,
        pos,
        np.zeros(b),
        iters,
        np.zeros(b, int),
        times,
        q0,
        batched=batch,
    )


def _pinv_rows(model, targets, q, lower, upper, step, tol, max_iter):
    q = q.copy()
    iters = np.full(len(q), max_iter)
    active = np.ones(len(q), bool)
    for i in range(max_iter):
        idx = np.flatnonzero(active)
        if not len(idx):
            break
        poses, jac = model(q[idx])
        err = targets[idx, :3, 3] - poses[:, :3, 3]
        conv = np.linalg.norm(err, axis=-1) < tol
        iters[idx[conv]] = i
        active[idx[conv]] = False
        move = ~conv
        dq = (np.linalg.pinv(jac[move, :3]) @ err[move, :, None])[..., 0]
        q[idx[move]] = np.clip(q[idx[move]] + step * dq, lower, upper)
    return q, iters
