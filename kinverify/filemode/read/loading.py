"""Reading a user's URDF and MJCF safely, and cleaning them so every library loads them without meshes.

Untrusted XML goes through defusedxml first: a DTD with entities (external or an expansion bomb)
is refused before any library sees the file. Mesh references are resolved where the files exist
(``package://pkg/...`` looked up beside or above the model's folder, ROS style; ``file://``,
relative and absolute paths) and rewritten as absolute paths; meshes whose files are absent (real
files are usually copied without them) are dropped: URDF ``<visual>``/``<collision>`` elements
with such a ``<mesh>``, MJCF geoms using such a mesh asset (primitives fitted to one too), and the asset. File textures are
always dropped (they are visual only).
"""

from __future__ import annotations

import warnings
import xml.etree.ElementTree as ET
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path

import mujoco

from kinverify.errors import InputError, library_reason
from kinverify.filemode.read.stated import attribute, class_defaults
from kinverify.filemode.read.xacro import compile_xacro, is_xacro
from kinverify.io.formats import xml_parse
from kinverify.io.models import check_mjcf_numbers, check_urdf_numbers, check_urdf_tree, expand_includes
from kinverify.io.read import read_bytes
from kinverify.io.references import Budget, mjcf_files, package_file, sdf_for_drake, sdf_meshes
from kinverify.pipeline.limits import MAX_JOINTS, MAX_LINKS, MAX_MODEL_BYTES


@dataclass(frozen=True)
class LoadedFile:
    """A model file after safe parsing and cleaning: ``text`` is what the backends load."""

    path: str
    kind: str  # "urdf", "mjcf" or "sdf"
    original: str
    text: str
    name: str
    warnings: tuple[str, ...] = field(default_factory=tuple)
    unknown_mass: tuple[str, ...] = ()  # MJCF bodies whose mass came in part from a dropped mesh
    unknown_com: tuple[str, ...] = ()  # MJCF bodies whose dropped meshes stated their mass: mass known, not where

    @cached_property
    def tree(self) -> ET.Element:
        """``text`` parsed (once): what the later stages read the file's statements from."""
        return ET.fromstring(self.text)


def read_xml(path: str, kind: str, text: str | None = None) -> tuple[str, ET.Element]:
    """The file's text and its root element; :class:`InputError` on anything unsafe or wrong
    (:mod:`kinverify.io`: a bounded read of a regular file, bounded nesting, a URDF that is one
    tree with finite poses, an MJCF's includes expanded). ``text``: what the file compiled to
    (xacro), checked the same way under the file's name."""
    label = f"--{kind}"
    compiled = text is not None
    if text is None:
        data = read_bytes(path, label)
        try:
            text = data.decode("utf-8-sig")
        except UnicodeDecodeError as err:
            raise InputError(f"{label}: cannot read {path}: not UTF-8 text (byte {err.start})") from None
    elif len(text.encode()) > MAX_MODEL_BYTES:
        raise InputError(
            f"{label}: {path} is {len(text.encode()) / 2**20:.1f} MB, above the {MAX_MODEL_BYTES // 2**20} MB "
            "kinverify reads (see docs/robustness.md)"
        )
    root = xml_parse(text.encode(), path, label)
    expected = {"urdf": "robot", "mjcf": "mujoco", "sdf": "sdf"}[kind]
    if root.tag != expected:
        names = {"robot": "a URDF", "mujoco": "an MJCF", "sdf": "an SDFormat file"}
        hint = names.get(root.tag, f"a <{root.tag}> document")
        raise InputError(f"--{kind}: {path} is {hint}, not {names[expected]} (root element <{root.tag}>, expected <{expected}>)")
    if kind == "urdf" and (compiled or not is_xacro(path, text)):  # a xacro source is checked once compiled
        check_urdf_tree(root, path, label)
        check_urdf_numbers(root, path, label)
    elif kind == "mjcf":
        root, included = expand_includes(root, path, label, len(text.encode()))
        if len(included) > 1:
            text = ET.tostring(root, encoding="unicode")
        check_mjcf_numbers(root, path, label)
    check_supported(root, kind, path)
    return text, root


