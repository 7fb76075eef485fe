"""Restart seeds for IK: stored configurations whose tip pose is near the target's.

A :class:`SeedTable` holds ``samples`` uniform random configurations inside the limits, the
limits' corners (every joint on a limit: all 2ⁿ of them up to ``MAX_CORNERS``, that many random
ones beyond) and their tip poses, bucketed in a voxel grid (``cell`` m) over the tip positions:
every cell keeps the ``pool`` samples whose tip lies closest to the cell's centre, ``pool`` being
what the fullest cell holds (at least ``k``; at most ``MAX_TABLE`` entries in all). A target's
candidates are those of its cell, ranked by ``|p_c − p_t|² + w²·‖R_c − R_t‖²_F``; the r-th restart
of a target starts from its r-th best candidate (r < ``k``). From the best seed most Panda targets
converge in under 8 iterations, against ~25 % from a random configuration.

The corners are there because no uniform sample comes near one in 6 or 7 dimensions, while a
target made with every joint on a limit is often an isolated solution at a singular Jacobian that
local steps reach only from close by (random 6-7 joint arms, targets drawn as the property tests
draw them: 5 of 1,800 unsolved in 2,000 evaluations without the corners, none with them). The
pool is what keeps the orientations: where the tip hardly moves (a wrist, an arm whose joint
axes all meet at one point) every sample falls in one or a few cells, and keeping only ``k`` of
them by position would rank ``k`` arbitrary orientations (on a 7-joint arm with all axes through
one point, the best of 32 was 1.2 rad from a target, the best of all 5,000 0.4 rad).
"""

from __future__ import annotations

import numpy as np

MAX_RADIUS = 2  # cells: how far the search for a cell's candidates grows
MAX_CELLS = 20_000  # grid cells at most (memory, build time)
MAX_TABLE = 1_000_000  # cell × candidate entries at most (8 MB)
MAX_CORNERS = 1024  # corners of the limits stored at most (all of them up to 10 joints)


