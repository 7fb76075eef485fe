"""The dynamics suite in file mode: Pinocchio on the URDF against MuJoCo on the MJCF, after the
alignment, and after the differences other findings report.

- Both files over every matched joint (followers of a coupling included, at their coupled value),
  joints present in one file only locked at zero; a base both files float is six coordinates
  in front (:mod:`kinverify.filemode.align.floating`: mass matrix and gravity compared), any other free
  base fixed (see :mod:`prepare`).
- MuJoCo is read through the joint map (``q_mjcf = s·q + o``, forces and velocities times ``s``)
  with gravity turned by the world transform.
- What a finding already reports is substituted on the Pinocchio side before comparing: the
  MJCF's inertial for a rigid body whose mass or inertia differs, the MJCF's damping for a joint
  whose damping differs, and the MJCF's armature (URDF has no field for it). So the state checks
  measure what no finding explains; each says what was substituted ("explained by").
- Damping and friction are compared as parameters on the files' own values (the substituted
  damping only enters the state comparisons).
"""

from __future__ import annotations

import numpy as np
import pinocchio

from kinverify.backends import ModelSources
from kinverify.filemode.align.floating import conjugated
from kinverify.filemode.compare.inertials import ROOT
from kinverify.filemode.findings.table import finding
from kinverify.filemode.read.prepare import lock_mjcf_joints, lock_urdf_joints
from kinverify.filemode.read.stated import unset
from kinverify.model.floating import BASE_COORDINATES, BASE_REVOLUTE
from kinverify.suites.base import VerifyContext
from kinverify.suites.dynamics import DynamicsSuite
from kinverify.tracking.models import MujocoDynamics, PinocchioDynamics


class AlignedMujoco:
    """MuJoCo's dynamics of the MJCF seen in the URDF's joint coordinates (``T``: the world
    transform, for a floating base's coordinates: :func:`kinverify.filemode.align.floating.conjugated`)."""

    def __init__(
        self, inner: MujocoDynamics, signs: np.ndarray, offsets: np.ndarray, gravity: np.ndarray, t: np.ndarray | None = None
    ) -> None:
        self.inner, self.s, self.o = inner, signs, offsets
        self.t = None if t is None or np.array_equal(t, np.eye(4)) else t
        inner.model.opt.gravity[:] = gravity
        self.armature, self.damping, self.friction = inner.armature, inner.damping, inner.friction

    def snapped_inertia_frames(self):
        return self.inner.snapped_inertia_frames()

    def _q(self, q):
        q = np.asarray(q, dtype=float)
        if not self.inner.floating:
            return self.s * q + self.o
        base = q[:6] if self.t is None else conjugated(self.t, q[:6])[0][0]
        return np.concatenate([base, self.s * q[6:] + self.o])

    def _jac(self, q) -> np.ndarray:
        """d q_mjcf / d q: the signs, after the base block when floating."""
        if not self.inner.floating:
            return np.diag(self.s)
        out = np.zeros((len(self.s) + 6,) * 2)
        out[:6, :6] = np.eye(6) if self.t is None else conjugated(self.t, np.asarray(q, dtype=float)[:6])[1][0]
        out[6:, 6:] = np.diag(self.s)
        return out

    def mass(self, q):
        if not self.inner.floating:
            return self.s[:, None] * self.inner.mass(self._q(q)) * self.s[None, :]
        j = self._jac(q)
        return j.T @ self.inner.mass(self._q(q)) @ j

    def gravity(self, q):
        if not self.inner.floating:
            return self.s * self.inner.gravity(self._q(q))
        return self._jac(q).T @ self.inner.gravity(self._q(q))

    def bias(self, q, v):
        return self.s * self.inner.bias(self._q(q), self.s * v)

    def inverse(self, q, v, a):
        return self.s * self.inner.inverse(self._q(q), self.s * v, self.s * a)

    def forward(self, q, v, tau):
        return self.s * self.inner.forward(self._q(q), self.s * v, self.s * tau)