MOVABLE = {"urdf": ("revolute", "continuous", "prismatic"), "mjcf": ("hinge", "slide")}
PLANAR_URDF = ("planar",)  # a planar root (three coordinates in a plane) is not compared


def check_supported(root: ET.Element, kind: str, path) -> None:
    """What kinverify cannot compare yet, refused in one place with one line: a URDF whose root
    joint is planar, and models above the documented size (:mod:`kinverify.pipeline.limits`).
    A floating root is compared (:mod:`kinverify.filemode.align.floating`)."""
    if kind == "urdf":
        links = root.findall("link")
        joints = root.findall("joint")
        children = {c.get("link") for j in joints for c in j.findall("child")}
        roots = {el.get("name") for el in links} - children
        for joint in joints:
            parent = joint.find("parent")
            if joint.get("type") in PLANAR_URDF and parent is not None and parent.get("link") in roots:
                raise InputError(
                    f"--urdf: {path}: joint {joint.get('name')!r} is {joint.get('type')}: unsupported: planar base "
                    f"(kinverify compares fixed and floating bases; make the root joint fixed or floating)"
                )
        bodies, movable = len(links), sum(j.get("type") in MOVABLE["urdf"] for j in joints)
    elif kind == "sdf":
        bodies = sum(1 for _ in root.iter("link"))
        movable = sum(1 for j in root.iter("joint") if j.get("type") in ("revolute", "prismatic", "continuous"))
    else:
        # bodies MuJoCo will make: <body> elements, plus those <composite>/<flexcomp> generate
        # (count "nx ny nz"), all times each <replicate> count (an upper bound)
        bodies = sum(1 for _ in root.iter("body"))
        bodies += sum(_product(el.get("count")) for tag in ("composite", "flexcomp") for el in root.iter(tag))
        movable = sum(1 for j in root.iter("joint") if j.get("type", "hinge") in MOVABLE["mjcf"])
        for rep in root.iter("replicate"):
            bodies *= _product(rep.get("count"))
    what = "bodies" if kind == "mjcf" else "links"
    if bodies > MAX_LINKS or movable > MAX_JOINTS:
        count, limit, noun = (bodies, MAX_LINKS, what) if bodies > MAX_LINKS else (movable, MAX_JOINTS, "movable joints")
        raise InputError(f"--{kind}: {path} has {count} {noun}, above the {limit} kinverify compares (see docs/robustness.md)")


def _product(counts: str | None) -> int:
    """Product of the whole numbers in a ``count`` attribute (1 when absent or unreadable: MuJoCo
    reports a bad count itself)."""
    out = 1
    for word in (counts or "").split():
        try:
            out *= max(1, int(word))
        except ValueError:
            return 1
    return out


def resolve_asset(filename: str, base: Path, packages: dict[str, str] | None = None, budget: Budget | None = None) -> Path | None:
    """The file a mesh reference names, if it exists: ``package://pkg/rel`` as ``<PATH>/rel`` for
    ``packages`` ``{pkg: PATH}`` (``--package``), else as ``<dir>/pkg/rel`` or ``<dir>/rel`` with
    ``<dir>`` named ``pkg``, for the model's folder and each folder above it; ``file://`` and plain
    paths relative to ``base``. None when absent. ``budget``: what the model's meshes may take together."""
    if filename.startswith("package://"):
        found = package_file(filename, base, packages)
        return _read_asset(found, budget) if found is not None and found.is_file() else None
    filename = filename[len("file://") :] if filename.startswith("file://") else filename
    candidate = Path(filename) if Path(filename).is_absolute() else base / filename
    return _read_asset(candidate, budget) if candidate.is_file() else None


def _read_asset(path: Path, budget: Budget | None = None) -> Path:
    """An asset the model references is an input of the run: no output may replace it. The
    libraries read it themselves: a regular file whose size is exact, bounded here."""
    path = path.resolve()
    (budget or Budget()).check_data(path, "a mesh the model references")
    return path


_GIVEN: dict[str, dict[str, str]] = {"packages": {}, "xacro_args": {}}  # set by :func:`given_packages`


