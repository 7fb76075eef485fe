"""Levenberg-Marquardt IK on any :class:`FrameModel`: joint limits, restarts from a seed table.

Pose error ``e = [p_t − p; log(R_t Rᵀ)]`` (base frame; position only: the first three rows);
its rotation part's norm is the geodesic angle, so the stop test ``‖e_p‖ ≤ tol_pos`` and
``‖e_r‖ ≤ tol_rot`` is exactly the one the suite and the benchmarks judge with.

- **Step**: damped least squares in the m×m form, ``dq = Jᵀ (J Jᵀ + λI)⁻¹ e`` with
  ``λ = mu·E + w_n``, ``E = ½ eᵀe`` (Sugihara's error-proportional damping with a small gain and
  floor: far from the target it damps, near it the steps become Gauss-Newton and converge
  quadratically). Every step is taken.
- **Limits**: a revolute joint that leaves its range moves by whole turns when that brings it
  back inside (the same pose; always possible when the range spans 2π), else it is clipped; once
  ``E < clamp_below``, clipped joints are held at the limit and the step is re-solved for the
  others (one active-set pass).
- **Restarts**: the first attempt starts at the caller's ``q0`` (``start="seeded"``: at whichever of
  ``q0`` and the target's best stored seed is nearer the target, two evaluations to decide) and
  gets ``first_attempt_iter`` iterations, later ones ``attempt_iter``; an attempt also ends when its error has not halved over
  ``stall_window`` iterations. Restarts start from the target's best candidates in a
  :class:`SeedTable` (tip poses near the target), then every other one from the best iterate plus
  noise (``perturb_sigma`` rad), then uniform random. A target gets at most ``max_evaluations``
  FK + Jacobian evaluations, ``max_restarts`` restarts and ``time_budget`` seconds.

Batched models (the analytic backend, a URDF chain) solve every target at once
(:mod:`kinverify.ik.batch`, time = batch time / targets); others one target at a time
(:mod:`kinverify.ik.single`, each with its own time).
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from kinverify.ik.frame_model import FrameModel

_STREAM = 0x1C  # separates IK starts from uniform_configurations(seed)


@dataclass(frozen=True)
class IKOptions:
    tol_pos: float = 1e-12  # m: solved when the position error is at most this...
    tol_rot: float = 1e-12  # rad: ...and the rotation error at most this (full-pose targets)
    max_restarts: int = 100  # attempts after the first
    max_evaluations: int = 2000  # FK + Jacobian evaluations per target, all attempts together
    time_budget: float = 1.0  # s per target (a batch gets time_budget × targets)
    seed: int = 0  # random restarts (and random first guesses) come from default_rng([seed, _STREAM])
    mu: float = 0.03  # damping λ = mu·E + w_n
    w_n: float = 1e-12  # a floor only: near the target the steps are Gauss-Newton, singular or not
    clamp_below: float = 0.1  # E below which joints pushed onto a limit are held there
    first_attempt_iter: int = 15
    attempt_iter: int = 20
    stall_window: int = 3  # an attempt ends when E(3k) > stall_ratio · E(3k − 2)
    stall_ratio: float = 0.5
    perturb_sigma: float = 0.1  # rad: noise on the best iterate for every other late restart...
    perturb_after: int = 6  # ...from this restart on
    seed_samples: int = 5_000  # configurations in the seed table (0: random restarts only)
    start: str = "given"  # first attempt: "given" from q0; "seeded" from the better of q0 and the best stored seed


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
    iterations: np.ndarray  # (B,) FK + Jacobian evaluations over all attempts
    restarts: np.ndarray  # (B,)
    time_s: np.ndarray  # (B,) per solve; in a batch, the batch time / B
    seed_q: np.ndarray  # (B, n): first configuration of the attempt that gave q
    batched: bool = False
    extra: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.q)

    def solved(self, tol_pos: float, tol_rot: float) -> np.ndarray:
        return (self.pos_error <= tol_pos) & (self.rot_error <= tol_rot)


def solve_lm(
    model: FrameModel,
    targets,
    lower,
    upper,
    position_only: bool = False,
    options: IKOptions | None = None,
    q0=None,
    batch: bool | None = None,
) -> IKSolutions:
    """Solve IK for ``targets`` ``(B, 4, 4)`` (position-only: only the translation is used).

    ``q0`` ``(B, n)``: first guesses (default uniform random inside the limits). ``batch``:
    solve all targets at once (default: when the model is batched). The seed table (built once
    per model, not timed) is reported in ``extra["seed_table_s"]``; process CPU seconds per target
    in ``extra["cpu_s"]`` (like ``time_s``, without the time other processes took).
    """
    opts = options or IKOptions()
    targets = np.asarray(targets, dtype=float).reshape(-1, 4, 4)
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    rng = np.random.default_rng([opts.seed, _STREAM])  # not the stream sampling.py draws targets from
    b = len(targets)
    lo_s, hi_s = np.where(np.isfinite(lower), lower, -np.pi), np.where(np.isfinite(upper), upper, np.pi)
    q0 = rng.uniform(lo_s, hi_s, (b, len(lower))) if q0 is None else np.asarray(q0, float).reshape(b, -1)
    if opts.start not in ("given", "seeded"):
        raise ValueError(f"IKOptions.start must be 'given' or 'seeded', got {opts.start!r}")
    batch = model.batched if batch is None else batch
    wanted = b and (opts.max_restarts or opts.start == "seeded")
    seeds, build_s = model.seed_table(lo_s, hi_s, position_only, opts.seed_samples) if wanted else (None, 0.0)
    wrap = np.asarray(model.revolute, bool)
    if batch:
        from kinverify.ik.batch import solve_chunks

        t0, c0 = time.perf_counter(), time.process_time()
        out = (
            solve_chunks(model.soa, targets, q0, lower, upper, wrap, position_only, opts, seeds, rng) if b else _empty(len(lower))
        )
        out["time_s"] = np.full(b, (time.perf_counter() - t0) / max(b, 1))
        out["cpu_s"] = np.full(b, (time.process_time() - c0) / max(b, 1))
    else:
        from kinverify.ik.single import solve_each

        fk, log3 = model.point()
        out = solve_each(fk, log3, targets, q0, lower, upper, wrap, position_only, opts, seeds, rng)
    extra = {"seed_table_s": build_s, "cpu_s": out.pop("cpu_s")}
    return IKSolutions("lm", model.name, model.frame, position_only, batched=batch, extra=extra, **out)


def _empty(n: int) -> dict:
    return {
        "q": np.empty((0, n)),
        "success": np.zeros(0, bool),
        "pos_error": np.empty(0),
        "rot_error": np.empty(0),
        "iterations": np.zeros(0, int),
        "restarts": np.zeros(0, int),
        "seed_q": np.empty((0, n)),
    }


def wrappable(lower, upper, model) -> np.ndarray:
    """Revolute joints whose range spans at least 2π: for any q inside, q ± 2π may be inside too."""
    revolute = np.asarray(getattr(model, "revolute", np.ones(len(lower), bool)))
    return revolute & (np.asarray(upper) - np.asarray(lower) >= 2 * np.pi)
