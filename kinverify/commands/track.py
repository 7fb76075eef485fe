"""``kinverify track MODEL``: plan a quintic, execute it in MuJoCo under a controller, judge it.

Exit 0 when every checked controller tracks within its criteria, 1 when one fails (e.g.
``--controller seed-pid``), 2 on bad input (unknown controller, target outside the limits,
non-positive duration).
"""

from __future__ import annotations

import argparse


def _float(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("track", help="execute a quintic joint trajectory in MuJoCo under a controller",
                       description="Plan a rest-to-rest quintic from the start configuration to --to, execute it in MuJoCo "
                       "on the generated MJCF (model terms from Pinocchio on the generated URDF) and report tracking "
                       "metrics. Default: the model's default trajectory (on arm3 the seed's 0 -> (60, 45, -30) deg in 2 s).")
    p.add_argument("model", help="spec file (models/*.toml)")
    p.add_argument("--to", nargs="+", type=_float, metavar="Q", help="target joint values (rad, m; degrees with --deg)")
    p.add_argument("--deg", action="store_true", help="--to revolute values are in degrees")
    p.add_argument("--duration", type=_float, help="motion time in s (default: the default trajectory's)")
    p.add_argument("--hold", type=_float, help="hold time after the motion in s (default: the default trajectory's)")
    p.add_argument("--controller", default="computed-torque",
                   help="computed-torque (default), pd+gravity, position, seed-pid, or all")
    p.add_argument("--json", help="write the result (kinverify results JSON, section 'tracking') to this path")
    return p


def run(args) -> int:
    import math
    import shlex
    import time
    from datetime import datetime, timezone

    import numpy as np
    from rich.console import Console
    from rich.table import Table

    from ..backends import ModelSources
    from ..errors import InputError
    from ..results import VerifyResult
    from ..specfile import load_spec
    from ..tracking.controllers import CONTROLLERS
    from ..tracking.suite import Trajectory, default_trajectory, track, validate_target
    from ..versions import library_versions

    controllers = list(CONTROLLERS) if args.controller == "all" else [args.controller]
    if controllers[0] not in CONTROLLERS:
        raise InputError(f"unknown controller {args.controller!r}; controllers: {', '.join(CONTROLLERS)}, all")
    for name, value in (("--duration", args.duration), ("--hold", args.hold)):
        if value is not None and not (math.isfinite(value) and (value > 0 if name == "--duration" else value >= 0)):
            raise InputError(f"{name} must be {'positive' if name == '--duration' else 'non-negative'}, got {value:g}")
    spec = load_spec(args.model)
    default = default_trajectory(spec)
    q1 = default.q1
    if args.to is not None:
        q1 = np.array(args.to, dtype=float)
        if args.deg and q1.shape == (spec.dof,):
            q1 = np.array([math.radians(v) if j.type == "revolute" else v for v, j in zip(q1, spec.joints)])
    duration = default.duration if args.duration is None else args.duration
    q1 = validate_target(spec, q1, duration)
    trajectory = Trajectory(default.q0, q1, duration, default.hold if args.hold is None else args.hold)
    sources = ModelSources.from_spec(spec)
    started, t0 = datetime.now(timezone.utc), time.perf_counter()
    result = track(spec, sources.urdf, trajectory, controllers)
    console = Console(width=140)
    table = Table(title=f"kinverify track: {spec.name}, {duration:g} s motion + {trajectory.hold:g} s hold")
    for col in ("controller", "RMS error", "max error", "final error", "ee path dev.", "overshoot", "settling",
                "residual speed", "speed at end", ""):
        table.add_column(col)
    for m in result.metrics:
        settle = "-" if m.settling_time is None else f"{m.settling_time:.3f} s"
        table.add_row(m.controller, f"{m.rms_error:.3e} rad", f"{m.max_error:.3e} rad", f"{m.final_error:.3e} rad",
                      f"{m.ee_path_deviation:.3e} m", f"{m.overshoot:.3e} rad", settle, f"{m.residual_speed:.3e} rad/s",
                      f"{m.final_speed:.3e} rad/s", "[green]ok[/]" if m.passed else "[bold red]FAIL[/]")
    console.print(table)
    for m in result.metrics:
        if not m.passed:
            console.print(f"[red]{m.controller} fails:[/] {m.reason}")
    for c in result.checks:
        if c.property == "tracking.plan" and not c.passed:
            console.print(f"[red]plan outside limits:[/] {c.note}")
    passed = all(c.passed for c in result.checks)
    if args.json:
        from ..report import write_json

        vr = VerifyResult(model=spec.name, source=str(args.model), seed=0, samples=len(result.runs[0].plan.t),
                          joint_names=list(spec.joint_names), frames=list(spec.frame_names), backends=["pinocchio-urdf", "mujoco"],
                          checks=result.checks, versions=library_versions(), command="kinverify " + shlex.join(args.argv),
                          started=started.isoformat(timespec="seconds"), duration_s=time.perf_counter() - t0,
                          lower=list(spec.lower), upper=list(spec.upper), sections={"tracking": result.section})
        console.print(f"json: {write_json(vr, args.json)}")
    console.print(f"verdict: {'PASS' if passed else 'FAIL'}")
    return 0 if passed else 1