@contextmanager
def given_packages(packages: dict[str, str] | None = None, xacro_args: dict[str, str] | None = None):
    """Within this block, every :func:`load_urdf` (also file mode's) resolves packages from
    ``packages`` (``--package``) and compiles xacro with ``xacro_args`` (``--xacro-arg``)."""
    before = dict(_GIVEN)
    _GIVEN.update(packages=dict(packages or {}), xacro_args=dict(xacro_args or {}))
    try:
        yield
    finally:
        _GIVEN.update(before)


def load_urdf(
    path: str, keep_meshes: bool = True, packages: dict[str, str] | None = None, xacro_args: dict[str, str] | None = None
) -> LoadedFile:
    """URDF without the mesh visuals/collisions whose files are absent (kinematics and inertials
    are untouched); meshes that exist are kept with absolute paths (``keep_meshes=False``: none).
    A xacro file (``.xacro``, or the xacro namespace) is compiled first (:mod:`kinverify.filemode.read.xacro`)
    with ``packages`` (``--package NAME=PATH``) and ``xacro_args`` (``--xacro-arg NAME=VALUE``);
    ``original`` is then the compiled URDF."""
    packages = _GIVEN["packages"] if packages is None else packages
    given_here, xacro_args = xacro_args, _GIVEN["xacro_args"] if xacro_args is None else xacro_args
    text, root = read_xml(path, "urdf")
    compiled: list[str] = []
    if is_xacro(path, text):
        text, compiled = compile_xacro(path, packages, xacro_args)
        text, root = read_xml(path, "urdf", text)
        compiled.insert(0, f"URDF compiled from xacro ({Path(path).name})")
    elif given_here:  # arguments for this very file (a block's arguments are for its xacro files)
        raise InputError(f"--xacro-arg: {path} is not a xacro file (no .xacro suffix, no xacro namespace)")
    dropped = kept = present = 0
    budget = Budget()
    base = Path(path).resolve().parent
    for link in root.iter("link"):
        for tag in ("visual", "collision"):
            for el in list(link.findall(tag)):
                mesh = el.find("geometry/mesh")
                if mesh is None:
                    continue
                found = resolve_asset(mesh.get("filename", ""), base, packages, budget)  # an input even when not loaded
                if found is None or not keep_meshes:
                    link.remove(el)
                    dropped += found is None
                    present += found is not None
                else:
                    mesh.set("filename", str(found))
                    kept += 1
    warnings = tuple(compiled) + (
        (
            f"URDF: {dropped} mesh visual/collision elements skipped, their files are absent "
            "(meshes are not needed for kinematics and dynamics)",
        )
        if dropped
        else ()
    )
    if kept:
        warnings += (f"URDF: {kept} mesh references resolved to existing files and kept",)
    if present:
        warnings += (
            f"URDF: {present} mesh visual/collision elements not loaded, their files present (meshes are not "
            "needed for kinematics and dynamics)",
        )
    cleaned = ET.tostring(root, encoding="unicode")
    return LoadedFile(str(path), "urdf", text, cleaned, root.get("name") or Path(path).stem, warnings)


def load_sdf(path: str, packages: dict[str, str] | None = None) -> LoadedFile:
    """An SDFormat file, read safely. Drake's plant is built without a scene graph, so it never
    opens the meshes (nor any other geometry; they are inputs of the run all the same); the files
    it ``<include>``s are checked and handed to Drake as snapshots (``text``:
    :func:`kinverify.io.references.sdf_for_drake`)."""
    packages = _GIVEN["packages"] if packages is None else packages
    text, root = read_xml(path, "sdf")
    model = root.find("model")
    name = (model.get("name") if model is not None else None) or Path(path).stem
    sdf_meshes(root, path, packages)
    return LoadedFile(str(path), "sdf", text, sdf_for_drake(text, root, path, "--sdf", packages), name)


