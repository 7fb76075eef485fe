"""Atomic file writes: an output is either complete or absent, never half-written.

Every file kinverify writes goes through :func:`write_atomic`: the target is checked first
(:mod:`kinverify.io.plan`: not an input of the run, not another output, not a directory
or device), the data goes to a temporary file in the target's directory, is flushed and
``fsync``-ed, its size is checked, and only then is it renamed over the target. A failed or
short write (disk full, file size limit) is a one-line :class:`InputError` and nothing is
replaced.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from kinverify.errors import InputError
from kinverify.io.plan import target_for_write


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _fsync_dir(folder: Path) -> None:
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass  # some filesystems cannot sync a directory; the file itself is synced
    finally:
        os.close(fd)


def write_atomic(path: str | os.PathLike, data: str | bytes) -> Path:
    """Write ``data`` to a temporary file beside ``path``, ``fsync`` it, then rename it over ``path``.

    Returns ``path`` as given. A symbolic link at ``path`` is kept: its target file is replaced."""
    given = Path(path)
    target = target_for_write(given)
    payload = data.encode("utf-8") if isinstance(data, str) else bytes(data)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
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
        os.replace(tmp, target)
    except OSError as err:
        _remove(tmp)
        raise InputError(f"{given}: cannot write: {err.strerror or err}; nothing was replaced") from None
    except BaseException:
        _remove(tmp)
        raise
    _fsync_dir(target.parent)
    return given


def _remove(tmp: str) -> None:
    try:
        os.unlink(tmp)
    except FileNotFoundError:
        pass
