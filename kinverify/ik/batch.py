"""The batched IK solver: every target (and its restarts) advanced together, one numpy call per step.

Rows are attempts, each owned by a target; all per-row arrays keep the batch on the *last* axis
(structure of arrays), so each numpy call is one contiguous vector operation over the active rows
and no small batched matrix product is needed. One iteration: one FK + Jacobian of every active
row (``fk``), the pose errors, one batched ``m×m`` solve (m = 6, or 3 position-only) and the
bookkeeping (solved targets leave, stalled rows restart). When fewer than ``MIN_ROWS`` rows are
left, each unsolved target gets up to ``ROWS_PER_TARGET`` parallel restart rows: a small batch
costs about what one row does, and the first row of a target to converge wins.

The step, the limit handling and the restart policy are those of :mod:`kinverify.ik.lm` (see its
docstring); with one row per target and no parallel rows the iterates equal the per-target
solver's.
"""

from __future__ import annotations

import time

import numpy as np

from kinverify.model.transforms import rotation_log

# bytes one row holds per joint while it is solved: the Jacobian (6 × 8 bytes) and about seven
# arrays of its size (FK's joint axes and origins, the steps' products); measured, docs/robustness.md
ROW_BYTES_PER_JOINT = 400
ROW_BYTES = 1024  # and per row whatever the chain: the target, its rotation columns, the bookkeeping
CHUNK_BYTES = 192 * 2**20  # targets are solved in chunks of at most this working set
MIN_ROWS = 64  # below this many active rows, unsolved targets get parallel restart rows...
ROWS_PER_TARGET = 8  # ...up to this many rows each
LDL_ABOVE = 300  # systems: numpy's batched LAPACK solve below, a vectorised LDLᵀ above


