"""Batch IK files for ``kinverify ik --targets``: reading targets and initial guesses (``.npy``)
and the URDF text, and the JSON of the results.

Targets: ``(N, 4, 4)`` homogeneous poses of the tip in the base frame [m] (a single ``(4, 4)`` is
one target). Initial guesses: ``(N, n)`` joint values [rad | m] in chain order (a single ``(n,)``
is used for every target). Anything else is an :class:`InputError` naming the file and what is
wrong: a wrong shape, a non-finite value, a rotation block that is not a rotation, a last row that
is not ``0 0 0 1``.
"""

from __future__ import annotations

import io
import json

import numpy as np

from kinverify.errors import InputError
from kinverify.pipeline.limits import MAX_DATA_BYTES, MAX_IK_TARGETS, MAX_TARGET_M

ROTATION_TOL = 1e-6  # ‖RᵀR − I‖ and |det R − 1| allowed in a target's rotation block


def read_text(path: str, flag: str) -> str:
    """A text file's content (:mod:`kinverify.io.read`: a regular file within the model size
    limit), or an :class:`InputError` naming the flag and the file."""
    from kinverify.io.read import read_text as read

    return read(path, flag)


def _load(path: str, flag: str) -> np.ndarray:
    from kinverify.io.formats import npy_load
    from kinverify.io.read import read_bytes

    data = npy_load(read_bytes(path, flag, MAX_DATA_BYTES), path, flag)
    if not np.issubdtype(data.dtype, np.number) or np.iscomplexobj(data):
        raise InputError(f"{flag}: {path} must hold a real-valued array (an .npz archive or object array is not one)")
    return data.astype(float)


def load_targets(path: str, flag: str = "--targets") -> np.ndarray:
    """``(N, 4, 4)`` validated poses."""
    t = _load(path, flag)
    if t.shape == (4, 4):
        t = t[None]
    if t.ndim != 3 or t.shape[1:] != (4, 4) or len(t) == 0:
        raise InputError(f"{flag}: {path} has shape {t.shape}; expected (N, 4, 4) homogeneous poses of the tip in the base frame")
    if len(t) > MAX_IK_TARGETS:
        raise InputError(
            f"{flag}: {path} holds {len(t):,} targets, above the {MAX_IK_TARGETS:,} kinverify solves in one run "
            "(see docs/robustness.md)"
        )
    bad = ~np.isfinite(t).all(axis=(1, 2))
    if bad.any():
        raise InputError(f"{flag}: {path}: target {int(np.argmax(bad))} has a non-finite value (NaN or inf)")
    far = np.abs(t[:, :3, 3]).max(axis=1) > MAX_TARGET_M
    if far.any():
        raise InputError(
            f"{flag}: {path}: target {int(np.argmax(far))} is more than {MAX_TARGET_M:g} m from the base (see docs/robustness.md)"
        )
    last = np.abs(t[:, 3] - [0.0, 0.0, 0.0, 1.0]).max(axis=1) > 0
    if last.any():
        raise InputError(
            f"{flag}: {path}: target {int(np.argmax(last))}'s last row is {t[np.argmax(last), 3].tolist()}, not [0, 0, 0, 1]"
        )
    rot = t[:, :3, :3]
    ortho = np.abs(np.swapaxes(rot, 1, 2) @ rot - np.eye(3)).max(axis=(1, 2))
    det = np.linalg.det(rot)
    wrong = (ortho > ROTATION_TOL) | (np.abs(det - 1.0) > ROTATION_TOL)
    if wrong.any():
        k = int(np.argmax(wrong))
        raise InputError(
            f"{flag}: {path}: target {k}'s rotation block is not a rotation (|RᵀR − I| = {ortho[k]:.1e}, det = {det[k]:.6g})"
        )
    return t


def load_initial(path: str, n_targets: int, n_joints: int, flag: str = "--initial") -> np.ndarray:
    """``(N, n)`` validated initial guesses."""
    q = _load(path, flag)
    if q.shape == (n_joints,):
        q = np.tile(q, (n_targets, 1))
    if q.shape != (n_targets, n_joints):
        raise InputError(
            f"{flag}: {path} has shape {q.shape}; expected ({n_targets}, {n_joints}): one initial guess "
            f"per target, one value per chain joint"
        )
    bad = ~np.isfinite(q).all(axis=1)
    if bad.any():
        raise InputError(f"{flag}: {path}: initial guess {int(np.argmax(bad))} has a non-finite value (NaN or inf)")
    return q


def results_json(sol, joints, lower, upper, tol_pos: float, tol_rot: float, **header) -> dict:
    """The JSON of a batch: ``success_rate`` (fraction solved within the tolerance), ``median_ms``
    and ``p99_ms`` (solve time per target: start-up and setup excluded; batched: batch time / N)
    at the top level, then one record per target (``results``: a list made by :func:`records`
    when the dict is read as a whole; :func:`json_bytes` writes them one by one)."""
    ok = sol.solved(tol_pos, tol_rot)
    ms = np.asarray(sol.time_s, float) * 1e3
    return {
        **header,
        "success_rate": float(ok.mean()) if len(ok) else 0.0,
        "median_ms": float(np.median(ms)) if len(ms) else 0.0,
        "p99_ms": float(np.percentile(ms, 99)) if len(ms) else 0.0,
        "solved": int(ok.sum()),
        "targets": len(ok),
        "tolerance": {"position_m": tol_pos, "rotation_rad": tol_rot},
        "position_only": bool(sol.position_only),
        "batched": bool(sol.batched),
        "total_solve_s": float(ms.sum() / 1e3),
        "setup_s": {"seed_table": float(sol.extra.get("seed_table_s", 0.0))},
        "joints": list(joints),
        "lower": [_finite(x) for x in lower],
        "upper": [_finite(x) for x in upper],
        "results": Records(sol, ok, ms),
    }


class Records:
    """The per-target records of a batch, made when iterated (100,000 targets on 64 joints as
    Python objects took about 1 GB)."""

    def __init__(self, sol, ok, ms) -> None:
        self.sol, self.ok, self.ms = sol, ok, ms

    def __len__(self) -> int:
        return len(self.ok)

    def __iter__(self):
        sol = self.sol
        for k in range(len(self.ok)):
            yield {
                "index": k,
                "success": bool(self.ok[k]),
                "q": [float(x) for x in sol.q[k]],
                "position_error_m": float(sol.pos_error[k]),
                "rotation_error_rad": float(sol.rot_error[k]),
                "iterations": int(sol.iterations[k]),
                "restarts": int(sol.restarts[k]),
                "time_ms": float(self.ms[k]),
            }


def json_bytes(data: dict) -> bytes:
    """``data`` (from :func:`results_json`) as UTF-8 JSON: the header indented, one line per target
    record, written one record at a time."""
    head = json.dumps({k: v for k, v in data.items() if k != "results"}, indent=1)
    out = io.BytesIO()
    out.write(head[:-2].encode())  # without the closing "\n}"
    out.write(b',\n "results": [')
    for k, record in enumerate(data["results"]):
        out.write((",\n  " if k else "\n  ").encode() + json.dumps(record).encode())
    out.write(b"\n ]\n}\n")
    return out.getvalue()


def _finite(x) -> float | None:
    """JSON has no infinity: an unlimited (continuous) joint's bound is null."""
    return float(x) if np.isfinite(x) else None
