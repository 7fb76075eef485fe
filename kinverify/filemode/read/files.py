"""Each file read once: loaded safely (:mod:`~kinverify.filemode.read.loading`), cleaned for the
libraries, its floating base decided, and described by the library that reads it best (URDF:
Pinocchio, or MuJoCo's URDF import when Pinocchio refuses it; MJCF: MuJoCo; SDFormat: Drake, its
only reader). A library's refusal is a finding.

File mode compares two *sides*: the first is read like a URDF (its floating root decided against
the second's free bodies), the second like an MJCF (its free bodies held at the identity). An
SDFormat file takes either side (:data:`SIDES`): after a URDF it is the second, before an MJCF the
first; :func:`read_sdf` gives it the same shape as :func:`read_urdf` or :func:`read_mjcf`."""

from __future__ import annotations

import dataclasses
import math
import xml.etree.ElementTree as ET

from kinverify.backends.mujoco_ import urdf_for_mujoco
from kinverify.errors import InputError, library_reason
from kinverify.filemode.align.floating import UrdfBase, decide, fixed_urdf, floating_urdf, urdf_base
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.describe_mjcf import describe_mjcf, free_joint_values
from kinverify.filemode.read.describe_sdf import describe_sdf
from kinverify.filemode.read.describe_usd import describe_usd, pose_mismatches
from kinverify.filemode.read.describe_urdf import describe_urdf
from kinverify.backends.usd_stage import UsdRobot, read_robot
from kinverify.filemode.read.loading import LoadedFile, load_mjcf, load_sdf, load_urdf
from kinverify.filemode.read.model import ModelDesc
from kinverify.filemode.read.prepare import fix_free_bases, prepare_urdf
from kinverify.filemode.read.stated import mjcf_joint_values, urdf_joint_values, urdf_links_without_inertial

LABELS = {"urdf": "URDF", "mjcf": "MJCF", "sdf": "SDF", "usd": "USD"}


def sides(urdf: str | None, mjcf: str | None, sdf: str | None, usd: str | None = None) -> tuple[tuple[str, str], tuple[str, str]]:
    """The two sides ``((kind, path), (kind, path))`` of a pair of files: URDF before MJCF, an
    SDFormat or USD file after a URDF or before an MJCF (SDFormat before USD)."""
    given = [(k, p) for k, p in (("urdf", urdf), ("sdf", sdf), ("usd", usd), ("mjcf", mjcf)) if p]
    if len(given) != 2:
        raise InputError("file mode compares two files: give two of --urdf, --mjcf, --sdf and --usd")
    return given[0], given[1]


def read_urdf(path: str, findings: list, free=()):
    """The loaded URDF, its prepared text, its description, the library that read it and the
    floating-base decision (:class:`BaseDecision`) against the MJCF's ``free`` top-level bodies.
    The text and description have a floating root fixed (at the identity when both files float:
    the base coordinates at zero; else at its origin)."""
    loaded = load_urdf(path)
    base = urdf_base(loaded.text)
    floating, kind, message = decide(base, list(free))
    fixed = fixed_urdf(loaded.text, keep_origin=not floating)
    decision = BaseDecision(
        floating, kind, message, base, list(free), prepare_urdf(floating_urdf(loaded.text)) if floating else ""
    )
    text = prepare_urdf(fixed)
    try:
        return loaded, text, with_statements(describe_urdf(fixed), loaded), "pinocchio", decision
    except (ValueError, RuntimeError) as err:
        findings.append(
            finding(
                "parser_refused",
                f"Pinocchio refuses the URDF: {library_reason(err)}; read with MuJoCo's URDF import instead",
                {"file": "URDF", "library": "pinocchio"},
            )
        )
    try:
        desc = dataclasses.replace(describe_mjcf(urdf_for_mujoco(text)), kind="urdf", library="mujoco (URDF import)")
        return loaded, text, with_statements(desc, loaded), "mujoco", decision
    except ValueError as err:
        findings.append(
            finding(
                "parser_refused",
                f"MuJoCo's URDF import refuses the URDF too: {library_reason(err)}; read with Drake's URDF parser instead",
                {"file": "URDF", "library": "mujoco"},
            )
        )
        refusal = library_reason(err)
    try:
        return loaded, text, with_statements(describe_sdf(text, "urdf"), loaded), "drake", decision
    except (RuntimeError, ValueError) as err:
        raise InputError(f"--urdf: no library can load {path}: {refusal}; Drake: {library_reason(err)}") from None


@dataclasses.dataclass
class BaseDecision:
    """Whether the base pose is compared as coordinates, and the finding that says why (see
    :func:`kinverify.filemode.align.floating.decide`); ``urdf_text``: the URDF with its floating root
    (one added above the root link when the URDF left it unstated), for the libraries."""

    floating: bool
    kind: str
    message: str
    urdf: UrdfBase
    free: list
    urdf_text: str = ""


def read_mjcf(path: str, findings: list):
    """The loaded MJCF, its prepared text (free base fixed), its description and the fixed bodies.
    A mesh file MuJoCo cannot read is dropped like an absent one (a warning says which)."""
    loaded = load_mjcf(path)
    for attempt in (0, 1):
        text, free = fix_free_bases(loaded.text)
        try:
            desc = with_statements(describe_mjcf(text), loaded)
            if free:  # the free joints' own values, from the file as written (the description fixes them)
                desc = dataclasses.replace(desc, free_joint=free_joint_values(loaded.text))
            return loaded, text, desc, free
        except ValueError as err:
            if attempt == 0 and "mesh assets resolved" in " ".join(loaded.warnings):
                findings.append(
                    finding(
                        "parser_refused",
                        f"MuJoCo cannot read a mesh of the MJCF ({library_reason(err)}): meshes "
                        "dropped (they do not change kinematics or dynamics)",
                        {"file": "MJCF", "library": "mujoco"},
                    )
                )
                loaded = load_mjcf(path, keep_meshes=False)
                continue
            raise InputError(f"--mjcf: MuJoCo cannot load {path}: {library_reason(err)}") from None


