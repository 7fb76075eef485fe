"""Reading a user's URDF and MJCF safely, and cleaning them so every library loads them without meshes.

Untrusted XML goes through defusedxml first: a DTD with entities (external or an expansion bomb)
is refused before any library sees the file. Meshes are dropped (real files are usually copied
without them): URDF ``<visual>``/``<collision>`` elements with a ``<mesh>``; MJCF mesh geoms,
mesh assets and file textures through MuJoCo's ``MjSpec`` editing API.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import defusedxml
import defusedxml.ElementTree as DET

from ..errors import InputError


@dataclass(frozen=True)
class LoadedFile:
    """A model file after safe parsing and cleaning: ``text`` is what the backends load."""

    path: str
    kind: str  # "urdf" or "mjcf"
    original: str
    text: str
    name: str
    warnings: tuple[str, ...] = field(default_factory=tuple)


def read_xml(path: str, kind: str) -> tuple[str, ET.Element]:
    """The file's text and its root element; :class:`InputError` on anything unsafe or wrong."""
    p = Path(path)
    if not p.is_file():
        raise InputError(f"--{kind}: {path} is not a file")
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        raise InputError(f"--{kind}: cannot read {path}: {err}") from None
    try:
        root = DET.fromstring(text.encode(), forbid_dtd=False, forbid_entities=True, forbid_external=True)
    except defusedxml.EntitiesForbidden:
        raise InputError(f"--{kind}: {path} declares XML entities (external entities and entity expansion "
                         "are refused for safety; remove the DTD)") from None
    except (defusedxml.DTDForbidden, defusedxml.ExternalReferenceForbidden, defusedxml.NotSupportedError) as err:
        raise InputError(f"--{kind}: {path}: unsafe XML refused ({type(err).__name__})") from None
    except ET.ParseError as err:
        raise InputError(f"--{kind}: {path} is not XML: {err}") from None
    expected = {"urdf": "robot", "mjcf": "mujoco"}[kind]
    if root.tag != expected:
        hint = {"robot": "a URDF", "mujoco": "an MJCF"}.get(root.tag, f"a <{root.tag}> document")
        raise InputError(f"--{kind}: {path} is {hint}, not {'a URDF' if kind == 'urdf' else 'an MJCF'} "
                         f"(root element <{root.tag}>, expected <{expected}>)")
    return text, root


def load_urdf(path: str) -> LoadedFile:
    """URDF without mesh visuals/collisions (kinematics and inertials are untouched)."""
    text, root = read_xml(path, "urdf")
    dropped = 0
    for link in root.iter("link"):
        for tag in ("visual", "collision"):
            for el in list(link.findall(tag)):
                if el.find("geometry/mesh") is not None:
                    link.remove(el)
                    dropped += 1
    warnings = (f"URDF: {dropped} mesh visual/collision elements skipped (meshes are not needed for kinematics "
                "and dynamics)",) if dropped else ()
    cleaned = ET.tostring(root, encoding="unicode")
    return LoadedFile(str(path), "urdf", text, cleaned, root.get("name") or Path(path).stem, warnings)


def load_mjcf(path: str) -> LoadedFile:
    """MJCF with mesh geoms, mesh assets and file textures removed through ``mujoco.MjSpec``.

    A file MuJoCo cannot parse is still returned (``text`` = the original) with a warning, so the
    other parser can be tried and the refusal reported as a finding."""
    import mujoco

    text, root = read_xml(path, "mjcf")
    name = root.get("model") or Path(path).stem
    try:
        spec = mujoco.MjSpec.from_file(str(path))
    except ValueError as err:
        return LoadedFile(str(path), "mjcf", text, text, name, (f"mujoco refused the MJCF: {_first_line(err)}",))
    dropped = 0
    for geom in list(spec.geoms):
        if geom.type == mujoco.mjtGeom.mjGEOM_MESH:
            spec.delete(geom)
            dropped += 1
    for mesh in list(spec.meshes):
        spec.delete(mesh)
    for tex in list(spec.textures):
        if tex.file:
            spec.delete(tex)
    warnings = [f"MJCF: {dropped} mesh geoms and their assets skipped"] if dropped else []
    try:
        spec.compile()
        cleaned = spec.to_xml()
    except ValueError as err:
        warnings.append(f"mujoco cannot compile the MJCF without its meshes: {_first_line(err)}")
        cleaned = text
    return LoadedFile(str(path), "mjcf", text, cleaned, name, tuple(warnings))


def _first_line(err: Exception) -> str:
    lines = str(err).strip().splitlines()
    return lines[0] if lines else type(err).__name__


