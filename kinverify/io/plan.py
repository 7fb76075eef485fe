"""Which files a run may write: the one place every output path is checked.

A run declares what it reads and what it will write (:func:`output_plan`, opened by the CLI
before any work starts). An output is refused, with a one-line :class:`InputError` (exit 2),
when it is

- an input of the same run (same resolved path, or the same file through a hard link),
- the same file as another output of the run (``--json X --report X``),
- a directory, or an existing file that is not a regular file (device, FIFO, socket): the
  temporary-file-then-rename write would otherwise *replace* ``/dev/full`` or a FIFO.

Every file the run reads is added with :func:`note_input` by the one reader
(:mod:`kinverify.io.read`): the files a model includes, its meshes, an accepted-differences file
found beside the URDF... An input added after the outputs were claimed is checked against them at
once, so the refusal comes when the file is read, before the run computes anything.
:func:`kinverify.io.write.write_atomic` checks every target against the open plan again just
before it writes, so a default path computed after the run (``reports/<model>.json``) gets the
same protection. Without an open plan (library use) only the target itself is checked
(directory, non-regular file).

The outputs of a run are one transaction: within a plan, :func:`~kinverify.io.write.write_atomic`
writes each output to a temporary file beside its target and *stages* it; :meth:`OutputPlan.commit`
renames them all over their targets at the end of the run, and a run that fails or is
interrupted before then removes them all, so no output is replaced (the JSON is never new beside
an old HTML page).
"""

from __future__ import annotations

import contextlib
import contextvars
import os
import re
import stat
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Iterator

from kinverify.errors import InputError

KINDS = {
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFIFO: "a FIFO (named pipe)",
    stat.S_IFSOCK: "a socket",
    stat.S_IFDIR: "a directory",
}


@dataclass(frozen=True)
class _File:
    label: str  # how the user named it: "--json", "the spec MODEL", ...
    path: Path  # as given
    resolved: Path
    inode: tuple[int, int] | None  # (st_dev, st_ino) when it exists


def _file(label: str, path) -> _File:
    path = Path(path)
    try:
        resolved = path.resolve()
    except (RuntimeError, OSError):  # Python 3.11 raises RuntimeError on a loop, 3.13 OSError (ELOOP)
        named = f"{label} {path}" if label else str(path)
        raise InputError(f"{named} is a loop of symbolic links (it never reaches a file)") from None
    try:
        st = os.stat(resolved)
        inode = (st.st_dev, st.st_ino)
    except OSError:
        inode = None
    return _File(label, path, resolved, inode)


def _named(f: _File) -> str:
    return f"{f.label} {f.path}" if f.label else str(f.path)


def check_target(path, label: str = "") -> Path:
    """The path a write to ``path`` lands on (symbolic links followed); :class:`InputError`
    when it is a directory or an existing non-regular file."""
    f = _file(label, path)
    try:
        mode = os.stat(f.resolved).st_mode
    except FileNotFoundError:
        return f.resolved
    except OSError as err:
        raise InputError(f"{_named(f)}: cannot write: {err.strerror or err}") from None
    if not stat.S_ISREG(mode):
        kind = KINDS.get(stat.S_IFMT(mode), "not a regular file")
        raise InputError(f"{_named(f)} is {kind}, not a regular file: refusing to write there (give a file path)")
    return f.resolved