class DampingSubstituted:
    """Pinocchio's dynamics with ``extra`` damping added in the state comparisons only: the
    parameters (``damping``, ``friction``) stay what the URDF says."""

    def __init__(self, inner: PinocchioDynamics, extra: np.ndarray) -> None:
        self.inner, self.extra = inner, extra
        self.model, self.idx_v, self.damping, self.friction = inner.model, inner.idx_v, inner.damping, inner.friction

    def mass(self, q):
        return self.inner.mass(q)

    def gravity(self, q):
        return self.inner.gravity(q)

    def bias(self, q, v):
        return self.inner.bias(q, v)

    def inverse(self, q, v, a):
        return self.inner.inverse(q, v, a) + self.extra * np.asarray(v)

    def forward(self, q, v, tau):
        return self.inner.forward(q, v, np.asarray(tau) - self.extra * np.asarray(v))


class FileDynamicsSuite(DynamicsSuite):
    """:class:`DynamicsSuite` on the two files, aligned, with reported differences substituted.
    The forward residual ``M·Δq̈ = ΔM·q̈ + Δb`` is scaled by |M|·|q̈| as well as |τ|: files written
    with rounded values differ in ``M`` by their written precision, and light links take large
    accelerations, so the written-precision floor of the forward check grows with them."""

    forward_scales_with_acceleration = True

    def __init__(self, info, inertial_groups: dict, damping_joints: set, notes: list[str]) -> None:
        self.info, self.groups, self.damping_joints, self.explained = info, inertial_groups, damping_joints, notes

    def context(self, ctx: VerifyContext) -> VerifyContext:
        info, al = self.info, self.info.alignment
        base = BASE_COORDINATES if info.base_coordinates else ()
        u_names = base + tuple(j.urdf for j in al.joints)
        m_names = base + tuple(j.mjcf for j in al.joints)
        revolute = BASE_REVOLUTE[: len(base)] + tuple(j.type == "revolute" for j in al.joints)
        src = ctx.sources
        assert src.urdf is not None and src.mjcf is not None  # file mode: both files
        sources = ModelSources(
            src.name,
            u_names,
            src.frames,
            (),
            (),
            revolute,
            None,
            lock_urdf_joints(src.urdf, info.matching.unmatched_urdf + info.u.held),
            lock_mjcf_joints(src.mjcf, info.matching.unmatched_mjcf + info.m.held),
            m_names,
            src.mjcf_frames,
        )
        n = int(ctx.options.extra.get("dynamics_samples", 100))
        q = np.asarray(ctx.q[:n])
        q = np.concatenate([q[:, : len(base)], al.expand(q[:, len(base) :])], axis=1)
        return VerifyContext(sources, {}, q, ctx.options)

    def run(self, ctx: VerifyContext):
        return super().run(self.context(ctx))

    def models(self, ctx: VerifyContext):
        al = self.info.alignment
        assert ctx.sources.urdf is not None and ctx.sources.mjcf is not None  # file mode: both files
        mj = MujocoDynamics(ctx.sources.mjcf, ctx.sources.mjcf_joint_names, rigid=True)
        pin = PinocchioDynamics(ctx.sources.urdf, ctx.sources.joint_names, mj.armature)
        self._substitute_inertia(pin)
        extra = np.array(
            [0.0] * 6 * pin.floating
            + [mj.damping[k] - pin.damping[k] if j.urdf in self.damping_joints else 0.0 for k, j in enumerate(al.joints)]
        )
        gravity = al.T[:3, :3] @ np.array([0.0, 0.0, -9.81])
        return DampingSubstituted(pin, extra), AlignedMujoco(mj, al.signs, al.offsets, gravity, al.T), "MJCF"

    def _substitute_inertia(self, pin: PinocchioDynamics) -> None:
        """The MJCF's inertial (common frame, aligned zero) for each rigid body a finding reports."""
        model, data = pin.model, pin.data
        full = self.info.alignment.expand(np.zeros((1, len(self.info.alignment.independent))))[0]
        q = pin._q(np.concatenate([np.zeros(6 * pin.floating), full]))  # a floating base at the identity
        pinocchio.forwardKinematics(model, data, q)
        for key, inertial in self.groups.items():
            if key == ROOT and pin.floating:
                jid = next(i for i in range(1, model.njoints) if model.parents[i] == 0)  # the free-flyer
            elif model.existJointName(key):
                jid = model.getJointId(key)
            else:
                continue
            pose = data.oMi[jid]
            rot = pose.rotation
            lever = rot.T @ (inertial.com - pose.translation)
            model.inertias[jid] = pinocchio.Inertia(inertial.mass, lever, rot.T @ inertial.inertia @ rot)


