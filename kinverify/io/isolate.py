"""Libraries that can crash or run away, run where that cannot end the run.

A library's C++ code can end the process (Drake's MJCF parser aborts on ``<inertial mass="0">``,
a body MuJoCo writes from a URDF's massless link), and an evaluator can run away (xacro's
``${9**9**9}`` never ends, ``${len('x'*10**10)}`` takes 10 GB). :func:`in_child` runs a function
in a forked child process bounded in memory (``RLIMIT_AS``: the address space the process had
plus ``LIBRARY_MEMORY_BYTES``) and time (``LIBRARY_SECONDS`` of CPU and of wall clock); its
result comes back pickled through a pipe. A child that aborts, segfaults, exceeds its memory or
its time raises :class:`LibraryDied` with the reason (the library's last words on stderr, the
signal, or the limit it reached); what the library raises normally is raised again here.

:func:`survives` is a trial run: a parser is run once in a child for each distinct input, and the
caller parses in its own process only what the child survived (a fork costs about 10 ms; Drake
parses a 7-joint arm in 2 to 4 ms), because a parsed library object cannot cross processes.
"""

from __future__ import annotations

import contextlib
import faulthandler
import hashlib
import os
import pickle
import re
import resource
import selectors
import signal
import sys
import time
from typing import Callable, Iterator

from kinverify.pipeline import limits


class LibraryDied(Exception):
    """A library run by :func:`in_child` ended its process or reached a limit; ``reason`` says how."""

    def __init__(self, reason: str) -> None:
        self.reason = reason
        super().__init__(reason)


class ChildRaised(Exception):
    """An exception raised in the child that could not be sent back as itself: its type and message."""


_SURVIVED: dict[str, str | None] = {}  # trial runs: digest -> None (survived) or the reason it died


def _address_space() -> int:
    """Bytes of address space this process holds now (``/proc/self/statm``'s first field)."""
    try:
        with open("/proc/self/statm", "rb") as f:
            return int(f.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError, IndexError):
        return 0


def in_child(fn: Callable[[], object], seconds: float | None = None, memory: int | None = None):
    """``fn()`` computed in a forked child within ``memory`` more bytes and ``seconds`` (defaults:
    :mod:`kinverify.pipeline.limits`); :class:`LibraryDied` when the child does not come back."""
    seconds = limits.LIBRARY_SECONDS if seconds is None else seconds
    memory = limits.LIBRARY_MEMORY_BYTES if memory is None else memory
    ceiling = _address_space() + memory
    out_r, out_w = os.pipe()
    err_r, err_w = os.pipe()
    sys.stdout.flush()
    sys.stderr.flush()
    try:
        pid = os.fork()
    except OSError:  # no process to spare (a process limit): computed here, unbounded, rather than not at all
        for fd in (out_r, out_w, err_r, err_w):
            os.close(fd)
        return fn()
    if pid == 0:  # the child: never returns
        _child(fn, out_w, err_w, (out_r, err_r), ceiling, seconds)
    os.close(out_w)
    os.close(err_w)
    try:
        data, said, timed_out = _collect(pid, out_r, err_r, seconds)
    finally:
        os.close(out_r)
        os.close(err_r)
    _, status = os.waitpid(pid, 0)
    if timed_out:
        raise LibraryDied(f"ran longer than {seconds:g} s (stopped)")
    return _outcome(status, data, said, memory, seconds)


def _child(fn, out_w: int, err_w: int, closing, ceiling: int, seconds: float) -> None:
    code = 0
    try:
        for fd in closing:
            os.close(fd)
        faulthandler.disable()  # a crash is the parent's to report, not a traceback on the terminal
        for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGALRM):
            with contextlib.suppress(ValueError):  # forked from another thread than the main one
                signal.signal(sig, signal.SIG_DFL)
        null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(null, 1)
        os.dup2(err_w, 2)  # the library's last words, for the reason
        if ceiling:
            resource.setrlimit(resource.RLIMIT_AS, (ceiling, ceiling))
        cpu = max(1, int(seconds + 0.999))
        resource.setrlimit(resource.RLIMIT_CPU, (cpu, cpu + 1))
        try:
            result = ("ok", fn())
        except MemoryError:
            result = ("memory", None)
        except SystemExit as err:  # pydrake turns a failed internal assertion (an abort) into SystemExit
            result = ("exit", str(err))
        except BaseException as err:  # sent back to be raised again in the parent
            result = ("raised", err)
        try:
            data = pickle.dumps(result)
            pickle.loads(data)  # an exception whose class takes other arguments does not come back as itself
        except Exception:
            data = pickle.dumps(("raised", ChildRaised(f"{type(result[1]).__name__}: {result[1]}")))
        view = memoryview(data)
        while view:
            view = view[os.write(out_w, view) :]
    except BaseException:
        code = 70
    finally:
        os._exit(code)