@dataclass
class OutputPlan:
    """The inputs and outputs of one run (see the module doc)."""

    inputs: list[_File] = field(default_factory=list)
    outputs: dict[Path, _File] = field(default_factory=dict)
    written: set[Path] = field(default_factory=set)

    staged: list[tuple[str, Path]] = field(default_factory=list)  # (temporary file, target), renamed by commit

    def add_input(self, path, label: str = "") -> None:
        """Record an input; :class:`InputError` at once if an output already claimed is that file."""
        if path is None:
            return
        f = _file(label, path)
        self.inputs.append(f)
        for out in self.outputs.values():
            _not_the_input(out, out.resolved, f)

    def claim(self, path, label: str = "") -> Path:
        """Check ``path`` as an output of this run and record it; returns the resolved target.
        Claiming the same path again under the same label is allowed (a pre-check, then the write)."""
        target = check_target(path, label)
        f = _file(label, path)
        for other in self.inputs:
            _not_the_input(f, target, other)
        prior = self.outputs.get(target)
        if prior is None and f.inode is not None:
            prior = next((o for o in self.outputs.values() if o.inode == f.inode), None)
        if prior is not None and prior.label != label:
            raise InputError(f"{_named(f)} and {_named(prior)} name the same file: give each output its own path")
        self.outputs.setdefault(target, f)
        return target

    def before_write(self, path) -> Path:
        """The check :func:`~kinverify.io.write.write_atomic` makes: a path claimed earlier keeps
        its label; one path is written at most once per run."""
        target = Path(path).resolve()
        label = self.outputs[target].label if target in self.outputs else ""
        if target in self.written:
            raise InputError(f"{path}: written twice in one run (two outputs name the same file): give each output its own path")
        target = self.claim(path, label)
        self.written.add(target)
        return target

    def stage(self, tmp: str, target: Path) -> None:
        """A complete temporary file, to rename over ``target`` at :meth:`commit`."""
        self.staged.append((tmp, target))

    def commit(self) -> None:
        """Rename every staged temporary file over its target (each rename is atomic)."""
        staged, self.staged = self.staged, []
        folders = []
        for i, (tmp, target) in enumerate(staged):
            try:
                os.replace(tmp, target)
            except OSError as err:
                for rest, _ in staged[i:]:
                    remove_quietly(rest)
                done = f"; {i} other output(s) were already replaced" if i else "; nothing was replaced"
                raise InputError(f"{target}: cannot write: {err.strerror or err}{done}") from None
            if target.parent not in folders:
                folders.append(target.parent)
        for folder in folders:
            fsync_dir(folder)

    def discard(self) -> None:
        """Remove every staged temporary file: no output is replaced."""
        staged, self.staged = self.staged, []
        for tmp, _ in staged:
            remove_quietly(tmp)


def _not_the_input(out: _File, target: Path, other: _File) -> None:
    if other.resolved == target or (out.inode is not None and out.inode == other.inode):
        link = "" if other.resolved == target else " (the same file through a link)"
        raise InputError(
            f"{_named(out)} is {_named(other)}, an input of this run{link}: refusing to overwrite it (choose another output path)"
        )


def remove_quietly(path: str) -> None:
    try:
        os.unlink(path)
    except FileNotFoundError:
        pass


def fsync_dir(folder: Path) -> None:
    """Make a rename in ``folder`` durable (where the filesystem can sync a directory)."""
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


_PLAN: contextvars.ContextVar[OutputPlan | None] = contextvars.ContextVar("kinverify_output_plan", default=None)


def current_plan() -> OutputPlan | None:
    return _PLAN.get()


@contextlib.contextmanager
def output_plan(inputs: Iterable[tuple[str, object]] = (), outputs: Iterable[tuple[str, object]] = ()) -> Iterator[OutputPlan]:
    """Open a plan for one run: ``inputs`` and ``outputs`` are ``(label, path)`` pairs (``None``
    paths skipped). Every output is checked now, before the run starts. The outputs written in
    the block are committed when it ends normally (unless :meth:`OutputPlan.commit` was called
    already) and discarded when it raises."""
    plan = OutputPlan()
    for label, path in inputs:
        plan.add_input(path, label)
    for label, path in outputs:
        if path is not None:
            plan.claim(path, label)
    token = _PLAN.set(plan)
    try:
        yield plan
        plan.commit()
    finally:
        plan.discard()
        _PLAN.reset(token)


def note_input(path, label: str = "") -> None:
    """Record a file the run reads (e.g. a mesh a model references) in the open plan, if any."""
    plan = _PLAN.get()
    if plan is not None:
        plan.add_input(path, label)


def claim_outputs(*pairs: tuple[str, object]) -> list[Path]:
    """Check several outputs together before writing any (e.g. a command's default paths, known
    only after loading the model): all are accepted or none is written."""
    plan = _PLAN.get()
    if plan is None:
        plan = OutputPlan()
    return [plan.claim(path, label) for label, path in pairs]


def default_output(name: str, suffix: str, folder: str = "reports") -> str:
    """``folder/<name><suffix>`` for a default output path, with ``name`` (a model name, which a
    user's URDF or MJCF may set to anything, e.g. ``../../x``) reduced to a plain file name."""
    safe = re.sub(r"[^A-Za-z0-9_.+-]", "_", name).lstrip(".") or "model"
    return f"{folder}/{safe[:120]}{suffix}"


def target_for_write(path) -> Path:
    """Where :func:`~kinverify.io.write.write_atomic` writes ``path``: checked against the open
    plan, or on its own without one."""
    plan = _PLAN.get()
    return plan.before_write(path) if plan is not None else check_target(path)
