"""The files a library opens on kinverify's behalf, found before the library parses the model and
checked like every input (:mod:`kinverify.io.read`: a regular file, no FIFO, device, directory or
symbolic-link loop, within the size kinverify reads), each recorded as an input of the run, so
that no output may replace it (:mod:`kinverify.io.plan`). A bad one is one line naming it (exit 2).

- SDFormat ``<include><uri>`` (:func:`sdf_for_drake`), resolved as SDFormat resolves it: relative
  to the *including* file's folder (``file://`` too) or absolute; ``package://NAME/...`` and
  ``model://NAME/...`` from ``--package`` or a folder ``NAME`` beside or above the file; a folder
  is a model folder (the file its ``model.config`` names, else ``model.sdf``). Recursively: a file
  including itself, or one that includes it (a → b → a), is refused. Drake resolves a relative URI
  against the current folder, not the including file's, and opens the files itself: it is given
  *snapshots* instead, the checked content of each file written to a private folder with its
  includes pointing at the other snapshots, so Drake reads only what was checked.
- MJCF (:func:`mjcf_files`, after :func:`kinverify.io.models.expand_includes`): ``<asset><model
  file>`` (with what that model includes and references, from its own folder), ``<flexcomp
  file>``, and mesh, skin, texture and height-field files, in ``<compiler meshdir>`` /
  ``texturedir`` / ``assetdir`` as MuJoCo looks for them.

Text files (included SDFormat or MJCF) share ``MAX_MODEL_BYTES`` with the model that includes
them; data files (meshes, textures...) share ``MAX_DATA_BYTES``.
"""

from __future__ import annotations

import atexit
import hashlib
import os
import re
import shutil
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path
from xml.sax.saxutils import escape

from kinverify.errors import InputError
from kinverify.io.formats import xml_parse
from kinverify.io.models import expand_includes
from kinverify.io.plan import note_input
from kinverify.io.read import InputFileError, check_file, read_bytes
from kinverify.pipeline.limits import MAX_DATA_BYTES, MAX_INCLUDE_DEPTH, MAX_LINKS, MAX_MODEL_BYTES


DATA_FILES = "all meshes, textures and other data files of the model"  # what shares ``MAX_DATA_BYTES``


class Budget:
    """Bytes still allowed: ``text`` for model files, ``data`` for meshes and images."""

    def __init__(self, used_text: int = 0) -> None:
        self.text, self.data = MAX_MODEL_BYTES - used_text, MAX_DATA_BYTES

    def check_data(self, path, label: str) -> int:
        """:func:`check_file` against the data budget, which it is charged: the size of ``path``."""
        size = check_file(path, label, max(self.data, 0), shared=(MAX_DATA_BYTES, DATA_FILES))
        self.data -= size
        return size


def package_file(filename: str, base: Path, packages: dict[str, str] | None = None) -> Path | None:
    """The path ``package://pkg/rel`` (or ``model://pkg/rel``) names: ``<PATH>/rel`` for
    ``packages`` ``{pkg: PATH}`` (``--package``), else ``<dir>/pkg/rel`` or ``<dir>/rel`` with
    ``<dir>`` named ``pkg``, for ``base`` and each folder above it; None when none exists."""
    package, _, rel = filename.split("://", 1)[1].partition("/")
    if packages and package in packages:
        given = Path(packages[package]).expanduser() / rel
        if given.exists():
            return given
    for folder in (base, *base.parents):
        for candidate in (folder / package / rel, folder / rel if folder.name == package else None):
            if candidate is not None and candidate.exists():
                return candidate
    return None


def _local(uri: str, base: Path, packages) -> Path | None:
    if uri.startswith(("package://", "model://")):
        return package_file(uri, base, packages)
    uri = uri[len("file://") :] if uri.startswith("file://") else uri
    return Path(uri) if Path(uri).is_absolute() else base / uri


