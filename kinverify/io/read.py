"""The one reader of every input file: bounded, non-blocking, and recorded as an input of the run.

:func:`read_bytes` opens ``path`` only if it is a regular file (a FIFO would block the run, a
device such as ``/dev/zero`` never ends, a directory is not a file: each is refused with one line),
without blocking even if the file is swapped for a FIFO between the check and the open
(``O_NONBLOCK``), and reads at most ``limit`` bytes: the size is measured by reading, so a file
that reports 0 bytes (``/proc``), grows while read, or is sparse cannot make it read more. The
path is recorded in the open output plan (:func:`kinverify.io.plan.note_input`): no output
of the run may replace it, also through a symbolic or hard link.
"""

from __future__ import annotations

import builtins
import contextlib
import errno
import io
import os
import stat
from typing import Iterator

from kinverify.errors import InputError
from kinverify.pipeline.limits import MAX_DATA_BYTES, MAX_MODEL_BYTES
from kinverify.io.plan import KINDS, note_input

_BLOCK = 1 << 20


class InputFileError(InputError):
    """An input file kinverify cannot read: ``path``, ``reason`` (e.g. ``is a FIFO (named pipe),
    not a regular file``), ``label`` (how the user named it, e.g. ``--accept``) and, for a system
    error, its ``errno``."""

    def __init__(self, path, reason: str, label: str = "", err: int | None = None, too_large: bool = False) -> None:
        self.path, self.reason, self.label, self.errno, self.too_large = str(path), reason, label, err, too_large
        super().__init__(f"{label}: {path} {reason}" if label else f"{path} {reason}")


def size_text(size: int) -> str:
    """``512 bytes``, ``1.5 kB`` or ``2.0 MB`` (1 kB = 1024 bytes, 1 MB = 1024 kB): a unit that shows the size."""
    if size < 2**10:
        return f"{size} byte{'s' * (size != 1)}"
    return f"{size / 2**10:.1f} kB" if size < 2**20 else f"{size / 2**20:.1f} MB"


def _limit_text(limit: int) -> str:
    return f"{limit // 2**20} MB" if limit and limit % 2**20 == 0 else size_text(limit)