class SeedTable:
    """``fk_soa(qT (n, N)) -> (S (3, 3, N), p (3, N), ...)`` (e.g. :meth:`SerialChain.fk_jac_soa`
    with ``jacobian=False``); ``lower``/``upper`` ``(n,)`` finite sampling bounds [rad | m]; ``k``
    restart candidates per target. The grid has at most ``MAX_CELLS`` cells (``cell`` grows for
    long arms); memory: samples × (13 + n) floats + cells × ``pool`` indices (~3 MB for the Panda
    with the defaults: no cell holds more than ``k`` samples there, so ``pool`` = ``k``)."""

    def __init__(
        self, fk_soa, lower, upper, samples: int = 5_000, cell: float = 0.1, k: int = 32, w_rot: float = 0.2, seed: int = 1
    ) -> None:
        lower, upper = np.asarray(lower, float), np.asarray(upper, float)
        rng = np.random.default_rng(seed)
        qs = np.concatenate([rng.uniform(lower, upper, (samples, len(lower))), corners(lower, upper, rng)])
        samples = len(qs)
        rot9_parts: list[np.ndarray] = []
        pos_parts: list[np.ndarray] = []
        for a in range(0, samples, 4096):
            s, p = fk_soa(np.ascontiguousarray(qs[a : a + 4096].T))[:2]
            rot9_parts.append(s.transpose(2, 1, 0).reshape(-1, 9))  # row-major R per sample
            pos_parts.append(p.T)
        rot9, pos = np.concatenate(rot9_parts), np.concatenate(pos_parts)
        extent = pos.max(0) - pos.min(0) + cell
        cell = max(float(cell), float(np.prod(extent) / MAX_CELLS) ** (1 / 3))
        self.cell, self.k, self.w = cell, int(k), float(w_rot)
        self.origin = pos.min(0) - 0.5 * cell
        self.dims = np.floor((pos.max(0) + 0.5 * cell - self.origin) / cell).astype(int) + 1
        self._o, self._d = [float(x) for x in self.origin], [int(x) for x in self.dims]
        n_cells = int(np.prod(self.dims))
        fullest = int(np.bincount(self.cells(pos), minlength=n_cells).max())
        self.pool = max(self.k, min(fullest, MAX_TABLE // n_cells))
        self.table, distinct = self._nearest_per_cell(pos)  # (cells, pool) sample indices
        self.width = np.maximum(distinct, self.k)  # entries a query ranks per cell (repeats only below k)
        w2 = self.w**2
        # feature · [R_t | p_t] (the top 3×4 block of a target, row-major) = w² R_c:R_t + p_c·p_t
        self.features = np.concatenate([w2 * rot9.reshape(-1, 3, 3), pos[:, :, None]], axis=2).reshape(-1, 12)
        self.norms = np.einsum("ij,ij->i", pos, pos) + w2 * np.einsum("ij,ij->i", rot9, rot9)
        self.q = qs  # (samples, n)

    def _nearest_per_cell(self, pos: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(cells, pool)`` sample indices and ``(cells,)`` how many are distinct: per cell the
        ``pool`` samples nearest its centre among those in the cube of cells around it, the cube
        growing (for the cells still short) up to ``MAX_RADIUS``; a cell with fewer repeats them,
        an empty one takes a nearby cell's."""
        dims = self.dims
        n_cells = int(np.prod(dims))
        cid = np.clip(((pos - self.origin) / self.cell).astype(int), 0, dims - 1)
        table = np.full((n_cells, self.pool), -1, np.int64)
        count = np.zeros(n_cells, int)
        short = np.ones(n_cells, bool)
        for r in range(1, MAX_RADIUS + 1):
            offsets = np.stack(np.meshgrid(*[np.arange(-r, r + 1)] * 3, indexing="ij"), -1).reshape(-1, 3)
            cells = cid[None] + offsets[:, None]  # (offsets, samples, 3): the cells each sample is near
            inside = np.all((cells >= 0) & (cells < dims), axis=-1)
            flat = np.where(inside, (cells[..., 0] * dims[1] + cells[..., 1]) * dims[2] + cells[..., 2], 0)
            pick = inside & short[flat]
            cell_of, sample = flat[pick], np.broadcast_to(np.arange(len(pos)), flat.shape)[pick]
            centre = self.origin + (np.stack(np.unravel_index(cell_of, dims), -1) + 0.5) * self.cell
            dist = np.einsum("ij,ij->i", pos[sample] - centre, pos[sample] - centre)
            order = np.lexsort((dist, cell_of))
            cell_of, sample = cell_of[order], sample[order]
            first = np.searchsorted(cell_of, cell_of, side="left")
            rank = np.arange(len(cell_of)) - first
            keep = rank < self.pool
            table[cell_of[keep], rank[keep]] = sample[keep]
            count[short] = np.bincount(cell_of, minlength=n_cells)[short].clip(max=self.pool)
            short = count < self.pool
            if not short.any():
                break
        some = np.flatnonzero(short & (count > 0))  # a short cell cycles what it has
        table[some] = np.take_along_axis(table[some], np.arange(self.pool)[None] % count[some, None], axis=1)
        # an empty cell (outside the reach, or in a sparse corner) takes its nearest filled cell's
        source = np.where(count > 0, np.arange(n_cells), -1).reshape(tuple(dims))
        while (source < 0).any() and (source >= 0).any():
            for axis in range(3):
                for step in (1, -1):
                    moved = np.roll(source, step, axis=axis)
                    edge: list[slice | int] = [slice(None)] * 3
                    edge[axis] = 0 if step == 1 else -1
                    moved[tuple(edge)] = -1  # no wrap-around
                    source = np.where(source < 0, moved, source)
        empty = count == 0
        table[empty] = table[source.reshape(-1)[empty]]
        count[empty] = count[source.reshape(-1)[empty]]
        return table, count

    def cells(self, positions: np.ndarray) -> np.ndarray:
        """Flat cell index of positions ``(..., 3)`` (clipped into the grid)."""
        c = np.clip(((positions - self.origin) / self.cell).astype(int), 0, self.dims - 1)
        return (c[..., 0] * self._d[1] + c[..., 1]) * self._d[2] + c[..., 2]

    def query(self, targets: np.ndarray, rank) -> np.ndarray:
        """Seeds ``(m, n)``: for each target ``(m, 4, 4)`` its ``rank``-th best candidate (``rank``
        an int or ``(m,)``; ranks beyond ``k`` give the last)."""
        m = len(targets)
        r = np.minimum(np.broadcast_to(rank, (m,)), self.k - 1)
        out = np.empty((m, self.q.shape[1]))
        step = max(1, (1 << 18) // self.pool)  # targets per chunk: (chunk, pool, 12) stays small
        for a in range(0, m, step):
            t = targets[a : a + step]
            cell = self.cells(t[:, :3, 3])
            idx = self.table[cell]  # (chunk, pool)
            d = self.norms[idx] - 2.0 * np.einsum("mkj,mj->mk", self.features[idx], t[:, :3, :].reshape(len(t), 12))
            rows = np.arange(len(t))
            if self.pool > self.k:  # the k best of the distinct entries, then their order
                d[np.arange(self.pool)[None] >= self.width[cell][:, None]] = np.inf
                top = np.argpartition(d, self.k - 1, axis=1)[:, : self.k]
                idx, d = np.take_along_axis(idx, top, 1), np.take_along_axis(d, top, 1)
            out[a : a + step] = self.q[idx[rows, np.argsort(d, axis=1)[rows, r[a : a + step]]]]
        return out

    def ranked(self, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """One target ``(4, 4)`` -> (candidates ``(k, n)``, their order best first): the per-target
        solvers' lean query (scalar cell index, one ``(pool, 12) @ (12,)`` product)."""
        o, d, cell = self._o, self._d, self.cell
        ix = min(max(int((target[0, 3] - o[0]) / cell), 0), d[0] - 1)
        iy = min(max(int((target[1, 3] - o[1]) / cell), 0), d[1] - 1)
        iz = min(max(int((target[2, 3] - o[2]) / cell), 0), d[2] - 1)
        c = (ix * d[1] + iy) * d[2] + iz
        idx = self.table[c, : self.width[c]]
        dist = self.norms[idx] - 2.0 * self.features[idx].dot(target[:3].reshape(12))
        if len(idx) > self.k:
            top = np.argpartition(dist, self.k - 1)[: self.k]
            idx, dist = idx[top], dist[top]
        return self.q[idx], dist.argsort()


def corners(lower, upper, rng) -> np.ndarray:
    """Configurations with every joint on a limit: all ``2ⁿ`` up to ``MAX_CORNERS``, else that many
    drawn at random."""
    n = len(lower)
    if 2**n <= MAX_CORNERS:
        on_upper = (np.arange(2**n)[:, None] >> np.arange(n)[None]) & 1
    else:
        on_upper = rng.integers(0, 2, (MAX_CORNERS, n))
    return np.where(on_upper == 1, upper, lower)
