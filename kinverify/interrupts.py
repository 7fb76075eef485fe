"""SIGINT (Ctrl-C) and SIGTERM during a command: never lost, never a traceback.

:func:`install` is the first thing :func:`kinverify.cli.main` does. The first signal is recorded
and raised in the main thread (:class:`KeyboardInterrupt`, or :class:`Terminated` for SIGTERM),
so every ``finally`` runs: worker processes are stopped, temporary files removed. Later signals
are only recorded: a second Ctrl-C while shutting down cannot interrupt the shutdown itself (no
traceback from a half-finished ``except`` block).

A library may swallow the exception: trimesh, imported through yourdfpy, catches
``BaseException`` around its optional imports, and a ``KeyboardInterrupt`` inside ``import
mujoco`` can come out as another exception. The signal is still recorded: :func:`check` raises it
again at the checkpoints (each suite, each chunk of configurations, after the backends are
built) and :func:`kinverify.cli.main` checks once more before it commits the outputs, so a run
that was interrupted never writes them and exits 130 (SIGINT) or 143 (SIGTERM), however the
library handled the exception.
"""

from __future__ import annotations

import contextlib
import signal
from typing import Iterator

SIGNALS = (signal.SIGINT, signal.SIGTERM)
_state = {"received": None, "armed": False}


class Terminated(KeyboardInterrupt):
    """SIGTERM, handled like SIGINT."""


def _exception(signum: int) -> KeyboardInterrupt:
    return Terminated() if signum == signal.SIGTERM else KeyboardInterrupt()


def _handler(signum, frame) -> None:
    if _state["received"] is None:
        _state["received"] = signum
    if _state["armed"]:
        _state["armed"] = False  # raise once: later signals must not interrupt the shutdown
        raise _exception(signum)


def install() -> dict:
    """Handle SIGINT and SIGTERM as above (main thread only); returns the previous handlers, for
    :func:`restore` ({} when not in the main thread: nothing installed)."""
    _state.update(received=None, armed=True)
    previous = {}
    try:
        for sig in SIGNALS:
            previous[sig] = signal.signal(sig, _handler)
    except ValueError:  # not the main thread
        _state["armed"] = False
        return {}
    return previous


def restore(previous: dict) -> None:
    _state["armed"] = False
    for sig, handler in previous.items():
        signal.signal(sig, handler)


def received() -> int | None:
    """The first signal received since :func:`install` (None: none)."""
    return _state["received"]


def check() -> None:
    """Raise the recorded signal again (a library swallowed it); nothing when none came."""
    if _state["received"] is not None:
        _state["armed"] = False
        raise _exception(_state["received"])


def exit_code(signum: int | None = None) -> int:
    """130 for SIGINT, 143 for SIGTERM (128 + the signal number, as a shell reports a signal)."""
    return 128 + int(signum or received() or signal.SIGINT)


@contextlib.contextmanager
def held() -> Iterator[None]:
    """SIGINT and SIGTERM only recorded during the block (renaming the outputs into place is not
    cut half-way); :func:`check` after it acts on them. (Not a signal mask: a process-directed
    signal may be delivered to any thread, and Python runs the handler in the main thread anyway.)"""
    armed, _state["armed"] = _state["armed"], False
    try:
        yield
    finally:
        _state["armed"] = armed and _state["received"] is None
