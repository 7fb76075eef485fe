"""The documented limits of a run (docs/robustness.md): above them kinverify refuses with one
line (exit 2) instead of running away with memory or time.

- ``MAX_SAMPLES``: ``verify --samples``. Memory does not grow with it (configurations are
  generated chunk by chunk, statistics are streamed), so the limit is about time: a default
  run compares a few thousand configurations per second, so 10⁹ is days; larger values are typos.
- ``MAX_STORED_SAMPLES``: ``baseline save --samples`` and ``diff --samples``, which keep every
  configuration's values (a baseline stores them all in its file).
- ``MAX_CHUNK``: ``--chunk``, the configurations one worker holds at a time. A chunk's memory
  also grows with the model (frames × joints per configuration): :func:`chunk_for` lowers the
  chunk, with a note, so one chunk's arrays stay below ``CHUNK_BYTES``.
- ``MAX_SEED``: seeds are numpy ``default_rng`` seeds, whole numbers in ``[0, 2**64)``.
- ``MAX_TRACK_SECONDS``: ``track --duration`` and ``--hold`` (simulated time, at MuJoCo's 1 ms
  step every second is a thousand steps per controller).
- ``--jobs`` is capped (with a note) at the cores this process may run on.
- ``MAX_MODEL_BYTES``, ``MAX_LINKS``, ``MAX_JOINTS``: a URDF or MJCF read by file mode or
  ``diff``, and a spec (joints). Parsing is linear in the file size, but what a run computes
  per configuration grows with the square of the number of frames and joints (a Jacobian per
  frame) and, for yourdfpy, faster still with the chain's depth: a 200-link chain needed 7.5 GB
  and six minutes. Real arms have 6-7 joints, a quadruped 12 (largest test file: 31 links, 25 kB).
  ``MAX_MODEL_BYTES`` bounds every text input (spec, URDF, MJCF with everything it ``<include>``s,
  xacro sources, accepted-differences files); ``MAX_DATA_BYTES`` the data inputs (results JSON,
  baselines, ``.npy`` arrays: a panda baseline at ``MAX_STORED_SAMPLES`` is about 120 MB). Both
  are measured by reading (:mod:`kinverify.io.read`), never by ``stat`` alone: ``/dev/zero`` or a
  FIFO reports 0 bytes.
- ``MAX_XML_DEPTH``, ``MAX_JSON_DEPTH``: element (value) nesting of an XML (JSON, TOML) input. A
  serial MJCF chain of ``MAX_LINKS`` bodies nests about 260 deep; kinverify's own JSON about 8.
- ``MAX_INCLUDE_DEPTH``: ``<include>`` inside included files.
- ``MAX_IK_TARGETS``: ``kinverify ik --targets`` (the solver holds about 4 kB per target).
- ``MAX_TARGET_M``: an IK target's distance from the base (a 1 km arm is already a typo).
- ``SCHEDULER_TIMEOUT_S``: connecting to a Dask scheduler (``--scheduler``).
"""

from __future__ import annotations

import os

from kinverify.errors import InputError

MAX_SAMPLES = 1_000_000_000
MAX_STORED_SAMPLES = 10_000
MAX_CHUNK = 100_000
CHUNK_BYTES = 256 * 2**20
MAX_SEED = 2**64 - 1
MAX_TRACK_SECONDS = 600.0
MAX_MODEL_BYTES = 8 * 2**20
MAX_LINKS = 256  # URDF links, MJCF bodies
MAX_JOINTS = 64  # movable (1-DOF) joints
MAX_DATA_BYTES = 256 * 2**20
MAX_XML_DEPTH = 300
MAX_JSON_DEPTH = 64
MAX_INCLUDE_DEPTH = 8
MAX_IK_TARGETS = 100_000
MAX_TARGET_M = 1e6
SCHEDULER_TIMEOUT_S = 5.0


def available_cores() -> int:
    """Cores this process may run on (its CPU affinity where the OS tells, else the CPU count)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def cap_jobs(jobs: int) -> tuple[int, str | None]:
    """``jobs`` capped at :func:`available_cores`, and the note saying so (None when not capped)."""
    cores = available_cores()
    if jobs <= cores:
        return jobs, None
    return cores, f"--jobs {jobs} capped at {cores}: the number of cores available to this process"


def check_count(value, flag: str, maximum: int, minimum: int = 0) -> int:
    """``value`` as a whole number in ``[minimum, maximum]``, else a one-line :class:`InputError`."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(f"{flag} must be a whole number, got {value!r}")
    if value < minimum:
        raise InputError(f"{flag} must be >= {minimum}, got {value}")
    if value > maximum:
        raise InputError(f"{flag} {value} is above the maximum {maximum:,} (see docs/robustness.md)")
    return value


def check_seed(seed, flag: str = "--seed") -> int:
    return check_count(seed, flag, MAX_SEED)


def chunk_bytes_per_row(frames: int, dof: int, backends: int) -> int:
    """Estimated bytes one configuration costs in a chunk: every backend's poses (4×4) and
    Jacobians (6×dof) per frame, plus the 2·dof shifted poses of a finite-difference Jacobian and
    their temporaries."""
    return 8 * frames * (16 + 6 * dof) * max(1, backends) + 4 * 128 * frames * 2 * dof


def chunk_for(requested: int, frames: int, dof: int, backends: int) -> tuple[int, str | None]:
    """``requested`` lowered so a chunk stays below ``CHUNK_BYTES``, and the note saying so."""
    per_row = chunk_bytes_per_row(frames, dof, backends)
    fits = max(1, CHUNK_BYTES // per_row)
    if requested <= fits:
        return requested, None
    return fits, (
        f"--chunk {requested} lowered to {fits} configurations: with {frames} frames and {dof} joints "
        f"a larger chunk would hold more than {CHUNK_BYTES // 2**20} MB"
    )


# A library run in a child process (:mod:`kinverify.io.isolate`: xacro evaluation, Drake's parsers):
# the memory it may add to the process it was forked from (address space, RLIMIT_AS) and the
# seconds it may run (CPU and wall clock).
LIBRARY_MEMORY_BYTES = 512 * 2**20
LIBRARY_SECONDS = 30.0