def load_mjcf(path: str, keep_meshes: bool = True) -> LoadedFile:
    """MJCF with mesh geoms, mesh assets and file textures removed from the XML tree, then checked
    by compiling it with MuJoCo (``MjSpec``).

    The tree is edited directly rather than written back with ``MjSpec.to_xml()``, which prints
    numbers to 6 significant digits and would round the model. A file MuJoCo refuses is still
    returned, with a warning, so the refusal is reported as a finding."""
    _route_mujoco_warnings(mujoco)
    text, root = read_xml(path, "mjcf")
    name = root.get("model") or Path(path).stem
    found = mjcf_files(root, path)  # every file MuJoCo would open, checked, an input of the run
    kept, present = _resolve_mesh_assets(root, found, keep_meshes)
    dropped, fitted, massless, approximate = _drop_meshes(root, kept)
    fits = f" ({fitted} of them primitives fitted to a mesh, whose size came from it)" if fitted else ""
    warnings = (
        [
            f"MJCF: {dropped} mesh geoms{fits} and their assets skipped, their files are absent"
            if not present
            else f"MJCF: {dropped} mesh geoms{fits} and their assets skipped ({present} of their files present, not loaded: "
            "meshes are not needed for kinematics and dynamics)"
        ]
        if dropped
        else []
    )
    if kept:
        warnings.append(f"MJCF: {len(kept)} mesh assets resolved to existing files and kept")
    if massless:
        warnings.append(
            f"MJCF bodies without <inertial> whose mass came from their (absent) meshes, not compared (a body "
            f"left with no mass at all holds {PLACEHOLDER_MASS:g} kg so that MuJoCo loads it): {', '.join(massless)}"
        )
    cleaned = ET.tostring(root, encoding="unicode")
    try:
        spec = mujoco.MjSpec.from_string(cleaned)
        spec.compile()
    except ValueError as err:
        warnings.append(f"mujoco cannot compile the MJCF (absent meshes dropped): {library_reason(err)}")
    if approximate:
        warnings.append(
            "MJCF bodies whose (absent) mesh geoms state their mass: the mass is compared, not the centre of "
            f"mass and inertia: {', '.join(approximate)}"
        )
    return LoadedFile(str(path), "mjcf", text, cleaned, name, tuple(warnings), tuple(massless), tuple(approximate))


def _route_mujoco_warnings(mujoco) -> None:
    """MuJoCo's default warning handler prints to stdout and appends to ``MUJOCO_LOG.TXT`` in the
    current folder (e.g. "XML contains a 'NaN'"): a user's folder is not MuJoCo's log. Its
    warnings become Python warnings instead (once per process, unless a handler is set)."""
    if mujoco.get_mju_user_warning() is None:
        mujoco.set_mju_user_warning(_mujoco_warning)


def _mujoco_warning(message: str) -> None:
    warnings.warn(f"MuJoCo: {message}", UserWarning, stacklevel=2)


def _resolve_mesh_assets(root: ET.Element, found: dict, keep: bool = True) -> tuple[set[str], int]:
    """Names of the mesh assets kept (their files exist, ``keep``) and how many exist not kept: each file
    found (:func:`~kinverify.io.references.mjcf_files`) rewritten as an absolute path, so the text
    loads from anywhere (``<model>`` and ``<flexcomp>`` files too)."""
    kept, present = set(), 0
    meshes = {id(mesh) for asset in root.iter("asset") for mesh in asset.findall("mesh")}
    for (element, name), target in found.items():
        if element.tag in ("model", "flexcomp"):
            element.set(name, str(target))
        elif id(element) in meshes:
            if keep:
                kept.add(element.get("name") or Path(element.get("file")).stem)
                element.set("file", str(target))
            else:  # present, not loaded
                present += 1
    return kept, present


PLACEHOLDER_MASS, PLACEHOLDER_INERTIA = 1e-6, 1e-12  # kg, kg·m²: a body whose mass was all in absent meshes


def _mesh_of(geom: ET.Element, parents: dict, defaults: dict) -> tuple[str | None, bool]:
    """The mesh a geom uses (its own ``mesh`` or its default class's), and whether the geom is a
    primitive fitted to that mesh (``type="capsule" mesh="..."``: MuJoCo sizes it from the mesh;
    no type at all is MuJoCo's default, a sphere, fitted the same way)."""
    mesh = attribute(geom, "mesh", parents, defaults)
    kind = attribute(geom, "type", parents, defaults)
    return mesh, mesh is not None and kind != "mesh"


def _weighs(geom: ET.Element, parents: dict, defaults: dict) -> bool:
    """Whether a geom adds mass to its body (``mass`` > 0, or density > 0 when no mass is given)."""
    mass = attribute(geom, "mass", parents, defaults)
    value = mass if mass is not None else attribute(geom, "density", parents, defaults)
    try:
        return value is None or float(value) > 0
    except ValueError:
        return True