def with_statements(desc: ModelDesc, loaded: LoadedFile) -> ModelDesc:
    """``desc`` told what its file states and what it leaves to the format's default
    (:mod:`~kinverify.filemode.read.stated`): each joint's stated values, the links that state no
    inertial, the MJCF bodies whose mass came from an absent mesh."""
    if loaded.kind == "urdf":
        values, desc.no_inertial = urdf_joint_values(loaded.tree), urdf_links_without_inertial(loaded.tree)
    else:
        values = mjcf_joint_values(loaded.tree)
    for j in desc.joints:
        stated = values.get(j.name)
        if stated is not None and loaded.kind == "mjcf" and j.effort is not None and math.isfinite(j.effort):
            stated = stated | {"effort"}
        j.stated = stated
    for b in desc.bodies:
        b.mass_known = b.name not in loaded.unknown_mass
        b.com_known = b.name not in loaded.unknown_com
    return desc


def read_sdf(path: str, findings: list, free=None):
    """The loaded SDFormat file, read by Drake, shaped as the side it takes: ``free`` None, the
    second side (after a URDF): like :func:`read_mjcf`, ``(loaded, text, desc, free bodies)``;
    else the first (before an MJCF with ``free`` top-level bodies): like :func:`read_urdf`,
    ``(loaded, text, desc, "drake", BaseDecision)``. A free body (a link with no joint to the
    world) is held at the identity, as an MJCF's free joint is."""
    loaded = load_sdf(path)
    try:
        desc = describe_sdf(loaded.text)
    except (RuntimeError, ValueError) as err:
        raise InputError(f"--sdf: Drake cannot load {path}: {library_reason(err)}") from None
    roots = sdf_free_bodies(loaded.text)
    if free is None:
        return loaded, loaded.text, desc, roots
    root = roots[0] if roots else next(iter(desc.frames), "")
    base = UrdfBase("floating" if roots else "fixed", root, "(free body)" if roots else None, root)
    floating, kind, message = decide(base, list(free))
    message = message.replace("the URDF's root joint (free body) is floating", f"the SDF's link {root} is a free body")
    return (
        loaded,
        loaded.text,
        desc,
        "drake",
        BaseDecision(floating, kind, message, base, list(free), loaded.text if floating else ""),
    )


def load_usd(path: str) -> tuple[LoadedFile, UsdRobot]:
    """The USD file read by pxr (every layer checked first: :mod:`kinverify.backends.usd_stage`) as a
    :class:`LoadedFile` whose text is the path (pxr resolves its layers from there), and its articulation."""
    robot = read_robot(path)
    warnings = tuple(
        f"USD: layer {a} is absent (its prims are read without it: meshes are not needed for kinematics and dynamics)"
        for a in robot.absent
    )
    name = robot.names[robot.root] if not robot.stage.GetDefaultPrim() else robot.stage.GetDefaultPrim().GetName()
    return LoadedFile(str(path), "usd", str(path), str(path), name, warnings), robot


def read_usd(path: str, findings: list, free=None):
    """The USD file read by pxr, shaped as the side it takes (as :func:`read_sdf`): ``free`` None, the
    second side (after a URDF or SDFormat file); else the first (before an MJCF). An articulation with
    no joint to the world floats: its root body is held at the identity, as an MJCF's free joint is."""
    loaded, robot = load_usd(path)
    desc = describe_usd(robot)
    mismatched = pose_mismatches(robot)
    if mismatched:
        findings.append(
            finding(
                "usd_pose_mismatch",
                f"the USD places {len(mismatched)} bodies (their xformOps, where a "
                "simulator starts them) elsewhere than their joint frames do (compared: the joint frames): "
                + ", ".join(f"{b} {p:.3g} m, {r:.3g} rad" for b, p, r in mismatched),
                {"file": "USD", "bodies": {b: [p, r] for b, p, r in mismatched}},
                magnitude=max(max(p, r) for _, p, r in mismatched),
                unit="m|rad",
                link=[b.split(" (")[0] for b, _, _ in mismatched],
            )
        )
    roots = [robot.names[robot.root]] if robot.floating else []
    if free is None:
        return loaded, loaded.text, desc, roots
    root = robot.names[robot.root]
    base = UrdfBase("floating" if roots else "fixed", root, "(free body)" if roots else None, root)
    floating, kind, message = decide(base, list(free))
    message = message.replace(
        "the URDF's root joint (free body) is floating", f"the USD's root body {root} has no joint to the world"
    )
    return (
        loaded,
        loaded.text,
        desc,
        "usd",
        BaseDecision(floating, kind, message, base, list(free), loaded.text if floating else ""),
    )


def sdf_free_bodies(sdf_text: str) -> list[str]:
    """Links of the SDFormat model that no joint holds (Drake's free bodies)."""
    root = ET.fromstring(sdf_text)
    model = root.find("model")
    if model is None:
        return []
    children = {j.findtext("child", "").strip() for j in model.iter("joint")}
    return [el.get("name") for el in model.findall("link") if el.get("name") not in children]  # type: ignore[misc]  # links are named


def mjcf_angle_unit(mjcf_text: str) -> str:
    """The MJCF's ``<compiler angle>``: "degree" (MuJoCo's default) or "radian"."""
    compiler = ET.fromstring(mjcf_text).find("compiler")
    return "degree" if compiler is None else compiler.get("angle", "degree")