def parameter_findings(info, tolerances: dict) -> list:
    """Joint damping and friction that differ (one finding per pair of values: an error when both
    files state them, a warning naming the silent file when one leaves the value unset), armature
    the URDF cannot express (one warning), and format extensions a library ignores (one info)."""
    groups: dict
    out, groups = [], {}
    for j in info.alignment.joints:
        ju, jm = info.u.joint(j.urdf), info.m.joint(j.mjcf)
        for prop, value, x, y in (
            ("dynamics.damping", "damping", ju.damping, jm.damping),
            ("dynamics.friction", "friction", ju.friction, jm.friction),
            ("dynamics.armature", "armature", ju.armature, jm.armature),
        ):
            if value == "armature" and "usd" not in (info.u.kind, info.m.kind):
                continue  # a URDF has none; an MJCF's, against any file but a USD, is the finding below
            if x is None or y is None or abs(x - y) <= tolerances.get(prop, 1e-12):
                continue
            silent = "URDF" if unset(ju.stated, value) else "MJCF" if unset(jm.stated, value) else ""
            groups.setdefault((value, prop, silent, round(x, 12), round(y, 12)), []).append(j)
    units = {"dynamics.damping": "N·m·s/rad", "dynamics.friction": "N·m", "dynamics.armature": "kg·m²"}
    usd = {
        "damping": "no newton:damping or mjc:damping on the joint",
        "friction": "no newton:friction or mjc:frictionloss on the joint",
        "armature": "no physxJoint:armature, newton:armature or mjc:armature on the joint",
    }
    how = {
        "URDF": {"damping": "no <dynamics damping>", "friction": "no <dynamics friction>"},
        "MJCF": {
            "damping": "no damping on the joint or its default class",
            "friction": "no frictionloss on the joint or its default class",
            "armature": "no armature on the joint or its default class",
        },
    }
    for side, desc in (("URDF", info.u), ("MJCF", info.m)):
        if desc.kind == "usd":  # a USD side takes the URDF's or the MJCF's place
            how[side] = usd
    for (value, prop, silent, x, y), joints in groups.items():
        label = {"dynamics.friction": "friction (URDF friction, MJCF frictionloss)"}.get(prop, value)
        names = ", ".join(j.urdf for j in joints)
        count = f"{len(joints)} joint{'s' if len(joints) > 1 else ''}"
        if silent:
            other, said = ("MJCF", y) if silent == "URDF" else ("URDF", x)
            message = (
                f"the {silent} leaves {label} unset on {count} ({how[silent][value]}: 0 by default); the {other} "
                f"states {said:g}: {names}"
            )
            kind = f"{value}_unset"
        else:
            message = f"{label} {x:g} in the URDF, {y:g} in the MJCF on {count}: {names}"
            kind = f"{value}_difference"
        out.append(
            finding(
                kind,
                message,
                {"urdf": x, "mjcf": y, "unset_in": silent or None, "checks": [[prop, "parameters"]]},
                magnitude=abs(x - y),
                unit=units[prop],
                prop=prop,
                joint=[j.urdf for j in joints],
                mjcf_joint=[j.mjcf for j in joints],
            )
        )
    if "usd" in (info.u.kind, info.m.kind):
        out += velocity_findings(info)
    for kind, field, what, unit, prop, handled in (
        (
            "inexpressible",
            "armature",
            "armature (rotor inertia) {}",
            "kg·m²",
            "dynamics.armature",
            "the comparison gives Pinocchio the MJCF's",
        ),
        (
            "stiffness_inexpressible",
            "stiffness",
            "a spring (stiffness {})",
            "N·m/rad",
            "dynamics.stiffness",
            "springs are left out of the dynamics comparison",
        ),
    ):
        given = [
            (j, getattr(info.m.joint(j.mjcf), field))
            for j in info.alignment.joints
            if getattr(info.m.joint(j.mjcf), field) and not (info.u.kind == "usd" and field == "armature")
        ]  # a USD first side: compared above
        if given:
            values = ", ".join(f"{v:g}" for v in sorted({round(x, 12) for _, x in given}))
            out.append(
                finding(
                    kind,
                    f"the MJCF gives {len(given)} joints {what.format(values)}, which a URDF cannot express: "
                    f"the URDF's dynamics lack it ({handled})",
                    {"mjcf": {j.urdf: x for j, x in given}},
                    magnitude=max(x for _, x in given),
                    unit=unit,
                    prop=prop,
                    joint=[j.urdf for j, _ in given],
                    mjcf_joint=[j.mjcf for j, _ in given],
                )
            )
    if info.m.gravcomp:
        shares = ", ".join(f"{v:g}" for v in sorted(set(info.m.gravcomp.values())))
        out.append(
            finding(
                "inexpressible",
                f"the MJCF compensates gravity on {len(info.m.gravcomp)} bodies (gravcomp "
                f"{shares}: MuJoCo cancels that share of their weight), which a URDF cannot express: the "
                "rigid-body dynamics are compared without it: " + ", ".join(info.m.gravcomp),
                {"file": "MJCF", "mjcf_gravcomp": dict(info.m.gravcomp)},
                magnitude=max(info.m.gravcomp.values()),
                unit="",
                prop="dynamics.gravity",
            )
        )
    if info.m.free_joint:
        said = " and ".join(f"{k} {v:g}" for k, v in info.m.free_joint.items())
        out.append(
            finding(
                "inexpressible",
                f"the MJCF gives its free joint {said} (a floating base in a URDF has "
                "neither): left out of the rigid-body dynamics comparison",
                {"file": "MJCF", **info.m.free_joint},
                magnitude=max(info.m.free_joint.values()),
                unit="",
                prop="dynamics.mass_matrix",
            )
        )
    rotor = {j: e for j, e in info.u.extensions.items() if "rotor_inertia" in e}
    if rotor:
        reflected = {j: e["rotor_inertia"] * e.get("gear_ratio", 1.0) ** 2 for j, e in rotor.items()}
        out.append(
            finding(
                "format_extension",
                "the URDF's transmissions give rotor inertia and gear ratio (a Drake extension "
                "Pinocchio does not read): reflected inertia G²·I of "
                + ", ".join(f"{j} {v:.4g}" for j, v in reflected.items())
                + " kg·m², not in the comparison",
                {"reflected_inertia": reflected},
                magnitude=max(reflected.values()),
                unit="kg·m²",
                joint=list(reflected),
            )
        )
    return out


