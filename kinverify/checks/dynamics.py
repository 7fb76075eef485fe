"""Suite ``dynamics``: the URDF through Pinocchio against the MJCF through MuJoCo, same states.

- ``dynamics.mass_matrix``: CRBA vs ``mj_fullM`` (max |ΔM_ij|);
- ``dynamics.gravity``: generalized gravity vs ``qfrc_bias`` at rest;
- ``dynamics.bias``: Coriolis + centrifugal + gravity at random joint speeds;
- ``dynamics.inverse``: RNEA + damping vs ``mj_inverse`` at random speeds and accelerations;
- ``dynamics.damping`` / ``dynamics.friction``: the joint parameters each format carries;
  ``dynamics.armature``: the URDF cannot express armature, so Pinocchio's is *taken from the spec*
  and the MJCF's is compared with the spec (reported as such, never silently dropped);
- ``tracking.forward``: one torque sequence integrated by Pinocchio (ABA, MuJoCo's Euler step)
  and by MuJoCo gives the same joint trajectory.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import KinverifyError
from ..results import Check
from ..stats import ErrorStats
from ..tracking.models import MujocoDynamics, PinocchioDynamics
from ..tracking.quintic import quintic
from .tolerances import DEFAULT_TOLERANCES, Tolerance

TOLERANCES = {k: v for k, v in DEFAULT_TOLERANCES.items() if k.startswith(("dynamics.", "tracking.forward"))}
PAIR = ("pinocchio-urdf", "mujoco")
DEFAULT_SAMPLES = 100  # configurations (edges first) for the state comparisons
FORWARD_SECONDS = 0.5


def _tol(options, prop: str) -> Tolerance:
    return options.tolerances.get(prop, TOLERANCES[prop]) if options is not None else TOLERANCES[prop]


def _check(prop: str, stats: ErrorStats, tol: Tolerance, pair=PAIR, note: str = "", frame: str = "joints") -> Check:
    worst = tuple(stats.worst_q.tolist()) if stats.worst_q is not None else ()
    return Check(prop, frame, pair, stats.max_error, stats.percentile(99), tol.value, stats.max_error <= tol.value,
                 worst, tol.unit, stats.count, tuple(stats.histogram.tolist()), note)


def build_models(sources) -> tuple[PinocchioDynamics, MujocoDynamics, str]:
    """(Pinocchio on the URDF, MuJoCo on the MJCF, where the armature came from)."""
    mj = MujocoDynamics(sources.mjcf, sources.joint_names)
    if sources.spec is not None:
        armature, origin = [j.armature for j in sources.spec.joints], "spec"
    else:
        armature, origin = mj.armature, "MJCF"
    return PinocchioDynamics(sources.urdf, sources.joint_names, armature), mj, origin


def state_checks(pin: PinocchioDynamics, mj: MujocoDynamics, q: np.ndarray, vmax, seed: int = 0, options=None) -> list[Check]:
    """The four state comparisons on configurations ``q`` (N, n) with random speeds in ±vmax and
    accelerations in ±10 (units per s²)."""
    rng = np.random.default_rng(seed)
    stats = {p: ErrorStats() for p in ("dynamics.mass_matrix", "dynamics.gravity", "dynamics.bias", "dynamics.inverse")}
    for qk in q:
        v = rng.uniform(-1.0, 1.0, len(qk)) * vmax
        a = rng.uniform(-10.0, 10.0, len(qk))
        errs = {
            "dynamics.mass_matrix": np.abs(pin.mass(qk) - mj.mass(qk)).max(),
            "dynamics.gravity": np.abs(pin.gravity(qk) - mj.gravity(qk)).max(),
            "dynamics.bias": np.abs(pin.bias(qk, v) - mj.bias(qk, v)).max(),
            "dynamics.inverse": np.abs(pin.inverse(qk, v, a) - mj.inverse(qk, v, a)).max(),
        }
        for prop, e in errs.items():
            stats[prop].update(np.array([e]), qk[None])
    return [_check(p, s, _tol(options, p)) for p, s in stats.items()]


def parameter_checks(pin: PinocchioDynamics, mj: MujocoDynamics, spec, armature_origin: str, options=None) -> tuple[list[Check], list[list]]:
    """Checks on joint damping, friction and armature, and a per-joint table for the report."""
    checks, rows = [], []
    for prop, urdf_vals, mjcf_vals in (("dynamics.damping", pin.damping, mj.damping), ("dynamics.friction", pin.friction, mj.friction)):
        st = ErrorStats()
        st.update(np.array([np.abs(urdf_vals - mjcf_vals).max()]), np.zeros((1, len(urdf_vals))))
        checks.append(_check(prop, st, _tol(options, prop), ("urdf", "mjcf"), frame="parameters"))
    if armature_origin == "spec":
        spec_arm = np.array([j.armature for j in spec.joints])
        st = ErrorStats()
        st.update(np.array([np.abs(spec_arm - mj.armature).max()]), np.zeros((1, len(spec_arm))))
        checks.append(_check("dynamics.armature", st, _tol(options, "dynamics.armature"), ("spec", "mjcf"),
                             note="URDF cannot express armature; Pinocchio's is taken from the spec", frame="parameters"))
    arm_pin = np.array(pin.model.armature)[pin.idx_v]
    for i in range(len(mj.vadr)):
        rows.append([i, f"{pin.damping[i]:.6g}", f"{mj.damping[i]:.6g}", f"{pin.friction[i]:.6g}", f"{mj.friction[i]:.6g}",
                     f"URDF cannot express; taken from the {armature_origin} ({arm_pin[i]:.6g})", f"{mj.armature[i]:.6g}"])
    return checks, rows


def forward_check(pin: PinocchioDynamics, mj: MujocoDynamics, lower, upper, effort, options=None) -> Check:
    """``tracking.forward``: feed-forward torques of a short quintic (inverse dynamics of the plan,
    clipped to the effort limits) integrated by MuJoCo (``mj_step``, Euler) and by Pinocchio
    (ABA with MuJoCo's Euler step); max joint difference along the way. The torques go in as
    ``qfrc_applied`` so actuator ``ctrlrange`` and actuator type cannot interfere."""
    import mujoco

    lower, upper = np.asarray(lower), np.asarray(upper)
    mid, span = (lower + upper) / 2, np.minimum(upper - lower, 1.0)
    dt = mj.model.opt.timestep
    plan = quintic(mid - 0.2 * span, mid + 0.2 * span, FORWARD_SECONDS, dt)
    m, d = mj.model, mj.data
    integrator = mujoco.mjtIntegrator(m.opt.integrator).name
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER  # the step Pinocchio reproduces
    mujoco.mj_resetData(m, d)
    d.qpos[mj.qadr] = plan.q[0]
    qp, vp = plan.q[0].copy(), np.zeros(len(lower))
    stats = ErrorStats()
    for k in range(len(plan.t) - 1):
        tau = np.clip(pin.inverse(plan.q[k], plan.qd[k], plan.qdd[k]), -effort, effort)
        d.ctrl[:] = 0.0
        d.qfrc_applied[:] = 0.0
        d.qfrc_applied[mj.vadr] = tau
        mujoco.mj_step(m, d)
        qp, vp = pin.step_euler(qp, vp, tau, dt)
        qm = d.qpos[mj.qadr]
        stats.update(np.array([np.abs(qm - qp).max()]), qm[None])
    note = f"{FORWARD_SECONDS} s quintic, feed-forward torques as qfrc_applied, {len(plan.t) - 1} Euler steps of {dt:g} s"
    if integrator != "mjINT_EULER":
        note += f" (the MJCF asks for {integrator}; compared under Euler)"
    return _check("tracking.forward", stats, _tol(options, "tracking.forward"), note=note)


def dynamics_suite(ctx):
    from ..verify import SuiteResult

    sources, opts = ctx.sources, ctx.options
    if not sources.urdf or not sources.mjcf:
        return SuiteResult([], {"title": "Dynamics", "summary": "skipped: needs both a URDF and an MJCF", "notes": []})
    try:
        pin, mj, origin = build_models(sources)
    except KinverifyError as err:  # e.g. a file-mode URDF with more joints than are compared
        return SuiteResult([], {"title": "Dynamics", "summary": f"skipped: {err}", "tables": [], "figures": [], "notes": []})
    spec = sources.spec
    vmax = np.array([j.limits.velocity for j in spec.joints]) if spec is not None else np.full(len(sources.joint_names), 3.0)
    effort = np.array([j.limits.effort for j in spec.joints]) if spec is not None else np.full(len(sources.joint_names), 100.0)
    n = int(opts.extra.get("dynamics_samples", DEFAULT_SAMPLES))
    checks = state_checks(pin, mj, ctx.q[:n], vmax, opts.seed, opts)
    snapped = mj.snapped_inertia_frames()
    quirk = ("MuJoCo treats the principal inertia axes of " + ", ".join(f"{b} (rotated {a:.2g} rad)" for b, a in snapped)
             + " as aligned with the body frame (body_sameframe): differences of that order come from MuJoCo") if snapped else ""
    if quirk:
        checks = [dataclasses.replace(c, note=quirk) for c in checks]
    params, rows = parameter_checks(pin, mj, spec, origin, opts)
    checks += params
    checks.append(forward_check(pin, mj, sources.lower, sources.upper, effort, opts))
    section = {
        "title": "Dynamics: URDF (Pinocchio) vs MJCF (MuJoCo)",
        "summary": f"{min(n, len(ctx.q))} configurations with random joint speeds and accelerations; "
                   f"{sum(c.passed for c in checks)} of {len(checks)} checks pass.",
        "tables": [
            {"title": "Checks", "columns": ["property", "max error", "tolerance", "worst q", "ok"],
             "rows": [[c.property, f"{c.max_error:.3e} {c.unit}", f"{c.tolerance:.0e}", ", ".join(f"{x:.4g}" for x in c.worst_q),
                       "ok" if c.passed else "FAIL"] for c in checks]},
            {"title": "Joint parameters", "columns": ["joint", "damping URDF", "damping MJCF", "friction URDF",
                                                       "frictionloss MJCF", "armature (Pinocchio)", "armature MJCF"],
             "rows": [[sources.joint_names[r[0]]] + r[1:] for r in rows]},
        ],
        "figures": [],
        "notes": ([quirk] if quirk else []) + [f"URDF cannot express joint armature: Pinocchio's model.armature is taken from the {origin}; "
                  "Pinocchio's crba/rnea/aba include it.",
                  "Damping is applied as -D·q̇ on the Pinocchio side (its algorithms ignore model.damping); "
                  "mj_inverse includes it as a passive force."],
    }
    return SuiteResult(checks, section)