def _drop_meshes(root: ET.Element, kept: set[str] | frozenset[str] = frozenset()) -> tuple[int, int, list[str], list[str]]:
    """Remove geoms using a mesh not in ``kept`` (named on the geom or given by its default class;
    a primitive fitted to such a mesh too: its size came from the mesh), those mesh assets and the default classes' references to them, skin/hfield assets and file
    textures (and references to them). Also returns the bodies whose mass came in part from a
    dropped mesh (no ``<inertial>``, or ``inertiafromgeom="true"``): their mass is not known; and
    those whose dropped meshes all state their ``mass``: kept as points, so the body's mass is known,
    not its centre of mass and inertia. Returns (geoms dropped, of which fitted primitives, the
    bodies whose mass is not known, those whose mass is known but not where)."""
    parents = {child: parent for parent in root.iter() for child in parent}
    defaults = class_defaults(root, "geom")
    compiler = root.find("compiler")
    from_geoms = compiler is not None and compiler.get("inertiafromgeom") == "true"
    never = compiler is not None and compiler.get("inertiafromgeom") == "false"  # geoms give no body its mass
    dropped, fitted, massless, approximate, gone_geoms, gone_tex = 0, 0, [], [], set(), set()
    for geom in list(root.iter("geom")):
        if parents[geom].tag == "default":
            continue
        mesh, primitive = _mesh_of(geom, parents, defaults)
        if mesh is not None and mesh not in kept:
            fitted += primitive
            body = parents[geom]
            weighs = _weighs(geom, parents, defaults)
            mass = attribute(geom, "mass", parents, defaults)
            body.remove(geom)
            dropped += 1
            gone_geoms.add(geom.get("name"))
            if body.tag != "body" or not weighs or never or not (from_geoms or body.find("inertial") is None):
                continue
            if mass is not None:  # its mass is stated: kept, as a point at the geom's frame (where in the mesh is not known)
                point = ET.SubElement(
                    body,
                    "geom",
                    {k: v for k, v in geom.attrib.items() if k in ("pos", "quat", "name")}
                    | {"mass": mass, "type": "sphere", "size": "1e-4", "contype": "0", "conaffinity": "0", "group": "5"},
                )
                parents[point] = body
                approximate.append(body.get("name") or "?")
            elif (body.get("name") or "?") not in massless:
                massless.append(body.get("name") or "?")
    for body in root.iter("body"):  # massless now: MuJoCo refuses a moving body without mass
        if (
            (body.get("name") or "?") in massless
            and body.find("inertial") is None
            and not any(_weighs(g, parents, defaults) for g in body.findall("geom"))
        ):
            ET.SubElement(
                body, "inertial", pos="0 0 0", mass=repr(PLACEHOLDER_MASS), diaginertia=" ".join([repr(PLACEHOLDER_INERTIA)] * 3)
            )
    for geom in root.iter("geom"):  # a default class naming a dropped mesh: the mesh is gone
        if parents[geom].tag == "default" and geom.get("mesh") is not None and geom.get("mesh") not in kept:
            del geom.attrib["mesh"]
            if geom.get("type") == "mesh":
                del geom.attrib["type"]
    for asset in root.iter("asset"):
        for el in list(asset):
            kept_mesh = el.tag == "mesh" and (el.get("name") or Path(el.get("file") or "").stem) in kept
            from_file = any(k.startswith("file") for k in el.attrib)  # file, or a cube's fileright, fileup, ...
            if (el.tag in ("mesh", "skin", "hfield") and not kept_mesh) or (el.tag == "texture" and from_file):
                if el.tag == "texture":  # unnamed: MuJoCo names it after its file
                    gone_tex.add(el.get("name") or Path(el.get("file") or "").stem)
                asset.remove(el)
    for material in root.iter("material"):
        if material.get("texture") in gone_tex:
            del material.attrib["texture"]
    for contact in root.iter("contact"):
        for pair in list(contact):
            if pair.get("geom1") in gone_geoms or pair.get("geom2") in gone_geoms:
                contact.remove(pair)
    return dropped, fitted, massless, [b for b in dict.fromkeys(approximate) if b not in massless]