def velocity_findings(info) -> list:
    """Velocity limits that differ where both files state one (a USD's ``physxJoint:maxJointVelocity``
    or ``newton:velocityLimit`` against a URDF's ``<limit velocity>``; an MJCF has none): one error
    per pair of values, within a millionth of the value alike (a USD writes degrees per second in
    single precision)."""
    groups: dict[tuple, list] = {}
    for j in info.alignment.joints:
        x, y = info.u.joint(j.urdf).velocity, info.m.joint(j.mjcf).velocity
        if x is None or y is None or abs(x - y) <= 1e-6 * max(abs(x), abs(y)):
            continue
        groups.setdefault((round(x, 9), round(y, 9), info.u.joint(j.urdf).type), []).append(j)
    out = []
    for (x, y, kind), joints in groups.items():
        unit = "rad/s" if kind == "revolute" else "m/s"
        out.append(
            finding(
                "velocity_difference",
                f"velocity limit {x:g} {unit} in the URDF, {y:g} {unit} in the MJCF on "
                f"{len(joints)} joint{'s' if len(joints) > 1 else ''}: " + ", ".join(j.urdf for j in joints),
                {"urdf": x, "mjcf": y},
                magnitude=abs(x - y),
                unit=unit,
                prop="limits.velocity",
                joint=[j.urdf for j in joints],
                mjcf_joint=[j.mjcf for j in joints],
            )
        )
    return out
