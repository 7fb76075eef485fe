"""Opening a USD file safely: every layer file checked before pxr opens it (the root file, then each
sublayer, reference and payload it names, recursively). A FIFO, a device (``/dev/zero``), a
directory or a file above the size limit is refused with one line (exit 2); a layer that is absent
is tolerated and named; pxr's warnings are kept off the terminal; a composition cycle is refused,
naming the prim."""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from pathlib import Path

from kinverify.errors import InputError
from kinverify.io.plan import note_input
from kinverify.pipeline.limits import MAX_DATA_BYTES, MAX_MODEL_BYTES

try:  # the optional extra "usd" (usd-core)
    from pxr import Pcp, Sdf, Usd
except ImportError as _err:  # pragma: no cover - exercised without the extra
    Pcp = Sdf = Usd = None
    MISSING = f"usd-core (pxr) is not installed ({_err}): pip install 'kinverify[usd]'"
else:
    MISSING = ""


@contextlib.contextmanager
def quiet_stderr():
    """pxr's warnings (an absent mesh library, one line per prim) written to a scratch file, not the terminal."""
    with tempfile.TemporaryFile() as scratch:
        saved = os.dup(2)
        os.dup2(scratch.fileno(), 2)
        try:
            yield
        finally:
            os.dup2(saved, 2)
            os.close(saved)


def _check_layer(path: str, label: str, named_by: str | None) -> None:
    """A layer file is a regular file of bounded size (text layers: the model limit; crate files: the data limit)."""
    where = f"{label}: {path}" if named_by is None else f"{label}: layer {path} (named by {named_by})"
    try:
        st = os.stat(path)
    except OSError as err:
        raise InputError(f"{where}: cannot read: {err.strerror}") from None
    if not stat.S_ISREG(st.st_mode):
        what = (
            "a FIFO (named pipe)"
            if stat.S_ISFIFO(st.st_mode)
            else "a device"
            if stat.S_ISCHR(st.st_mode) or stat.S_ISBLK(st.st_mode)
            else "a directory"
            if stat.S_ISDIR(st.st_mode)
            else "not a regular file"
        )
        raise InputError(f"{where} is {what}, not a regular file")
    limit = MAX_DATA_BYTES if path.endswith(".usdc") else MAX_MODEL_BYTES
    if st.st_size > limit:
        raise InputError(
            f"{where} is {st.st_size / 2**20:.1f} MB, above the {limit // 2**20} MB kinverify reads (see docs/robustness.md)"
        )
    note_input(Path(path), "a USD layer:")


def _pxr_reason(err) -> str:
    """pxr's message without its C++ location: ``'a.usda:18:36: Expected } at ...'``."""
    text = " ".join(str(err).split())
    return text.split(" : ", 1)[-1].strip(" '") if " : " in text else text


def open_stage(path: str, label: str = "--usd") -> tuple[Usd.Stage, list[str], list]:
    """The stage of ``path`` (every layer checked first), the layers named but absent, and the opened
    layers (kept alive so the stage reuses them). :class:`InputError` on an unsafe or unreadable layer."""
    if MISSING:
        raise InputError(f"{label}: reading USD needs {MISSING}")
    root = os.path.abspath(path)
    _check_layer(root, label, None)
    todo: list[tuple[str, str | None]]
    todo, seen, layers, absent = [(root, None)], set(), [], []
    while todo:
        file, by = todo.pop()
        if file in seen:
            continue
        seen.add(file)
        with quiet_stderr():
            try:
                layer = Sdf.Layer.FindOrOpen(file)
            except Exception as err:  # pxr raises Tf.ErrorException
                raise InputError(f"{label}: {file}: not a USD layer pxr reads: {_pxr_reason(err)}") from None
        if layer is None:
            raise InputError(f"{label}: {file}: not a USD layer pxr reads")
        layers.append(layer)
        for dep in layer.GetCompositionAssetDependencies():
            resolved = layer.ComputeAbsolutePath(dep)
            if not dep:
                continue
            if not resolved or not os.path.lexists(resolved):
                absent.append(dep if by is None else f"{dep} (named by {os.path.basename(file)})")
                continue
            _check_layer(resolved, label, os.path.basename(file))
            todo.append((resolved, os.path.basename(file)))
    with quiet_stderr():
        stage = Usd.Stage.Open(layers[0], Usd.Stage.LoadAll)
    for error in stage.GetCompositionErrors():
        if isinstance(error, (Pcp.ErrorArcCycle, Pcp.ErrorSublayerCycle)):
            site = getattr(error, "rootSite", None)
            prim = getattr(site, "path", "") if site is not None else ""
            raise InputError(
                f"{label}: {path}: composition cycle at prim {prim or '/'}: a layer sublayers or references "
                "itself (pxr: " + str(error).strip().splitlines()[0] + ")"
            )
    return stage, sorted(set(absent)), layers