def _read_text(path: Path, label: str, budget: Budget) -> bytes:
    try:
        data = read_bytes(path, label, max(budget.text, 0))
    except InputFileError as err:
        if err.too_large:
            raise InputError(
                f"{label}: {path}: the model with the files it includes is above the "
                f"{MAX_MODEL_BYTES // 2**20} MB kinverify reads (see docs/robustness.md)"
            ) from None
        raise
    budget.text -= len(data)
    return data


# --- SDFormat -------------------------------------------------------------------------------------

_SNAPSHOTS: list[str] = []  # the private folder of this process (removed at exit)


def _snapshot_folder() -> Path:
    if not _SNAPSHOTS:
        _SNAPSHOTS.append(tempfile.mkdtemp(prefix="kinverify-includes-"))
        atexit.register(shutil.rmtree, _SNAPSHOTS[0], True)
    return Path(_SNAPSHOTS[0])


def _model_folder_file(folder: Path, label: str, budget: Budget) -> Path:
    """The SDFormat file of a model folder: the one its ``model.config`` names, else ``model.sdf``."""
    config = folder / "model.config"
    if config.exists():
        root = xml_parse(_read_text(config, label, budget), config, label)
        name = (root.findtext("sdf") or "").strip()
        if name:
            return folder / name
    return folder / "model.sdf"


def sdf_for_drake(text: str, root: ET.Element, path, label: str = "--sdf", packages=None) -> str:
    """The SDFormat text to hand Drake: ``text`` itself when it includes nothing, else with every
    ``<include><uri>`` pointing at a checked snapshot (see the module doc); :class:`InputError`
    naming the file on a bad include."""
    if root.find(".//include") is None:
        return text
    budget = Budget(len(text.encode()))
    done: dict[str, tuple[str, int]] = {}  # resolved file -> its snapshot, the links it makes (with its includes)
    main = str(Path(path).resolve())
    text, links = _rewrite(text, root, Path(path).resolve().parent, [main], done, budget, label, packages, str(path))
    if links > MAX_LINKS:  # each <include> is a copy: a file included twice by a file included twice... multiplies
        raise InputError(
            f"{label}: {path} has {links} links with the models it includes, above the {MAX_LINKS} kinverify "
            "compares (see docs/robustness.md)"
        )
    return text


def _rewrite(
    text: str, root: ET.Element, base: Path, chain: list[str], done: dict, budget: Budget, label: str, packages, where: str
) -> tuple[str, int]:
    links = sum(1 for _ in root.iter("link"))
    for include in root.iter("include"):
        uri = (include.findtext("uri") or "").strip()
        if not uri:
            raise InputError(f"{label}: {where}: an <include> has no <uri>")
        target = _local(uri, base, packages)
        if target is None:
            raise InputError(
                f"{label}: {where}: <include> uri {uri!r}: no such model (package not found beside or above "
                "the file; give it with --package NAME=PATH)"
            )
        what = f"{label}: an <include> of {where} (uri {uri!r})"
        if target.is_dir():
            target = _model_folder_file(target, what, budget)
        try:
            key = str(target.resolve(strict=False))
        except (OSError, RuntimeError):  # a symbolic-link loop
            key = str(target)
        if key in chain:
            loop = " -> ".join(Path(p).name for p in [*chain[chain.index(key) :], key])
            raise InputError(f"{what}: the file includes itself ({loop}): SDFormat includes form a tree")
        if len(chain) > MAX_INCLUDE_DEPTH:
            raise InputError(f"{what}: <include> nested more than {MAX_INCLUDE_DEPTH} deep")
        if key not in done:
            data = _read_text(target, what, budget)
            sub = xml_parse(data, target, what)
            if sub.tag != "sdf":
                raise InputError(f"{what}: {target} is not SDFormat (root element <{sub.tag}>, expected <sdf>)")
            inner, inner_links = _rewrite(
                data.decode("utf-8", "replace"),
                sub,
                target.resolve().parent,
                [*chain, key],
                done,
                budget,
                label,
                packages,
                str(target),
            )
            snap = _snapshot_folder() / f"{hashlib.sha256(inner.encode()).hexdigest()[:16]}-{target.name}"
            snap.write_text(inner, encoding="utf-8")
            done[key] = (str(snap), inner_links)
        links += done[key][1]
        if links > MAX_LINKS:
            break
        pattern = re.compile(r"<uri>\s*" + re.escape(escape(uri)) + r"\s*</uri>")
        replacement = f"<uri>{escape(done[key][0])}</uri>"
        text = pattern.sub(lambda _m, r=replacement: r, text)  # type: ignore[misc]  # mypy cannot type a lambda with defaults
    return text, links