def read_bytes(
    path, label: str = "", limit: int = MAX_MODEL_BYTES, register: bool = True, shared: tuple[int, str] | None = None
) -> bytes:
    """The content of the regular file ``path``, at most ``limit`` bytes; :class:`InputFileError`
    otherwise. ``register``: record it as an input of the run (False for a file about to be
    replaced, e.g. the previous baseline that ``baseline save`` checks first). ``shared``: ``limit``
    is what remains of a budget of ``(bytes, files)`` that several files share, e.g.
    ``(MAX_DATA_BYTES, "all meshes of the model")``: the refusal says so."""
    path = os.fspath(path)
    fd, size = _open(path, label)
    try:
        if size > limit:  # a regular file's size is exact: refuse before reading
            raise _too_large(path, label, limit, size, shared)
        if register:
            note_input(path, label)
        chunks, total = [], 0
        while total <= limit:
            chunk = os.read(fd, min(_BLOCK, limit + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
    except OSError as err:
        raise _system(path, label, err) from None
    finally:
        os.close(fd)
    if total > limit:
        raise _too_large(path, label, limit, None, shared)
    return b"".join(chunks)


def read_text(path, label: str = "", limit: int = MAX_MODEL_BYTES, register: bool = True) -> str:
    """:func:`read_bytes` decoded as UTF-8 (a byte-order mark is dropped)."""
    data = read_bytes(path, label, limit, register)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise InputFileError(path, f"is not UTF-8 text (byte {err.start})", label) from None


def check_file(
    path, label: str = "", limit: int = MAX_DATA_BYTES, register: bool = True, shared: tuple[int, str] | None = None
) -> int:
    """The size of ``path`` when a library may open it: a regular file (the same refusals as
    :func:`read_bytes`, made on a non-blocking descriptor) of at most ``limit`` bytes (a regular
    file's size is exact: nothing is read); recorded as an input of the run. ``shared``: as
    :func:`read_bytes`'s."""
    path = os.fspath(path)
    fd, size = _open(path, label)
    os.close(fd)
    if size > limit:
        raise _too_large(path, label, limit, size, shared)
    if register:
        note_input(path, label)
    return size


def read_head(path, size: int = 4096, label: str = "") -> bytes:
    """The first ``size`` bytes of ``path`` (to tell a URDF from an MJCF); the same refusals as
    :func:`read_bytes`, and nothing recorded."""
    path = os.fspath(path)
    fd, _ = _open(path, label)
    try:
        return os.read(fd, size)
    except OSError as err:
        raise _system(path, label, err) from None
    finally:
        os.close(fd)


def _open(path: str, label: str) -> tuple[int, int]:
    """A blocking descriptor on the regular file ``path`` and its size. Checked before opening
    (a FIFO is never opened) and again on the descriptor (swapped since the check: the
    non-blocking open returned at once)."""
    try:
        _regular(path, label, os.stat(path).st_mode)
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_NOCTTY", 0))
    except OSError as err:
        raise _system(path, label, err) from None
    try:
        st = os.fstat(fd)
        _regular(path, label, st.st_mode)
        os.set_blocking(fd, True)
    except BaseException:
        os.close(fd)
        raise
    return fd, st.st_size


def _regular(path: str, label: str, mode: int) -> None:
    if not stat.S_ISREG(mode):
        kind = KINDS.get(stat.S_IFMT(mode), "not a regular file")
        raise InputFileError(path, f"is {kind}, not a regular file: kinverify reads regular files only", label)


def _too_large(path: str, label: str, limit: int, size: int | None, shared: tuple[int, str] | None) -> InputFileError:
    what = size_text(size) if size is not None else f"more than {size_text(limit)}"
    if shared is None:
        reason = f"is {what}, above the {_limit_text(limit)} kinverify reads"
    else:  # ``limit`` is what the files read before it left of the budget
        total, files = shared
        reason = f"is {what}, which would exceed the {_limit_text(total)} {files} share: {size_text(total - limit)} already read"
    return InputFileError(path, f"{reason} (see docs/robustness.md)", label, too_large=True)


def _system(path: str, label: str, err: OSError) -> InputFileError:
    if err.errno in (errno.ENOENT, errno.ENOTDIR):
        return InputFileError(path, "is not a file", label, err.errno)
    if err.errno == errno.EISDIR:
        return InputFileError(path, "is a directory, not a regular file: kinverify reads regular files only", label, err.errno)
    return InputFileError(path, f"cannot be read: {err.strerror or err}", label, err.errno)


@contextlib.contextmanager
def library_reads(
    modules, label: str, limit: int = MAX_MODEL_BYTES, record: list | None = None, files: str = "the files the library opens"
) -> Iterator[None]:
    """Within the block, a library module that opens files itself (xacro, for its includes) reads
    them through :func:`read_bytes`: ``open(name)`` in each of ``modules`` returns the bounded
    content (the files together within ``limit`` bytes), a FIFO or device is refused, and each
    file is an input of the run. A missing file is still ``FileNotFoundError`` (the library's
    own optional includes rely on it). Opening for writing is left alone. ``record``: a list each
    file read is appended to (a child process's reads, to record in the parent's plan); ``files``:
    what shares ``limit``, as a refusal names it."""
    budget = [limit]

    def bounded_open(file, mode="r", *args, **kwargs):
        if any(flag in mode for flag in "wax+"):
            return builtins.open(file, mode, *args, **kwargs)
        try:
            data = read_bytes(file, label, max(budget[0], 0), shared=(limit, files))
        except InputFileError as err:
            if err.errno in (errno.ENOENT, errno.ENOTDIR):
                raise FileNotFoundError(err.errno, os.strerror(err.errno), os.fspath(file)) from None
            raise
        budget[0] -= len(data)
        if record is not None:
            record.append(os.fspath(file))
        return io.BytesIO(data) if "b" in mode else io.StringIO(data.decode(kwargs.get("encoding") or "utf-8"))

    patched = [m for m in modules if "open" not in vars(m)]
    for module in patched:
        module.open = bounded_open
    try:
        yield
    finally:
        for module in patched:
            del module.open
