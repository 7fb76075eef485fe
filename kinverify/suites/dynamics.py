"""Suite ``dynamics``: the URDF through Pinocchio against the MJCF through MuJoCo, same states,
and against the SDFormat file through Drake when the ``drake`` extra is installed (spec mode).

Rigid-body dynamics plus joint damping are compared state by state, with MuJoCo's constraints
(contacts, limits, ``frictionloss``), springs and actuators disabled (Pinocchio models none of
them, and ``mj_inverse`` would otherwise add their forces). What a side cannot model is compared
as a parameter instead, exactly:

- Coulomb friction: URDF ``<dynamics friction>`` against MJCF ``frictionloss``;
- damping: URDF ``<dynamics damping>`` against MJCF ``damping`` (and applied as ``-D·q̇`` on the
  Pinocchio side, so the state comparisons include it);
- armature: the URDF cannot express it, so Pinocchio's is *taken from the spec* (from the MJCF
  in file mode) and the MJCF's is compared with the spec.

``dynamics.forward`` compares the accelerations both libraries give from the same state and
joint forces (ABA against ``mj_forward``), not a long simulation whose divergence would be
integration error, not a disagreement. It is measured in force space, ``|M(q)·(a_mujoco −
a_pinocchio)|``: the joint forces by which MuJoCo's acceleration misses Pinocchio's equations of
motion, which stays well conditioned on long chains where the accelerations themselves are not.
A non-finite value is reported as a numerical breakdown finding, never as a disagreement.

Double precision agrees to a fixed *relative* precision, so the state comparisons pass when
``max |Δ| <= tolerance · max(1, max |value|)`` over the samples: the check's ``tolerance`` is
that product (reported in N·m, kg·m²), and ``--tolerance`` sets the relative factor.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from kinverify.backends import backend_info
from kinverify.errors import KinverifyError
from kinverify.model.floating import has_base
from kinverify.pipeline.stats import ErrorStats
from kinverify.suites.base import Finding, Property, Section, Suite, SuiteResult, VerifyContext, within
from kinverify.tracking.models import MujocoDynamics, PinocchioDynamics

PAIR = ("pinocchio-urdf", "mujoco")
DRAKE_PAIR = ("pinocchio-urdf", "drake-sdf")  # Drake's dynamics of the SDFormat file (kinverify[drake])
DEFAULT_SAMPLES = 100  # configurations (edges first) for the state comparisons
ACCELERATION = 10.0  # random joint accelerations in ±this [rad/s² or m/s²]
STATE_PROPERTIES = ("dynamics.mass_matrix", "dynamics.gravity", "dynamics.bias", "dynamics.inverse", "dynamics.forward")


def _units(revolute) -> dict[str, str]:
    """Units of each property for this model's joints (N·m for revolute, N for prismatic)."""
    rev = list(revolute)

    def pick(r, p):
        return r if all(rev) else p if not any(rev) else f"{r}|{p}"

    return {
        "dynamics.mass_matrix": pick("kg·m²", "kg"),
        "dynamics.gravity": pick("N·m", "N"),
        "dynamics.bias": pick("N·m", "N"),
        "dynamics.inverse": pick("N·m", "N"),
        "dynamics.forward": pick("N·m", "N"),
        "dynamics.damping": pick("N·m·s/rad", "N·s/m"),
        "dynamics.friction": pick("N·m", "N"),
        "dynamics.armature": pick("kg·m²", "kg"),
    }


