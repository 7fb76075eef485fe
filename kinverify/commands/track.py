"""``kinverify track MODEL``: plan a quintic, execute it in MuJoCo under a controller, judge it.

Exit 0 when every checked controller tracks within its criteria, 1 when one fails (e.g.
``--controller seed-pid``), 2 on bad input (unknown controller, target outside the limits,
non-positive duration, a Cartesian ``--target`` the tool cannot reach: the message gives the
closest approach the IK found).

``--target X Y Z`` (repeatable: Cartesian waypoints) replaces ``--to``: each target is solved by
IK (:mod:`kinverify.tracking.cartesian`) and the joint solution is planned and executed as usual;
the final end-effector error against the (last) target is reported per controller.
"""

from __future__ import annotations

import argparse

from kinverify.text import shown


def _float(text: str) -> float:
    try:
        return float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "track",
        help="plan a quintic trajectory (to joint values, or to a Cartesian target through IK) and execute it in MuJoCo under a controller",
        description="Plan a rest-to-rest quintic from the start configuration to --to, execute it in MuJoCo "
        "on the generated MJCF (model terms from Pinocchio on the generated URDF) and report tracking "
        "metrics. Default: the model's default trajectory (on arm3 the seed's 0 -> (60, 45, -30) deg in 2 s). "
        "--target X Y Z: a Cartesian goal for the tool frame, solved by IK (the solution closest to the start); "
        "the final end-effector error against it is reported.",
    )
    p.add_argument("model", help="spec file (models/*.toml)")
    p.add_argument("--to", nargs="+", type=_float, metavar="Q", help="target joint values (rad, m; degrees with --deg)")
    p.add_argument(
        "--target",
        nargs="+",
        action="append",
        metavar="X",
        help="Cartesian target X Y Z [m] for the tool frame, solved by IK (instead of --to); repeat for waypoints",
    )
    p.add_argument(
        "--rpy",
        nargs="+",
        action="append",
        metavar="R",
        help="target orientation roll pitch yaw [rad], one per --target (full pose: arms with >= 6 joints)",
    )
    p.add_argument("--ik-backend", help="IK solver backend: pinocchio-urdf (default) or analytic")
    p.add_argument("--deg", action="store_true", help="--to revolute values are in degrees")
    p.add_argument(
        "--duration",
        type=_float,
        help="motion time in s, per segment with --target (default: the default trajectory's; with --target, "
        "also long enough to keep each joint's peak speed at <= 80 %% of its limit and <= 1 rad/s)",
    )
    p.add_argument("--hold", type=_float, help="hold time after the motion in s (default: the default trajectory's)")
    p.add_argument(
        "--controller", default="computed-torque", help="computed-torque (default), pd+gravity, position, seed-pid, or all"
    )
    p.add_argument("--json", help="write the result (kinverify results JSON, section 'tracking') to this path")
    return p


def run(args) -> int:
    import math
    import time
    from datetime import datetime, timezone

    import numpy as np

    from kinverify.backends import ModelSources
    from kinverify.errors import InputError
    from kinverify.model.specfile import load_spec
    from kinverify.tracking.controllers import CONTROLLERS
    from kinverify.tracking.track import Trajectory, default_trajectory, track, validate_target

    controllers = list(CONTROLLERS) if args.controller == "all" else [args.controller]
    if controllers[0] not in CONTROLLERS:
        raise InputError(f"unknown controller {args.controller!r}; controllers: {', '.join(CONTROLLERS)}, all")
    for name, value in (("--duration", args.duration), ("--hold", args.hold)):
        if value is not None and not (math.isfinite(value) and (value > 0 if name == "--duration" else value >= 0)):
            raise InputError(f"{name} must be {'positive' if name == '--duration' else 'non-negative'}, got {value:g}")
    if args.target is not None and args.to is not None:
        raise InputError("--target and --to are mutually exclusive: give a Cartesian or a joint-space target")
    spec = load_spec(args.model)
    default = default_trajectory(spec)
    if args.target is not None:
        return _run_cartesian(args, spec, default, controllers)
    q1 = default.q1
    if args.to is not None:
        q1 = np.array(args.to, dtype=float)
        if args.deg and q1.shape == (spec.dof,):
            q1 = np.array([math.radians(v) if j.type == "revolute" else v for v, j in zip(q1, spec.joints, strict=True)])
    duration = default.duration if args.duration is None else args.duration
    q1 = validate_target(spec, q1, duration)
    trajectory = Trajectory(default.q0, q1, duration, default.hold if args.hold is None else args.hold)
    sources = ModelSources.from_spec(spec)
    assert sources.urdf is not None  # generated from the spec
    started, t0 = datetime.now(timezone.utc), time.perf_counter()
    result = track(spec, sources.urdf, trajectory, controllers, options=_gated())
    return _report(args, spec, result, started, t0)


def _gated():
    """``kinverify track`` is asked about the controllers' performance: their goals decide its verdict."""
    from kinverify.suites.base import VerifyOptions
    from kinverify.tracking.track import PROPERTIES

    return VerifyOptions(gates={name: None for name in PROPERTIES})


