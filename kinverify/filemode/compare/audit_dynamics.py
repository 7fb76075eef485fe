"""Dynamics in a one-file audit: the same file's rigid-body dynamics in Pinocchio and in MuJoCo.

A URDF: Pinocchio's reading against MuJoCo's URDF import. An MJCF: MuJoCo against Pinocchio's
MJCF parser (with the top-level pose it drops, pinocchio#2782, put back as the direction of
gravity in its world). The states and tolerances are :class:`~kinverify.suites.dynamics.DynamicsSuite`'s:
rigid body, constraints, springs and actuators off in MuJoCo; damping and friction compared as
the parameters each library read. Neither format gives both libraries an armature the other
reads (URDF has none), so Pinocchio takes MuJoCo's.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from kinverify.backends import ModelSources
from kinverify.backends.mujoco_ import urdf_for_mujoco
from kinverify.backends.pinocchio_ import PinocchioBackend
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.describe_mjcf import describe_mjcf
from kinverify.suites.base import Section, VerifyContext
from kinverify.suites.dynamics import DynamicsSuite
from kinverify.tracking.models import MujocoDynamics, PinocchioDynamics

PAIRS = {"urdf": ("pinocchio-urdf", "mujoco-urdf"), "mjcf": ("mujoco", "pinocchio-mjcf")}


class PinocchioMjcfDynamics(PinocchioDynamics):
    """:class:`PinocchioDynamics` on Pinocchio's MJCF parser's model."""

    library, reads = "pinocchio-mjcf", "MJCF"

    @classmethod
    def build_model(cls, mjcf: str):
        return PinocchioBackend.from_mjcf(mjcf, (), ()).model  # the backend's reading of the text


class AuditDynamicsSuite(DynamicsSuite):
    """Pinocchio and MuJoCo on one file (``kind``); ``top``: the MJCF's top-level pose Pinocchio drops."""

    def __init__(self, kind: str, text: str, top: np.ndarray | None = None) -> None:
        self.kind, self.text, self.top = kind, text, top
        self.title = f"Dynamics: the {kind.upper()} in {' and '.join(PAIRS[kind])}"

    def models(self, ctx: VerifyContext):
        joints = ctx.sources.joint_names
        if self.kind == "urdf":
            mj = MujocoDynamics(urdf_for_mujoco(self.text), joints, rigid=True, library="mujoco-urdf", reads="URDF")
            return PinocchioDynamics(self.text, joints, mj.armature), mj, "MuJoCo's URDF import"
        mj = MujocoDynamics(self.text, joints, rigid=True)
        pin = PinocchioMjcfDynamics(self.text, joints, mj.armature)
        rot = np.eye(3) if self.top is None else self.top[:3, :3]
        pin.model.gravity.linear = rot.T @ np.asarray(mj.model.opt.gravity, dtype=float)  # Pinocchio's world is the top body's
        return pin, mj, "MJCF"

    def run(self, ctx: VerifyContext):
        src = ctx.sources
        both = ModelSources(
            src.name, src.joint_names, src.frames, src.lower, src.upper, src.revolute, urdf=self.text, mjcf=self.text
        )  # one file: run() asks for both sources
        out = super().run(VerifyContext(both, {}, ctx.q, ctx.options))
        out.checks = [dataclasses.replace(c, backends=PAIRS[self.kind]) for c in out.checks]  # the reference first
        if out.section is not None:
            out.section = _relabel(out.section, self.title, *sorted(PAIRS[self.kind], key=lambda n: "mujoco" in n))
        return out


def _relabel(section: Section, title: str, pinocchio: str, mujoco: str) -> Section:
    """The suite's section with the two libraries reading one file named instead of "URDF" (its
    Pinocchio side) and "MJCF" (its MuJoCo side)."""
    section.title = title
    section.tables = [
        dataclasses.replace(t, columns=[c.replace("URDF", pinocchio).replace("MJCF", mujoco) for c in t.columns])
        for t in section.tables
    ]
    section.notes = [n for n in section.notes if "URDF cannot express joint armature" not in n]
    section.notes.append(f"{pinocchio}'s joint armature is set to {mujoco}'s (a URDF has none): armature is not compared.")
    return section


def inertial_findings(urdf_text: str, desc, scale: float = 1.0) -> list:
    """One error finding per URDF link whose inertial MuJoCo's URDF import reads differently from
    Pinocchio (``desc``: Pinocchio's description): mass, centre of mass or inertia (world, q = 0)."""
    mine = {b.name: b for b in desc.bodies}
    theirs = {b.name: b for b in describe_mjcf(urdf_for_mujoco(urdf_text)).bodies}
    out = []
    for name in sorted(set(mine) | set(theirs), key=lambda n: desc.frame_depth.get(n, 0)):
        a, b = mine.get(name), theirs.get(name)
        mass = (a.mass if a else 0.0, b.mass if b else 0.0)
        tol = 1e-9 * max(1.0, *mass)
        if a is None or b is None:
            differs = abs(mass[0] - mass[1]) > tol
            what, prop = f"a mass of {mass[1]:.6g} kg, pinocchio-urdf {mass[0]:.6g} kg", "inertia.mass"
        else:
            dm = abs(a.mass - b.mass)
            dc = float(np.linalg.norm(a.com - b.com))
            di = float(np.abs(a.inertia - b.inertia).max())
            differs = dm > tol or dc > 1e-9 * scale or di > tol
            prop = "inertia.mass" if dm > tol else "inertia.com" if dc > 1e-9 * scale else "inertia.tensor"
            what = {
                "inertia.mass": f"a mass of {b.mass:.6g} kg, pinocchio-urdf {a.mass:.6g} kg",
                "inertia.com": f"its centre of mass {dc:.3g} m from pinocchio-urdf's",
                "inertia.tensor": f"an inertia up to {di:.3g} kg·m² from pinocchio-urdf's",
            }[prop]
        if differs:
            out.append(
                finding(
                    "parser_disagreement",
                    f"mujoco-urdf gives link {name} {what}"
                    + (" (the link has no <inertial>: MuJoCo's URDF import takes one from its geometry)" if a is None else ""),
                    {
                        "file": "URDF",
                        "backends": ["pinocchio-urdf", "mujoco-urdf"],
                        "backend": "mujoco-urdf",
                        "pinocchio-urdf": mass[0],
                        "mujoco-urdf": mass[1],
                    },
                    magnitude=abs(mass[0] - mass[1]) if prop == "inertia.mass" else None,
                    unit="kg" if prop == "inertia.mass" else "",
                    prop=prop,
                    severity="error",
                    link=name,
                )
            )
    return out