def chunk_size(n_joints: int) -> int:
    """Targets solved together on a chain of ``n_joints``: as many as fit in ``CHUNK_BYTES`` (rows
    a chunk adds for restarts stay below ``MIN_ROWS × ROWS_PER_TARGET``, a few hundred)."""
    return max(MIN_ROWS, CHUNK_BYTES // (ROW_BYTES_PER_JOINT * max(n_joints, 1) + ROW_BYTES))


def solve_chunks(fk, targets, q0, lower, upper, wrap, position_only: bool, opts, seeds, rng) -> dict:
    """:func:`solve_rows` on consecutive chunks of :func:`chunk_size` targets, so memory does not
    grow with the number of targets; each chunk gets ``opts.time_budget`` per target of its own.
    One chunk (every run of up to about 7,500 targets on a 64-joint chain, 87,000 on 3 joints) is
    exactly :func:`solve_rows` on all targets."""
    size = chunk_size(q0.shape[1])
    parts = []
    for start in range(0, len(targets), size):
        part = slice(start, start + size)
        deadline = time.perf_counter() + opts.time_budget * len(targets[part])
        parts.append(solve_rows(fk, targets[part], q0[part], lower, upper, wrap, position_only, opts, seeds, rng, deadline))
    return {key: np.concatenate([p[key] for p in parts]) for key in parts[0]}


def solve_rows(fk, targets, q0, lower, upper, wrap, position_only: bool, opts, seeds, rng, deadline: float) -> dict:
    """Solve ``targets`` ``(N, 4, 4)`` from ``q0`` ``(N, n)``.

    ``fk(qT (n, m)) -> (S (3, 3, m), p (3, m), J (6, n, m))``: tip rotation columns, position [m]
    and world-aligned Jacobian of m configurations (see :meth:`SerialChain.fk_jac_soa`).
    ``wrap`` ``(n,)``: joints a whole turn may shift (revolute). ``opts``: :class:`IKOptions`;
    ``seeds``: a :class:`SeedTable` or None (random restarts); ``deadline``: perf_counter time.
    Returns the per-target arrays of :class:`IKSolutions` (without ``time_s``).
    """
    n_t, n = q0.shape
    limits = _Limits(lower, upper, wrap)
    rows_e = 3 if position_only else 6
    tp2, tr2 = opts.tol_pos**2, opts.tol_rot**2
    q_out, seed_out = q0.copy(), q0.copy()
    succ, open_ = np.zeros(n_t, bool), np.ones(n_t, bool)
    pe_out, re_out, best_e = np.full(n_t, np.inf), np.full(n_t, np.inf), np.full(n_t, np.inf)
    it_out, att_out = np.zeros(n_t, int), np.ones(n_t, int)
    pt_all = np.ascontiguousarray(targets[:, :3, 3].T)
    rts_all = np.ascontiguousarray(targets[:, :3, :3].transpose(2, 1, 0))  # [k, i, t] = R_t[i, k]
    b1_all, b2_all = np.ascontiguousarray(rts_all[:, [2, 0, 1]]), np.ascontiguousarray(rts_all[:, [1, 2, 0]])

    def new_points(tg, rank):
        """Restart configurations ``(n, len(tg))``: seed-table candidates by rank, every other
        restart from ``perturb_after`` on the best iterate plus noise, then uniform random."""
        out = rng.uniform(limits.lo_s, limits.hi_s, (len(tg), n))
        pert = (rank >= opts.perturb_after) & (rank % 2 == 1) if opts.perturb_sigma > 0 else np.zeros(len(tg), bool)
        if seeds is not None:
            use = (rank + skip[tg] < seeds.k) & ~pert
            if use.any():
                out[use] = seeds.query(targets[tg[use]], rank[use] + skip[tg[use]])
        if pert.any():
            noisy = q_out[tg[pert]] + opts.perturb_sigma * rng.standard_normal((int(pert.sum()), n))
            out[pert] = limits.wrapclip(noisy.T)[0].T
        return out.T

    own = np.arange(n_t)
    qT = limits.wrapclip(np.ascontiguousarray(q0.T))[0]
    skip = np.zeros(n_t, int)  # 1 where the first attempt started from the best seed: restarts take the next ones
    if opts.start == "seeded" and seeds is not None:  # start from the best seed where it is nearer than q0
        both = np.concatenate([qT, np.ascontiguousarray(seeds.query(targets, 0).T)], axis=1)
        s, p, _ = fk(both)
        ep = np.concatenate([pt_all, pt_all], axis=1) - p
        energy = (ep * ep).sum(0)
        if not position_only:
            two = [np.concatenate([x, x], axis=-1) for x in (rts_all, b1_all, b2_all)]
            energy += (_rotation_error(s, *two) ** 2).sum(0)
        skip = (energy[n_t:] < energy[:n_t]).astype(int)
        qT = np.where(skip.astype(bool), both[:, n_t:], qT)
        it_out += 2
    row = _Rows(
        own=own,
        q=qT,
        seed=qT.copy(),
        cap=np.full(n_t, opts.first_attempt_iter),
        it=np.zeros(n_t, int),
        ewin=np.full(n_t, np.inf),
        pt=pt_all,
        rts=rts_all,
        b1=b1_all,
        b2=b2_all,
    )
    while row.own.size:
        s, p, jac = fk(row.q)
        ep = row.pt - p
        pe2 = (ep * ep).sum(0)
        if position_only:
            err, re2 = ep, np.zeros_like(pe2)
        else:
            w = _rotation_error(s, row.rts, row.b1, row.b2)
            err, re2 = np.concatenate([ep, w]), (w * w).sum(0)
        energy = 0.5 * (pe2 + re2)
        np.add.at(it_out, row.own, 1)
        row.it += 1
        better = energy < best_e[row.own]
        if better.any():  # best iterate per target (what an unsolved target reports)
            b = np.flatnonzero(better)
            np.minimum.at(best_e, row.own[b], energy[b])
            win = b[energy[b] == best_e[row.own[b]]]
            t = row.own[win]
            q_out[t], seed_out[t] = row.q[:, win].T, row.seed[:, win].T
            pe_out[t], re_out[t] = np.sqrt(pe2[win]), np.sqrt(re2[win])
        done = np.flatnonzero((pe2 <= tp2) & (re2 <= tr2))
        if len(done):
            t = row.own[done]
            q_out[t], seed_out[t] = row.q[:, done].T, row.seed[:, done].T
            pe_out[t], re_out[t] = np.sqrt(pe2[done]), np.sqrt(re2[done])
            succ[t], open_[t] = True, False
        open_ &= it_out < opts.max_evaluations
        if time.perf_counter() > deadline:
            break
        keep = open_[row.own]
        if not keep.all():
            row.take(keep)
            err, jac, energy = err[:, keep], jac[..., keep], energy[keep]
            if not row.own.size:
                break
        # an attempt ends at its cap, or when its error has not halved over a stall window
        start = row.it % opts.stall_window == 1
        row.ewin = np.where(start, energy, row.ewin)
        restart = (row.it >= row.cap) | ((row.it % opts.stall_window == 0) & (energy > opts.stall_ratio * row.ewin))
        row.q = _step(row.q, err, jac[:rows_e], opts.mu * energy + opts.w_n, energy < opts.clamp_below, limits)
        if restart.any():
            r = np.flatnonzero(restart)
            tg = row.own[r]
            turn = _cumcount(tg)
            allowed = turn < opts.max_restarts - (att_out[tg] - 1)
            go, tg_go = r[allowed], tg[allowed]
            if len(go):
                row.q[:, go] = row.seed[:, go] = new_points(tg_go, att_out[tg_go] - 1 + _cumcount(tg_go))
                np.add.at(att_out, tg_go, 1)
                row.cap[go], row.it[go], row.ewin[go] = opts.attempt_iter, 0, np.inf
            if not allowed.all():  # out of restarts: the row ends; a target with no row left ends
                row.take(~np.isin(np.arange(row.own.size), r[~allowed]))
                open_ &= np.isin(np.arange(n_t), row.own)
        if row.own.size < MIN_ROWS and opts.max_restarts > 0:
            tgt = np.flatnonzero(open_)
            if len(tgt):
                per = min(ROWS_PER_TARGET, -(-MIN_ROWS // len(tgt)))
                add = np.minimum(
                    np.maximum(per - np.bincount(row.own, minlength=n_t)[tgt], 0), opts.max_restarts - (att_out[tgt] - 1)
                )
                if add.sum() > 0:
                    new = np.repeat(tgt, add)
                    q_new = new_points(new, att_out[new] - 1 + _cumcount(new))
                    att_out[tgt] += add
                    row.extend(new, q_new, opts, pt_all, rts_all, b1_all, b2_all)
    return {
        "q": q_out,
        "success": succ,
        "pos_error": pe_out,
        "rot_error": re_out,
        "iterations": it_out,
        "restarts": att_out - 1,
        "seed_q": seed_out,
    }


class _Limits:
    """Joint limits in column form and the projection onto them."""

    def __init__(self, lower, upper, wrap) -> None:
        self.lo, self.hi = lower[:, None], upper[:, None]
        self.lo_s = np.where(np.isfinite(lower), lower, -np.pi)  # sampling bounds of restarts
        self.hi_s = np.where(np.isfinite(upper), upper, np.pi)
        self.mid = (0.5 * (self.lo_s + self.hi_s))[:, None]
        self.wrap = np.asarray(wrap, bool)[:, None]
        # a whole turn can only bring a joint back inside when it overshoots by 2π − range or more
        margin = np.where(wrap, 2 * np.pi - (upper - lower), np.inf)
        self.min_margin = float(np.min(np.maximum(margin, 0.0), initial=np.inf))

    def wrapclip(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``x`` ``(n, m)`` onto the limits: a revolute joint outside moves by whole turns towards
        the middle of its range when that lands inside (same pose), else it is clipped.
        Returns ``(q, d)``; ``d`` ≠ 0 marks the clipped joints (by how much)."""
        y = np.minimum(np.maximum(x, self.lo), self.hi)
        d = x - y
        if self.min_margin < np.inf and np.abs(d).max(initial=0.0) >= self.min_margin:
            w = x - np.round((x - self.mid) / (2 * np.pi)) * (2 * np.pi)
            ok = (d != 0) & self.wrap & (w >= self.lo) & (w <= self.hi)
            y, d = np.where(ok, w, y), np.where(ok, 0.0, d)
        return y, d


def _step(q, err, jac, lam, clamp, limits: _Limits) -> np.ndarray:
    """Damped least squares ``dq = Jᵀ (J Jᵀ + λI)⁻¹ e`` on the limits; near the target (``clamp``)
    joints the step pushes onto a limit stay there and the step is re-solved for the others with
    the residual ``e − J dq_clamped`` (one active-set pass)."""
    y = spd_solve(_gram(jac, lam), err)
    qn, d = limits.wrapclip(q + (jac * y[:, None, :]).sum(0))
    rows = np.flatnonzero((d != 0).any(0) & clamp)
    if len(rows):
        held = d[:, rows] != 0
        jr = jac[..., rows]
        dq_held = np.where(held, qn[:, rows] - q[:, rows], 0.0)
        res = err[:, rows] - (jr * dq_held[None]).sum(1)
        jm = jr * ~held[None]
        y2 = spd_solve(_gram(jm, lam[rows]), res)
        qn[:, rows] = limits.wrapclip(q[:, rows] + (jm * y2[:, None, :]).sum(0) + dq_held)[0]
    return qn


def _gram(jac, lam) -> np.ndarray:
    a = np.einsum("akm,bkm->abm", jac, jac)
    a[range(len(a)), range(len(a))] += lam
    return a


def spd_solve(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Solve ``a x = b`` for many small SPD systems, batch last: ``a`` ``(k, k, m)``, ``b`` ``(k, m)``.
    Numpy's batched LAPACK below ``LDL_ABOVE`` systems; above, an LDLᵀ in O(k²) vectorised steps
    (numpy's batched solve costs ~1 µs per system)."""
    k, _, m = a.shape
    if m < LDL_ABOVE:
        return np.linalg.solve(np.ascontiguousarray(a.transpose(2, 0, 1)), b.T[:, :, None])[:, :, 0].T
    low, dia = np.zeros_like(a), np.empty((k, m))
    for j in range(k):
        ld = low[j, :j] * dia[:j]
        dia[j] = a[j, j] - (ld * low[j, :j]).sum(0)
        if j < k - 1:
            low[j + 1 :, j] = (a[j + 1 :, j] - (low[j + 1 :, :j] * ld[None]).sum(1)) / dia[j]
    x = b.copy()
    for j in range(1, k):
        x[j] -= (low[j, :j] * x[:j]).sum(0)
    x /= dia
    for j in range(k - 2, -1, -1):
        x[j] -= (low[j + 1 :, j] * x[j + 1 :]).sum(0)
    return x


def _rotation_error(s, rts, b1, b2) -> np.ndarray:
    """``log(R_t Rᵀ)`` ``(3, m)`` in the base frame from rotation columns ``s`` and the target's
    ``rts`` (and its two column permutations ``b1``, ``b2``, for the cross products)."""
    v = 0.5 * (s[:, [1, 2, 0]] * b1 - s[:, [2, 0, 1]] * b2).sum(0)  # sin θ · axis
    sin = np.sqrt((v * v).sum(0))
    cos = 0.5 * ((rts * s).sum((0, 1)) - 1.0)
    theta = np.arctan2(sin, cos)
    small = sin < 1e-6
    w = v * np.where(small & (cos > 0), 1.0 + theta * theta / 6.0, theta / np.where(sin > 0, sin, 1.0))
    near_pi = np.flatnonzero(small & (cos <= 0))
    if len(near_pi):  # rare: the axis from the full matrix
        w[:, near_pi] = rotation_log(np.einsum("kit,kjt->tij", rts[..., near_pi], s[..., near_pi])).T
    return w


def _cumcount(ids: np.ndarray) -> np.ndarray:
    """For each entry, how many equal ids come before it."""
    order = np.argsort(ids, kind="stable")
    sorted_ids = ids[order]
    first = np.r_[0, np.flatnonzero(sorted_ids[1:] != sorted_ids[:-1]) + 1]
    counts = np.diff(np.r_[first, len(ids)])
    out = np.empty(len(ids), int)
    out[order] = np.arange(len(ids)) - np.repeat(first, counts)
    return out


class _Rows:
    """Per-row state: owner target, q and attempt start ``(n, m)``, attempt cap,
    iterations in the attempt, error at the stall window's start, and the owner's target data."""

    COLUMNS = ("own", "cap", "it", "ewin")
    BATCH_LAST = ("q", "seed", "pt", "rts", "b1", "b2")
    own: np.ndarray  # the arrays above, set by __init__ and take/extend
    cap: np.ndarray
    it: np.ndarray
    ewin: np.ndarray
    q: np.ndarray
    seed: np.ndarray
    pt: np.ndarray
    rts: np.ndarray
    b1: np.ndarray
    b2: np.ndarray

    def __init__(self, **arrays) -> None:
        self.__dict__.update(arrays)

    def take(self, keep) -> None:
        for name in self.COLUMNS:
            setattr(self, name, getattr(self, name)[keep])
        for name in self.BATCH_LAST:
            setattr(self, name, getattr(self, name)[..., keep])

    def extend(self, own, q, opts, pt, rts, b1, b2) -> None:
        a = len(own)
        extra = {
            "own": own,
            "cap": np.full(a, opts.attempt_iter),
            "it": np.zeros(a, int),
            "ewin": np.full(a, np.inf),
            "q": q,
            "seed": q.copy(),
            "pt": pt[:, own],
            "rts": rts[..., own],
            "b1": b1[..., own],
            "b2": b2[..., own],
        }
        for name, value in extra.items():
            setattr(self, name, np.concatenate([getattr(self, name), value], axis=-1))
