"""Atomic file writes: an output is either complete or absent, never half-written.

Every file kinverify writes goes through :func:`write_atomic`: the target is checked first
(:mod:`kinverify.io.plan`: not an input of the run, not another output, not a directory
or device), the data goes to a temporary file in the target's directory, is flushed and
``fsync``-ed, its size is checked, and only then is it renamed over the target: at once without
an open plan (library use), with every other output of the run at the plan's commit within one
(the CLI). A failed or short write (disk full, a file size limit) is a one-line
:class:`InputError` and nothing is replaced.

The temporary file is ``.<name>.<random>.tmp`` beside the target, ``<name>`` shortened so the
whole stays within the 255 bytes a file name may have.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from kinverify.errors import InputError
from kinverify.io.plan import current_plan, fsync_dir, remove_quietly, target_for_write

NAME_MAX = 255
_TEMP_EXTRA = len(".") + len(".") + 8 + len(".tmp")  # the dots, mkstemp's random part, the suffix


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def temp_prefix(name: str) -> str:
    """``.<name>.`` with ``name`` cut (on a character boundary) so the temporary file's name fits
    in ``NAME_MAX`` bytes."""
    room = NAME_MAX - _TEMP_EXTRA
    raw = name.encode("utf-8", "surrogateescape")
    if len(raw) > room:
        name = raw[:room].decode("utf-8", "ignore")
    return f".{name}."


def write_atomic(path: str | os.PathLike, data: str | bytes) -> Path:
    """Write ``data`` to a temporary file beside ``path``, ``fsync`` it, then rename it over
    ``path`` (within an open plan: at the plan's commit, with the run's other outputs).

    Returns ``path`` as given. A symbolic link at ``path`` is kept: its target file is replaced."""
    given = Path(path)
    target = target_for_write(given)
    # a path that was not UTF-8 (its bytes are lone surrogates in Python) is shown as \udcff in the page
    payload = data.encode("utf-8", "backslashreplace") if isinstance(data, str) else bytes(data)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=temp_prefix(target.name), suffix=".tmp")
    except OSError as err:
        raise InputError(f"{given}: cannot write: {err.strerror or err}") from None
    try:
        with os.fdopen(fd, "wb") as handle:
            handle.write(payload)
            handle.flush()
            os.fsync(handle.fileno())
            size = os.fstat(handle.fileno()).st_size
        if size != len(payload):
            raise InputError(f"{given}: short write ({size} of {len(payload)} bytes): nothing was replaced")
        try:
            mode = os.stat(target).st_mode & 0o7777  # keep an existing file's permissions
        except FileNotFoundError:
            mode = 0o666 & ~_umask()  # mkstemp makes 0600; a report is meant to be shared
        os.chmod(tmp, mode)
        plan = current_plan()
        if plan is not None:
            plan.stage(tmp, target)
            return given
        os.replace(tmp, target)
    except OSError as err:
        remove_quietly(tmp)
        raise InputError(f"{given}: cannot write: {err.strerror or err}; nothing was replaced") from None
    except BaseException:
        remove_quietly(tmp)
        raise
    fsync_dir(target.parent)
    return given
