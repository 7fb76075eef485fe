"""Run a suite's chunks in this process, in worker processes (``--jobs N``) or on Dask.

A chunk function ``fn(backends, options, q, start) -> result`` is a module-level (picklable)
function of one chunk of configurations: rows ``start:start+len(q)`` of ``ctx.q``. Results come
back **in chunk order** whatever the executor, so a suite that merges them in that order gets
results identical to a single sequential pass.

Workers never receive backend objects (library models do not pickle): they get the model
sources, the backend names and the sample generator once, build the backends on first use and
keep them for later chunks; each worker generates its own chunk of configurations.
"""

from __future__ import annotations

import dataclasses
import os
import shutil
import signal
import tempfile
import uuid
from collections.abc import Sequence
from typing import Any, Callable, Iterator

from kinverify import interrupts
from kinverify.errors import InputError

EXECUTORS = ("local", "dask")
_WORKER_CACHE: dict[str, tuple[dict, Any, Any]] = {}  # token -> (backends, options, samples)


@dataclasses.dataclass
class Payload:
    """What a worker needs to rebuild a run: sent once per worker."""

    token: str
    sources: Any
    backend_names: list[str]
    extra_backends: tuple
    options: Any
    samples: Any


def _worker_state(payload: Payload):
    state = _WORKER_CACHE.get(payload.token)
    if state is None:
        from kinverify.backends import build_backends

        backends = {b.name: b for b in build_backends(payload.sources, payload.backend_names)}
        for b in payload.extra_backends:
            backends[b.name] = b
        _WORKER_CACHE.clear()  # one run per worker at a time
        state = _WORKER_CACHE[payload.token] = (backends, payload.options, payload.samples)
    return state


def _init_worker(payload: Payload) -> None:
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    # The main process handles SIGINT and SIGTERM and stops the workers; a worker ignores a
    # terminal's Ctrl-C (no traceback from each worker) and dies on SIGTERM.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    _worker_state(payload)


def _run_chunk(fn: Callable, payload: Payload, start: int, stop: int):
    backends, options, samples = _worker_state(payload)
    return fn(backends, options, samples[start:stop], start)


def _run_chunk_local(fn: Callable, token: str, start: int, stop: int):
    backends, options, samples = _WORKER_CACHE[token]
    return fn(backends, options, samples[start:stop], start)


def check_executor_options(options) -> None:
    if options.jobs < 1:
        raise InputError(f"--jobs must be >= 1, got {options.jobs}")
    if options.executor not in EXECUTORS:
        raise InputError(f"--executor must be one of {', '.join(EXECUTORS)}, got {options.executor!r}")
    if options.scheduler and options.executor != "dask":
        raise InputError("--scheduler needs --executor dask")


def run_chunks(ctx, fn: Callable, chunks: Sequence[tuple[int, int]]) -> Iterator:
    """Yield ``fn``'s result for each ``(start, stop)`` of ``chunks``, in that order."""
    opts = ctx.options
    check_executor_options(opts)
    report = opts.on_progress or (lambda done, total: None)
    total = chunks[-1][1] - chunks[0][0] if chunks else 0
    done = 0
    if opts.executor == "local" and (opts.jobs == 1 or len(chunks) <= 1):
        for start, stop in chunks:
            interrupts.check()  # a signal a library swallowed stops the run at the next chunk
            yield fn(ctx.backends, opts, ctx.q[start:stop], start)
            done += stop - start
            report(done, total)
        return
    payload = _payload(ctx)
    if opts.executor == "dask":
        results = _dask_results(fn, payload, chunks, opts)
    else:
        results = _process_results(fn, payload, chunks, opts.jobs)
    for (start, stop), result in zip(chunks, results, strict=True):
        interrupts.check()
        yield result
        done += stop - start
        report(done, total)


def _payload(ctx) -> Payload:
    from kinverify.backends import available_backends

    registry = available_backends()
    built = [n for n in ctx.backends if n in registry]
    extra = tuple(b for n, b in ctx.backends.items() if n not in registry)
    options = dataclasses.replace(ctx.options, on_progress=None)
    return Payload(uuid.uuid4().hex, ctx.sources, built, extra, options, ctx.q)