def _report(args, spec, result, started, t0, cartesian=None) -> int:
    import shlex
    import time

    from kinverify.text import console as text_console, markup

    from kinverify.report.terminal import track_table as metrics_table
    from kinverify.results import VerifyResult
    from kinverify.versions import library_versions

    console = text_console()  # the terminal's width: the table fits it
    console.print(metrics_table(spec, result, console))
    for m in result.metrics:
        if not m.passed:
            console.print(f"[red]{markup(m.controller)} fails:[/] {markup(m.reason)}")
    for c in result.checks:
        if c.property == "tracking.plan" and not c.passed:
            console.print(f"[red]plan outside limits:[/] {markup(c.note)}")
    if cartesian is not None:
        _ee_errors(console, spec, result, cartesian)
    passed = all(c.passed for c in result.checks)  # every check is gated here
    if args.json:
        from kinverify.report import write_json

        vr = VerifyResult(
            model=spec.name,
            source=str(args.model),
            seed=0,
            samples=len(result.runs[0].plan.t),
            joint_names=list(spec.joint_names),
            frames=list(spec.frame_names),
            backends=["pinocchio-urdf", "mujoco"],
            checks=result.checks,
            versions=library_versions(),
            command="kinverify " + shlex.join(args.argv),
            started=started.isoformat(timespec="seconds"),
            duration_s=time.perf_counter() - t0,
            lower=list(spec.lower),
            upper=list(spec.upper),
            sections={"tracking": result.section},
        )
        console.print(f"json: {markup(write_json(vr, args.json))}")
    console.print(f"verdict: {'PASS' if passed else 'FAIL'}")
    return 0 if passed else 1


def _run_cartesian(args, spec, default, controllers) -> int:
    """``--target``: IK for each Cartesian target, then plan, execute and report as for ``--to``."""
    import time
    from datetime import datetime, timezone

    from kinverify.backends import ModelSources
    from kinverify.errors import InputError
    from kinverify.tracking.cartesian import parse_target, plan_cartesian, track_waypoints
    from kinverify.tracking.track import Trajectory, track

    if args.deg:
        raise InputError("--deg applies to --to only; --target is in m and --rpy in rad")
    rpys = args.rpy or []
    if rpys and len(rpys) != len(args.target):
        raise InputError(f"give one --rpy per --target or none, got {len(rpys)} for {len(args.target)}")
    parsed = [parse_target(xyz, rpys[k] if rpys else None) for k, xyz in enumerate(args.target)]
    from kinverify.pipeline.limits import MAX_TARGET_M

    for t, _ in parsed:
        if not abs(t[:3, 3]).max() <= MAX_TARGET_M:
            raise InputError(
                f"--target {_vec(t[:3, 3])} m is more than {MAX_TARGET_M:g} m from the base (see docs/robustness.md)"
            )
    position_only = not rpys
    durations = None if args.duration is None else [args.duration]
    cplan = plan_cartesian(
        spec, [t for t, _ in parsed], default.q0, durations, position_only, args.ik_backend, min_duration=default.duration
    )
    kind = "position" if position_only else "pose"
    print(
        f"{shown(spec.name)}: {len(parsed)} {kind} target(s) for {shown(cplan.frame)}, IK by lm on {cplan.backend} "
        f"(closest of the solutions to the previous configuration)"
    )
    for k, c in enumerate(cplan.choices):
        print(
            f"  target {k + 1}: xyz = {_vec(c.target[:3, 3])} m -> q = {_vec(c.q)} rad  (IK residual {c.pos_error:.1e} m"
            + ("" if position_only else f", {c.rot_error:.1e} rad")
            + f"; {c.candidates} distinct solution(s), "
            f"joint distance {c.distance:.3g}, via {c.source}; segment {cplan.durations[k]:g} s)"
        )
    hold_s = default.hold if args.hold is None else args.hold
    sources = ModelSources.from_spec(spec)
    assert sources.urdf is not None  # generated from the spec
    started, t0 = datetime.now(timezone.utc), time.perf_counter()
    if len(cplan.choices) == 1:
        result = track(
            spec,
            sources.urdf,
            Trajectory(cplan.q_start, cplan.choices[0].q, cplan.durations[0], hold_s),
            controllers,
            options=_gated(),
        )
    else:
        result = track_waypoints(spec, sources.urdf, cplan, hold_s, controllers, options=_gated())
    return _report(args, spec, result, started, t0, cartesian=cplan)


def _ee_errors(console, spec, result, cplan) -> None:
    """Print each run's end-effector error against the (last) Cartesian target and record it in
    the section (``cartesian``: the IK solutions and the errors; one note per run)."""
    from kinverify.tracking.cartesian import end_effector_errors, end_of_motion_index

    target = cplan.choices[-1].target
    errors = []
    for run in result.runs:
        at_end = end_effector_errors(spec, cplan.frame, run.q[end_of_motion_index(run)], target, cplan.position_only)
        after = end_effector_errors(spec, cplan.frame, run.q[-1], target, cplan.position_only)

        def rot(e):
            return "" if cplan.position_only else f", {e[1]:.3e} rad"

        line = (
            f"{run.controller}: final end-effector error against the Cartesian target {at_end[0]:.3e} m{rot(at_end)} "
            f"at the end of the motion, {after[0]:.3e} m{rot(after)} at the end of the hold"
        )
        console.print(line, markup=False, highlight=False)
        result.section.notes.append(line)
        errors.append(
            {
                "controller": run.controller,
                "position_error_end_of_motion": at_end[0],
                "rotation_error_end_of_motion": at_end[1],
                "position_error_end_of_hold": after[0],
                "rotation_error_end_of_hold": after[1],
            }
        )
    result.section.data["cartesian"] = {
        "frame": cplan.frame,
        "ik_backend": cplan.backend,
        "position_only": cplan.position_only,
        "targets": [c.target.tolist() for c in cplan.choices],
        "q": [c.q.tolist() for c in cplan.choices],
        "ik_position_error": [c.pos_error for c in cplan.choices],
        "ik_rotation_error": [c.rot_error for c in cplan.choices],
        "durations": list(cplan.durations),
        "end_effector_errors": errors,
    }


def _vec(v) -> str:
    return "[" + ", ".join(f"{float(x):.6g}" for x in v) + "]"
