"""The per-target IK solver: one target at a time, each with its own wall-clock time.

The same iteration as :mod:`kinverify.ik.batch` on one configuration, written for low per-call
overhead: ``ndarray.dot`` instead of ``@`` on small arrays, an eigenpy ``LLT`` for the m×m system
when Pinocchio (which ships eigenpy) is loaded, and a library FK that returns live views where it
can (:meth:`kinverify.backends.pinocchio_.PinocchioBackend.frame_kinematics`: one
``computeFrameJacobian`` per iteration).
"""

from __future__ import annotations

import math
import sys
import time

import numpy as np

POOL = 1024  # random restart configurations drawn at a time


def solve_each(fk, log3, targets, q0, lower, upper, wrap, position_only: bool, opts, seeds, rng) -> dict:
    """Solve ``targets`` ``(N, 4, 4)`` one by one from ``q0`` ``(N, n)``.

    ``fk(q (n,)) -> (R (3, 3), p (3,), J (6, n))``: tip rotation, position [m] and world-aligned
    Jacobian (may be views valid until the next call); ``log3(M (3, 3)) -> (3,)`` the rotation
    vector. Other arguments as :func:`kinverify.ik.batch.solve_rows`; ``opts.time_budget`` is per
    target. Returns the per-target arrays of :class:`IKSolutions`, ``time_s`` included, and
    ``cpu_s`` (process CPU time per target: the wall time minus what other processes took).
    """
    n_t, n = q0.shape
    solve = _spd_solver(3 if position_only else 6)
    lo_s, hi_s = np.where(np.isfinite(lower), lower, -np.pi), np.where(np.isfinite(upper), upper, np.pi)
    mid = 0.5 * (lo_s + hi_s)
    wrap = np.asarray(wrap, bool)
    margin = np.where(wrap, 2 * np.pi - (upper - lower), np.inf)
    margin2 = float(np.min(np.maximum(margin, 0.0), initial=np.inf)) ** 2

    def wrap_fix(x, y):
        """``x`` raw, ``y`` = clip(x): joints a whole turn brings inside move there instead."""
        w = x - np.round((x - mid) / (2 * np.pi)) * (2 * np.pi)
        ok = (y != x) & wrap & (w >= lower) & (w <= upper)
        return np.where(ok, w, y), ok

    def onto_limits(x):
        y = np.minimum(np.maximum(x, lower), upper)
        return wrap_fix(x, y)[0] if (y != x).any() else y

    pool, pool_i = rng.uniform(lo_s, hi_s, (POOL, n)), 0
    seeded = opts.start == "seeded" and seeds is not None

    def energy_at(q, rt, pt):
        rot, pos, _ = fk(q)
        d = pt - pos
        return d.dot(d) + (0.0 if position_only else float(np.sum(log3(rt.dot(rot.T)) ** 2)))

    tp2, tr2 = opts.tol_pos**2, opts.tol_rot**2
    mu, w_n, clamp_below, max_eval = opts.mu, opts.w_n, opts.clamp_below, opts.max_evaluations
    sw, sr = opts.stall_window, opts.stall_ratio
    m = 3 if position_only else 6
    a, e = np.empty((m, m)), np.empty(m)
    diagonal = a.reshape(-1)[:: m + 1]  # views: λ is added in place, the error written in place
    ep, er = e[:3], e[3:]
    subtract, minimum, maximum = np.subtract, np.minimum, np.maximum
    out = {
        "q": np.empty((n_t, n)),
        "success": np.zeros(n_t, bool),
        "pos_error": np.empty(n_t),
        "rot_error": np.empty(n_t),
        "iterations": np.zeros(n_t, int),
        "restarts": np.zeros(n_t, int),
        "time_s": np.empty(n_t),
        "seed_q": np.empty((n_t, n)),
        "cpu_s": np.empty(n_t),
    }
    clock, cpu = time.perf_counter, time.process_time
    for k in range(n_t):
        t0, c0 = clock(), cpu()
        deadline = t0 + opts.time_budget
        target = np.ascontiguousarray(targets[k])
        rt, pt = target[:3, :3].copy(), target[:3, 3].copy()
        q = seed = onto_limits(q0[k])
        it = it_att = restarts = skip = 0
        cap, ewin, best, ok = opts.first_attempt_iter, math.inf, (math.inf, q, q, math.inf, math.inf), False
        candidates = None
        if seeded:  # start from the best stored seed when it is nearer the target than q0
            candidates, order = seeds.ranked(target)
            if energy_at(candidates[order[0]], rt, pt) < energy_at(q, rt, pt):
                q = seed = candidates[order[0]]
                skip = 1  # restarts take the seeds after it
            it = 2
        while it < max_eval:
            rot, pos, jac = fk(q)
            subtract(pt, pos, out=ep)
            pe2 = ep.dot(ep)
            if position_only:
                re2, jac = 0.0, jac[:3]
            else:
                er[:] = log3(rt.dot(rot.T))
                re2 = er.dot(er)
            it += 1
            it_att += 1
            if pe2 <= tp2 and re2 <= tr2:
                best, ok = (0.0, q, seed, pe2, re2), True
                break
            energy = 0.5 * (pe2 + re2)
            if energy < best[0]:
                best = (energy, q, seed, pe2, re2)
            if it_att % sw == 1:
                ewin = energy
            if it_att >= cap or (it_att % sw == 0 and energy > sr * ewin):  # attempt over: restart
                if restarts >= opts.max_restarts or clock() > deadline:
                    break
                if opts.perturb_sigma > 0 and restarts >= opts.perturb_after and restarts % 2 == 1:
                    q = onto_limits(best[1] + opts.perturb_sigma * rng.standard_normal(n))
                elif seeds is not None and restarts + skip < seeds.k:
                    if candidates is None:
                        candidates, order = seeds.ranked(target)
                    q = candidates[order[restarts + skip]]
                else:
                    if pool_i == POOL:
                        pool, pool_i = rng.uniform(lo_s, hi_s, (POOL, n)), 0
                    q, pool_i = pool[pool_i], pool_i + 1
                seed, restarts, it_att, cap = q, restarts + 1, 0, opts.attempt_iter
                continue
            lam = mu * energy + w_n
            jac.dot(jac.T, out=a)
            diagonal += lam
            x = q + solve(a, e).dot(jac)
            qn = minimum(maximum(x, lower), upper)
            d = x - qn
            dd = d.dot(d)
            if dd > 0.0:
                if dd >= margin2:
                    qn, wrapped = wrap_fix(x, qn)
                    d = np.where(wrapped, 0.0, d)
                    dd = d.dot(d)
                if energy < clamp_below and dd > 0.0:
                    # joints pushed onto a limit stay there; the others take the rest of the error
                    free = d == 0.0
                    held = (qn - q) * ~free
                    jm = jac * free
                    jm.dot(jm.T, out=a)
                    diagonal += lam
                    qn = onto_limits(q + solve(a, e - jac.dot(held)).dot(jm) + held)
            q = qn
        out["time_s"][k], out["cpu_s"][k] = clock() - t0, cpu() - c0
        _, out["q"][k], out["seed_q"][k], pe2, re2 = best
        out["success"][k], out["pos_error"][k], out["rot_error"][k] = ok, math.sqrt(pe2), math.sqrt(re2)
        out["iterations"][k], out["restarts"][k] = it, restarts
    return out


def _spd_solver(m: int):
    """``solve(A, b)`` for one m×m SPD system: eigenpy's LLT (~1.5 µs) when Pinocchio is loaded,
    else numpy (~10 µs)."""
    if "pinocchio" in sys.modules:
        try:
            from eigenpy import LLT

            llt = LLT(m)
            compute, llt_solve = llt.compute, llt.solve

            def solve(a, b):
                compute(a)
                return llt_solve(b)

            return solve
        except ImportError:  # pragma: no cover - eigenpy ships with pin
            pass
    return np.linalg.solve


def log3(m: np.ndarray) -> np.ndarray:
    """Rotation vector ``(3,)`` of one rotation matrix (angle in [0, π]); numpy, for FK without
    Pinocchio's ``log3``."""
    v = 0.5 * np.array([m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1]])
    s = math.sqrt(v.dot(v))
    c = 0.5 * (m[0, 0] + m[1, 1] + m[2, 2] - 1.0)
    if s < 1e-6 and c <= 0:  # near π: the axis from the full matrix
        from kinverify.model.transforms import rotation_log

        return rotation_log(m)
    angle = math.atan2(s, c)
    return v * (angle / s) if s > 1e-12 else v * (1.0 + angle * angle / 6.0)