def _process_results(fn, payload: Payload, chunks, jobs: int) -> Iterator:
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    # "spawn" would re-import everything per worker; "fork" is cheap and safe here (no threads
    # hold locks in the libraries we call), but is not available everywhere.
    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
    ctx = multiprocessing.get_context(method)
    pool = ProcessPoolExecutor(jobs, mp_context=ctx, initializer=_init_worker, initargs=(payload,))
    finished = False
    try:
        # Keep at most 2 chunks per worker in flight, so results waiting for an earlier chunk
        # stay bounded in memory.
        pending, order = {}, iter(chunks)
        window = 2 * jobs
        submitted = 0
        for start, stop in order:
            pending[submitted] = pool.submit(_run_chunk_local, fn, payload.token, start, stop)
            submitted += 1
            if len(pending) >= window:
                break
        for i in range(len(chunks)):
            result = pending.pop(i).result()
            nxt = next(order, None)
            if nxt is not None:
                pending[submitted] = pool.submit(_run_chunk_local, fn, payload.token, *nxt)
                submitted += 1
            yield result
        finished = True
    finally:
        if finished:
            pool.shutdown(wait=True)
        else:  # an error, Ctrl-C or SIGTERM in this process: stop the workers now, leave none behind
            stop_workers(pool)


def stop_workers(pool, timeout: float = 5.0) -> None:
    """Terminate a ``ProcessPoolExecutor``'s worker processes (queued chunks are cancelled; a
    worker still alive after ``timeout`` s is killed) and wait for them to exit."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in processes:
        if proc.is_alive():
            proc.terminate()
    for proc in processes:
        proc.join(timeout)
        if proc.is_alive():
            proc.kill()
            proc.join(timeout)
    # the executor's manager thread sees its workers gone and ends: wait for it here, or at exit it
    # writes to a wake-up pipe already closed ("Exception ignored ... Bad file descriptor")
    manager = getattr(pool, "_executor_manager_thread", None)
    if manager is not None:
        manager.join(timeout)


def _dask_results(fn, payload: Payload, chunks, opts) -> Iterator:
    try:
        import dask.config
        from dask.distributed import Client, LocalCluster
    except ImportError:
        raise InputError("--executor dask needs dask.distributed: pip install 'kinverify[dask]'") from None
    cluster = client = None
    scratch = tempfile.mkdtemp(prefix="kinverify-dask-")  # the workers' dask-scratch-space, removed at the end
    try:
        if opts.scheduler:
            client = _connect(Client, opts.scheduler)
        else:
            # a signal while the workers start is acted on once the cluster exists: a half-started
            # cluster cannot be closed, and distributed's exit handler then prints a traceback
            with interrupts.held(), dask.config.set({"temporary-directory": scratch}):
                cluster = LocalCluster(
                    n_workers=opts.jobs,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                    silence_logs=40,
                    local_directory=scratch,
                )
                client = Client(cluster)
        interrupts.check()
        remote = client.scatter(payload, broadcast=True)
        window = 4 * max(1, opts.jobs)
        futures, order = [], iter(chunks)
        for start, stop in order:
            futures.append(client.submit(_run_chunk, fn, remote, start, stop, pure=False))
            if len(futures) >= window:
                break
        for _ in range(len(chunks)):
            result = futures.pop(0).result()
            nxt = next(order, None)
            if nxt is not None:
                futures.append(client.submit(_run_chunk, fn, remote, *nxt, pure=False))
            yield result
    finally:  # also when the generator is closed by the garbage collector: a signal now is acted on later
        with interrupts.held():
            if client is not None:
                client.close()
            if cluster is not None:
                cluster.close()
            shutil.rmtree(scratch, ignore_errors=True)


def _connect(client_class, address: str):
    """A Dask client of the scheduler at ``address``, or a one-line :class:`InputError` within
    ``SCHEDULER_TIMEOUT_S`` (a refused TCP connection at once)."""
    import socket
    from urllib.parse import urlsplit

    from kinverify.pipeline.limits import SCHEDULER_TIMEOUT_S

    unreachable = f"--scheduler {address}: no Dask scheduler answers there within {SCHEDULER_TIMEOUT_S:g} s"
    parts = urlsplit(address if "://" in address else f"tcp://{address}")
    if parts.scheme in ("tcp", "tls"):
        try:
            port = parts.port
        except ValueError:
            port = None
        if not parts.hostname or port is None:
            raise InputError(f"--scheduler {address}: expected tcp://HOST:PORT")
        try:
            socket.create_connection((parts.hostname, port), timeout=SCHEDULER_TIMEOUT_S).close()
        except OSError as err:
            raise InputError(f"{unreachable} ({err.strerror or type(err).__name__})") from None
    try:
        return client_class(address, timeout=f"{SCHEDULER_TIMEOUT_S}s")
    except (OSError, TimeoutError) as err:
        raise InputError(f"{unreachable} ({' '.join(str(err).split())[:120] or type(err).__name__})") from None