class DynamicsSuite(Suite):
    forward_scales_with_acceleration = False  # see state_errors
    name = "dynamics"
    title = "Dynamics: URDF (Pinocchio) vs MJCF (MuJoCo)"
    # The same double-precision recursions agree to ~1e-13 on the shipped arms.
    properties = (
        Property("dynamics.mass_matrix", "kg·m²", 1e-9, compares="pin.crba vs mujoco.mj_fullM: max |ΔM_ij| ≤ tol·max(1, |M|)"),
        Property(
            "dynamics.gravity", "N·m", 1e-9, compares="pin.computeGeneralizedGravity vs qfrc_bias at rest, ≤ tol·max(1, |g|)"
        ),
        Property(
            "dynamics.bias", "N·m", 1e-9, compares="pin.nonLinearEffects (Coriolis + gravity) vs qfrc_bias, ≤ tol·max(1, |h|)"
        ),
        Property(
            "dynamics.inverse",
            "N·m",
            1e-9,
            compares="pin.rnea + damping·q̇ vs mujoco.mj_inverse (constraints off), ≤ tol·max(1, |τ|)",
        ),
        Property(
            "dynamics.forward",
            "N·m",
            1e-9,
            compares="pin.aba vs mj_forward from the same state and forces: |M·Δq̈| ≤ tol·max(1, |τ|)",
        ),
        Property("dynamics.damping", "N·m·s/rad", 1e-12, compares="URDF <dynamics damping> vs MJCF damping"),
        Property("dynamics.friction", "N·m", 1e-12, compares="URDF <dynamics friction> vs MJCF frictionloss"),
        Property("dynamics.armature", "kg·m²", 1e-12, compares="spec (or the MJCF in file mode) vs MJCF armature"),
    )

    def models(self, ctx: VerifyContext) -> tuple[PinocchioDynamics, MujocoDynamics, str]:
        """(Pinocchio on the URDF, MuJoCo on the MJCF for rigid-body dynamics, where the armature came from)."""
        sources = ctx.sources
        assert sources.urdf is not None and sources.mjcf is not None  # run() skips the suite otherwise
        mj = MujocoDynamics(sources.mjcf, sources.mjcf_joint_names or sources.joint_names, rigid=True)
        if sources.spec is not None:
            armature, origin = [j.armature for j in sources.spec.joints], "spec"
        else:
            armature, origin = mj.armature, "MJCF"
        return PinocchioDynamics(sources.urdf, sources.joint_names, armature), mj, origin

    def drake_model(self, ctx: VerifyContext):
        """Drake's dynamics of the SDFormat file, or None (no SDFormat, or no ``drake`` extra)."""
        info = backend_info(DRAKE_PAIR[1])
        if not ctx.sources.sdf or not info.available:
            return None
        return info.backend_class.dynamics(ctx.sources.sdf, "sdf", ctx.sources.sdf_joint_names or ctx.sources.joint_names)

    def run(self, ctx: VerifyContext) -> SuiteResult:
        sources, opts = ctx.sources, ctx.options
        if not sources.urdf or not sources.mjcf:
            return SuiteResult([], Section(self.title, "skipped: needs both a URDF and an MJCF"))
        try:
            pin, mj, origin = self.models(ctx)
        except KinverifyError as err:  # e.g. a file-mode URDF with more joints than are compared
            return SuiteResult([], Section(self.title, f"skipped: {err}"))
        spec = sources.spec
        floating = has_base(sources.joint_names)
        n_joints = len(sources.joint_names) - 6 * floating
        vmax = np.array([j.limits.velocity for j in spec.joints]) if spec is not None else np.full(n_joints, 3.0)
        effort = np.array([j.limits.effort for j in spec.joints]) if spec is not None else np.full(n_joints, 100.0)
        n = int(opts.extra.get("dynamics_samples", DEFAULT_SAMPLES))
        q = np.asarray(ctx.q[:n])
        units = _units(sources.revolute)
        # with a floating base: the mass matrix and gravity in the base coordinates (tracking/models.py)
        compared = STATE_PROPERTIES[:2] if floating else STATE_PROPERTIES
        # What MuJoCo's compiler aligns with a body's frame (principal axes, centre of mass) its run
        # time uses so: Pinocchio gets the same inertials against MuJoCo (file mode substitutes its own).
        run_inertials = mj.run_inertials() if isinstance(mj, MujocoDynamics) else {}
        stats, scales, breakdown = self.state_errors(
            pin.with_inertials(run_inertials) if run_inertials else pin,
            mj,
            q,
            vmax,
            effort,
            opts.seed,
            compared,
            opts.on_progress,
            self.forward_scales_with_acceleration,
        )
        quirk = _sameframe_note(mj.snapped_inertia_frames(), mj.moved_coms() if run_inertials else [], bool(run_inertials))
        checks = []
        for p in compared:
            check = self.check(ctx.options, p, "joints", PAIR, stats[p], quirk, units[p])
            tol = check.tolerance * max(1.0, scales[p])
            checks.append(dataclasses.replace(check, tolerance=tol, passed=within(check.max_error, tol)))
        drake = self.drake_model(ctx)
        if drake is not None:  # the same states (same seed): Drake's dynamics against Pinocchio's
            stats, scales, drake_breakdown = self.state_errors(pin, drake, q, vmax, effort, opts.seed, compared)
            breakdown = breakdown if breakdown is not None else drake_breakdown
            for p in compared:
                check = self.check(ctx.options, p, "joints", DRAKE_PAIR, stats[p], "", units[p])
                tol = check.tolerance * max(1.0, scales[p])
                checks.append(dataclasses.replace(check, tolerance=tol, passed=within(check.max_error, tol)))
        checks += self.parameter_checks(ctx, pin, mj, origin, units, drake)
        findings = []
        if breakdown:
            findings.append(
                Finding(
                    "numerical_breakdown",
                    "warning",
                    "non-finite dynamics at q = "
                    f"{np.round(breakdown, 6).tolist()}: a numerical breakdown of a library, not a disagreement "
                    "between the models; those states are left out of the comparison",
                    property="dynamics.forward",
                )
            )
        section = Section(
            self.title,
            f"{len(q)} configurations with random joint speeds, accelerations and forces; "
            f"{sum(c.passed for c in checks)} of {len(checks)} checks pass.",
        )
        section.table(
            "Checks",
            ["property", "max error", "tolerance", "worst q", "ok"],
            [
                [
                    c.property,
                    f"{c.max_error:.3e} {c.unit}",
                    f"{c.tolerance:.0e}",
                    ", ".join(f"{x:.4g}" for x in c.worst_q),
                    "ok" if c.passed else "FAIL",
                ]
                for c in checks
            ],
        )
        arm_pin = np.array(pin.model.armature)[pin.idx_v]
        section.table(
            "Joint parameters",
            [
                "joint",
                "damping URDF",
                "damping MJCF",
                "friction URDF",
                "frictionloss MJCF",
                "armature (Pinocchio)",
                "armature MJCF",
            ],
            [
                [
                    name,
                    pin.damping[i],
                    mj.damping[i],
                    pin.friction[i],
                    mj.friction[i],
                    f"URDF cannot express; taken from the {origin} ({arm_pin[i]:.6g})",
                    mj.armature[i],
                ]
                for i, name in enumerate(sources.joint_names[6 * floating :])
            ],
        )
        if drake is not None:
            section.notes.append(
                "Drake (drake-sdf) on the SDFormat file: its CalcMassMatrix, gravity, bias and "
                "CalcInverseDynamics (with its own gravity and joint damping forces) against Pinocchio's, "
                "same states; armature is Drake's reflected inertia from drake:rotor_inertia; Drake "
                "models no Coulomb joint friction, so friction is not compared for it."
            )
        if floating:
            section.notes.append(
                "Floating base: the mass matrix and gravity are compared in the base coordinates "
                "(base:x ... base:yaw, then the joints; S^T·M·S and S^T·g from each library's own base "
                "velocity); Coriolis, inverse and forward dynamics are not compared for a floating base."
            )
        section.notes += ([quirk] if quirk else []) + [
            "Compared exactly on both sides: rigid-body dynamics and joint damping (Pinocchio's algorithms ignore "
            "model.damping, so -D·q̇ is added on its side; MuJoCo applies it as a passive force).",
            "Compared as parameters, disabled in MuJoCo's state comparisons: Coulomb friction (frictionloss is a MuJoCo "
            "constraint that Pinocchio does not model), joint limits and contacts (constraints), springs and actuators.",
            f"URDF cannot express joint armature: Pinocchio's model.armature is taken from the {origin}; "
            "Pinocchio's crba/rnea/aba include it.",
        ]
        return SuiteResult(checks, section, findings)

    @staticmethod
    def state_errors(
        pin: PinocchioDynamics,
        mj: MujocoDynamics,
        q: np.ndarray,
        vmax,
        effort,
        seed: int = 0,
        compared=STATE_PROPERTIES,
        on_progress=None,
        forward_scales_with_acceleration: bool = False,
    ):
        """Max |difference| per state property over configurations ``q`` (N, n) with random
        speeds in ±vmax, accelerations in ±ACCELERATION and joint forces in ±effort. Returns the
        stats, the largest |value| per property (the scale of its tolerance) and the first
        configuration where a library gave a non-finite value (or None).
        ``forward_scales_with_acceleration``: the forward residual's scale is also |M|·|q̈| (two
        files written with rounded values: see :class:`~kinverify.filemode.compare.dynamics.FileDynamicsSuite`)."""
        rng = np.random.default_rng([seed, 0xD1])
        stats = {p: ErrorStats() for p in compared}
        scales = dict.fromkeys(compared, 0.0)
        breakdown = None
        report = on_progress or (lambda done, total: None)
        for k, qk in enumerate(q):
            if k % 10 == 0:
                report(k, len(q))
            n = len(vmax)
            v = rng.uniform(-1.0, 1.0, n) * vmax
            a = rng.uniform(-ACCELERATION, ACCELERATION, n)
            tau = rng.uniform(-1.0, 1.0, n) * effort
            mass = pin.mass(qk)
            accel = [mj.forward(qk, v, tau)] if "dynamics.forward" in compared else [None]
            terms = {  # evaluated below, for the compared properties only; each binds this configuration's values
                "dynamics.mass_matrix": lambda qk=qk, mass=mass: (mass, mj.mass(qk)),  # type: ignore[misc]  # mypy cannot type a lambda with defaults
                "dynamics.gravity": lambda qk=qk: (pin.gravity(qk), mj.gravity(qk)),
                "dynamics.bias": lambda qk=qk, v=v: (pin.bias(qk, v), mj.bias(qk, v)),  # type: ignore[misc]  # mypy cannot type a lambda with defaults
                "dynamics.inverse": lambda qk=qk, v=v, a=a: (pin.inverse(qk, v, a), mj.inverse(qk, v, a)),  # type: ignore[misc]  # mypy cannot type a lambda with defaults
                # force residual of MuJoCo's acceleration in Pinocchio's equations: M·(a_mj − a_pin)
                "dynamics.forward": lambda qk=qk, v=v, tau=tau, mass=mass, accel=accel: (  # type: ignore[misc]  # mypy cannot type a lambda with defaults
                    (tau, tau + mass @ (accel[0] - pin.forward(qk, v, tau)))
                ),
            }
            pairs = {p: terms[p]() for p in compared}
            if not all(np.isfinite(x).all() and np.isfinite(y).all() for x, y in pairs.values()):
                breakdown = qk if breakdown is None else breakdown
                continue
            for prop, (x, y) in pairs.items():
                stats[prop].update(np.array([np.abs(x - y).max()]), qk[None])
                scales[prop] = max(scales[prop], float(np.abs(x).max()))
            if (
                forward_scales_with_acceleration and accel[0] is not None
            ):  # the residual is (M_pin − M_mj)·a_mj + (b_pin − b_mj): its scale is |M|·|a| too,
                # far above |τ| where light links take large accelerations (a relative error in M grows with it)
                scales["dynamics.forward"] = max(scales["dynamics.forward"], float(np.abs(mass).max() * np.abs(accel[0]).max()))
        report(len(q), len(q))
        return stats, scales, breakdown

    def parameter_checks(
        self, ctx: VerifyContext, pin: PinocchioDynamics, mj: MujocoDynamics, origin: str, units, drake=None
    ) -> list:
        """Joint damping and friction (URDF vs MJCF), armature (spec vs MJCF; in file mode the
        MJCF's is what Pinocchio uses, so there is nothing to compare); with Drake, damping (URDF
        vs SDFormat) and armature (spec vs Drake's reflected inertia)."""
        joints = ctx.sources.joint_names[6 if has_base(ctx.sources.joint_names) else 0 :]

        def worst(a, b) -> tuple[float, str]:
            k = int(np.argmax(np.abs(a - b)))
            return float(np.abs(a - b)[k]), joints[k]

        checks = []
        for prop, urdf_vals, mjcf_vals in (
            ("dynamics.damping", pin.damping, mj.damping),
            ("dynamics.friction", pin.friction, mj.friction),
        ):
            err, joint = worst(urdf_vals, mjcf_vals)
            checks.append(
                self.value_check(
                    ctx.options,
                    prop,
                    "parameters",
                    ("urdf", "mjcf"),
                    err,
                    unit=units[prop],
                    note=f"largest at {joint}" if err > 0 else "",
                )
            )
        if origin == "spec":
            assert ctx.sources.spec is not None  # the armature came from it
            spec_arm = np.array([j.armature for j in ctx.sources.spec.joints])
            err, joint = worst(spec_arm, mj.armature)
            checks.append(
                self.value_check(
                    ctx.options,
                    "dynamics.armature",
                    "parameters",
                    ("spec", "mjcf"),
                    err,
                    unit=units["dynamics.armature"],
                    note="URDF cannot express armature; Pinocchio's is taken from the spec",
                )
            )
        if drake is not None:
            err, joint = worst(pin.damping, drake.damping)
            checks.append(
                self.value_check(
                    ctx.options,
                    "dynamics.damping",
                    "parameters",
                    ("urdf", "sdf"),
                    err,
                    unit=units["dynamics.damping"],
                    note=f"largest at {joint}" if err > 0 else "",
                )
            )
            if origin == "spec":
                err, joint = worst(spec_arm, drake.armature)
                checks.append(
                    self.value_check(
                        ctx.options,
                        "dynamics.armature",
                        "parameters",
                        ("spec", "sdf"),
                        err,
                        unit=units["dynamics.armature"],
                        note="Drake's reflected inertia (drake:rotor_inertia)",
                    )
                )
        return checks


def _sameframe_note(snapped: list, moved: list, substituted: bool) -> str:
    """The note naming what MuJoCo's compiler aligned with a body's frame (``body_sameframe``)."""
    parts = [f"the principal inertia axes of {b} (rotated {a:.2g} rad) as aligned with its frame" for b, a in snapped]
    parts += [f"the centre of mass of {b} ({d:.2g} m from its origin) as at its origin" for b, d in moved]
    if not parts:
        return ""
    return (
        "MuJoCo's compiler treats "
        + "; ".join(parts)
        + " (body_sameframe: within 1e-6 m and about 1e-6 rad) and its run time uses them so: "
        + (
            "Pinocchio is given the same inertials for the comparison with MuJoCo (Drake keeps the stated ones)"
            if substituted
            else "differences of that order come from MuJoCo"
        )
    )
