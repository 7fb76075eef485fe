"""Library messages kept off the terminal while a command runs.

Pinocchio's URDF parser (urdfdom) prints ``Error: ... at line 274 in /project/urdfdom/...`` to
file descriptor 2, yourdfpy logs "orphan not connected via joints" through :mod:`logging`,
MuJoCo's warnings become Python warnings that name kinverify's own source lines: none of it is
kinverify's message, and on bad input the one line kinverify prints must be the only one. What a
library has to say that matters reaches the user as kinverify's own message or finding (a library
that refuses a file is a finding naming the library and its reason).

Within :func:`library_output`, file descriptor 2 goes to ``/dev/null`` and ``sys.stderr`` to a
copy of the real descriptor 2 (so kinverify's own messages and progress still show), Python
warnings are ignored and log records go nowhere. ``KINVERIFY_DEBUG=1`` leaves all of it visible.
"""

from __future__ import annotations

import contextlib
import logging
import os
import sys
import warnings
from typing import Iterator


def _on_fd2(stream) -> bool:
    try:
        return stream.fileno() == 2
    except (AttributeError, OSError, ValueError):
        return False


@contextlib.contextmanager
def library_output(quiet: bool = True) -> Iterator[None]:
    """Library output discarded for the block (see the module doc); ``quiet=False``: unchanged."""
    root = logging.getLogger()
    handler = logging.NullHandler()  # with a handler on the root logger, logging's last resort prints nothing
    with warnings.catch_warnings():
        if not quiet:
            yield
            return
        warnings.simplefilter("ignore")
        root.addHandler(handler)
        saved, real, stream = sys.stderr, None, None
        try:
            for s in (sys.stdout, sys.stderr):
                with contextlib.suppress(Exception):
                    s.flush()
            real = os.dup(2)
            sink = os.open(os.devnull, os.O_WRONLY)
            os.dup2(sink, 2)
            os.close(sink)
            if _on_fd2(saved):
                stream = open(
                    real,
                    "w",
                    encoding=getattr(saved, "encoding", None) or "utf-8",
                    errors="backslashreplace",
                    buffering=1,
                    closefd=False,
                )
                sys.stderr = stream
        except OSError:  # no descriptor 2 to redirect: leave everything as it is
            pass
        try:
            yield
        finally:
            if stream is not None:
                with contextlib.suppress(Exception):
                    stream.flush()
                sys.stderr = saved
                stream.close()
            if real is not None:
                os.dup2(real, 2)
                os.close(real)
            root.removeHandler(handler)