def sdf_meshes(root: ET.Element, path, packages=None) -> None:
    """The mesh files an SDFormat file names that exist, recorded as inputs (Drake's plant is built
    without a scene graph and never opens them, but no output may replace them)."""
    base = Path(path).resolve().parent
    for mesh in root.iter("mesh"):
        uri = (mesh.findtext("uri") or "").strip()
        found = _local(uri, base, packages) if uri else None
        if found is not None and found.is_file():
            note_input(found, f"a mesh {path} references:")


# --- MJCF -----------------------------------------------------------------------------------------

TEXTURE_FILES = ("file", "fileright", "fileleft", "fileup", "filedown", "filefront", "fileback")


def _folders(root: ET.Element, base: Path) -> tuple[Path, Path]:
    """MuJoCo's mesh and texture folders (``<compiler meshdir texturedir assetdir>``)."""
    meshdir = texturedir = ""
    for compiler in root.iter("compiler"):
        asset = compiler.get("assetdir")
        meshdir = compiler.get("meshdir", asset if asset is not None else meshdir)
        texturedir = compiler.get("texturedir", asset if asset is not None else texturedir)
    return base / meshdir, base / texturedir


def mjcf_files(root: ET.Element, path, budget: Budget | None = None, chain: tuple[str, ...] = ()) -> dict:
    """Every file MuJoCo would open for ``root`` (the file ``path``, its includes expanded), checked
    and recorded: ``{element: absolute path}`` for the elements whose file exists (a mesh, texture,
    skin or height field that is absent is left to the caller, which drops it). ``<asset><model
    file>`` is followed into its own includes and files."""
    budget = budget or Budget()
    base = Path(path).resolve().parent
    chain = chain or (str(Path(path).resolve()),)
    meshdir, texturedir = _folders(root, base)
    found: dict = {}
    wanted = [(el, "file", meshdir) for el in root.iter("mesh") if el.get("file")]
    wanted += [(el, "file", meshdir) for el in root.iter("skin") if el.get("file")]
    wanted += [(el, "file", meshdir) for el in root.iter("flexcomp") if el.get("file")]
    wanted += [(el, "file", texturedir) for el in root.iter("hfield") if el.get("file")]
    wanted += [(el, a, texturedir) for el in root.iter("texture") for a in TEXTURE_FILES if el.get(a)]
    for el, attribute, folder in wanted:
        name = el.get(attribute)
        if not name:  # never: ``wanted`` keeps the attributes set
            continue
        target = Path(name) if Path(name).is_absolute() else folder / name
        try:
            os.stat(target)
        except FileNotFoundError:
            continue  # absent (or a link to nothing): the caller drops it
        except OSError:
            pass  # a symbolic-link loop...: refused by the check, naming the file
        budget.check_data(target, f"{path}: <{el.tag} {attribute}={name!r}>")
        found[(el, attribute)] = target.resolve()
    for el in root.iter("model"):
        name = el.get("file")
        if not name:
            continue
        target = Path(name) if Path(name).is_absolute() else base / name
        what = f"{path}: <model file={name!r}>"
        key = str(target.resolve())
        if key in chain:
            raise InputError(f"{what}: the model includes itself: MuJoCo would never end")
        data = _read_text(target, what, budget)
        sub = xml_parse(data, target, what)
        if sub.tag != "mujoco":
            raise InputError(f"{what}: {target} is not MJCF (root element <{sub.tag}>, expected <mujoco>)")
        sub, _ = expand_includes(sub, target, what, len(data))
        mjcf_files(sub, target, budget, (*chain, key))
        found[(el, "file")] = target.resolve()
    return found