def _collect(pid: int, out_r: int, err_r: int, seconds: float) -> tuple[bytes, bytes, bool]:
    """Everything the child writes on its two pipes until it closes them, or the deadline (the
    child is then killed)."""
    chunks: dict[int, list[bytes]] = {out_r: [], err_r: []}
    deadline = time.monotonic() + seconds + 1.0
    with selectors.DefaultSelector() as sel:
        for fd in chunks:
            sel.register(fd, selectors.EVENT_READ)
        try:
            while sel.get_map():
                left = deadline - time.monotonic()
                if left <= 0:
                    os.kill(pid, signal.SIGKILL)
                    return b"", b"", True
                for key, _ in sel.select(min(left, 1.0)):
                    data = os.read(key.fd, 1 << 16)
                    if data:
                        chunks[key.fd].append(data)
                    else:
                        sel.unregister(key.fd)
        except BaseException:  # interrupted (Ctrl-C): the child goes with the run
            os.kill(pid, signal.SIGKILL)
            os.waitpid(pid, 0)
            raise
    return b"".join(chunks[out_r]), b"".join(chunks[err_r])[-4096:], False


def _outcome(status: int, data: bytes, said: bytes, memory: int, seconds: float):
    words = last_words(said)
    if os.WIFSIGNALED(status):
        sig = os.WTERMSIG(status)
        what = (
            f"ran longer than {seconds:g} s of CPU (stopped)"
            if sig == signal.SIGXCPU
            else f"was killed by {signal.Signals(sig).name}"
        )
        raise LibraryDied(f"{what}{': ' + words if words else ''}")
    if not data:
        raise LibraryDied(f"ended the process (exit status {os.WEXITSTATUS(status)}){': ' + words if words else ''}")
    kind, value = pickle.loads(data)
    if kind == "memory":
        raise LibraryDied(f"needed more than the {memory // 2**20} MB of memory a library may use (stopped)")
    if kind == "exit":
        raise LibraryDied(f"ended the process: {last_words(str(value).encode())}")
    if kind == "raised":
        raise value
    return value


_LOCATION = re.compile(r"^(Failure|Abort|Error) at \S+ in ")


def last_words(said: bytes) -> str:
    """The last line a library printed before dying, without its C++ source location."""
    lines = [line.strip() for line in said.decode("utf-8", "replace").splitlines() if line.strip()]
    if not lines:
        return ""
    line = lines[-1]
    return _LOCATION.sub("", line).rstrip(".")[:300]


def survives(key, fn: Callable[[], object], seconds: float | None = None) -> None:
    """Run ``fn`` once in a child for each distinct ``key`` (a tuple of strings: the library, the
    text it parses...); :class:`LibraryDied` when the child did not come back (remembered). What
    ``fn`` raises or returns is dropped: the caller runs it again in its own process."""
    digest = hashlib.sha256(repr(key).encode("utf-8", "surrogatepass")).hexdigest()
    if digest not in _SURVIVED:
        try:
            in_child(fn, seconds)
            _SURVIVED[digest] = None
        except LibraryDied as err:
            _SURVIVED[digest] = err.reason
        except Exception:  # it raised: the caller's own run raises it again
            _SURVIVED[digest] = None
    reason = _SURVIVED[digest]
    if reason is not None:
        raise LibraryDied(reason)


@contextlib.contextmanager
def usable_cwd() -> Iterator[None]:
    """A current folder a library can ask for: when it was deleted (Drake's parsers fail with
    "cannot get current path"), ``/`` within the block, the deleted one restored after."""
    try:
        os.getcwd()
    except FileNotFoundError:
        here = os.open(".", os.O_RDONLY)
        try:
            os.chdir("/")
            yield
        finally:
            os.fchdir(here)
            os.close(here)
        return
    yield
