"""``kinverify ik``: solve IK for one target or a file of them, on a spec or on any URDF.

- ``kinverify ik MODEL --target X Y Z [--rpy R P Y]``: the solutions, their residual and the
  backends whose FK confirms them (exit 1 when the target is not reached or a backend disagrees).
- ``kinverify ik --urdf FILE --base LINK --tip LINK --targets FILE.npy [--initial FILE.npy]
  [--json OUT]`` (``--targets`` also works with a spec MODEL, ``--target`` with ``--urdf``): every
  target solved (batched numpy by default, ``--per-target`` for Pinocchio one target at a time),
  ``success_rate``, ``median_ms`` and ``p99_ms`` printed (solve time only) and written to the JSON
  with per-target records; exit 0 when every target is solved, 1 when one is not.

Bad input (files, shapes, non-finite values, unknown links) is exit 2 with one line.
"""

from __future__ import annotations

import math

from kinverify.commands.ik_single import ALL_STARTS
from kinverify.pipeline.limits import MAX_TARGET_M
from kinverify.text import shown


def add_parser(sub):
    p = sub.add_parser(
        "ik",
        help="solve inverse kinematics for a target or a file of targets, on a spec or any URDF",
        description="Solve IK with kinverify's Levenberg-Marquardt solver. On a spec MODEL with --target: "
        "the solutions and every other backend's FK of them (position-only unless --rpy). With --urdf "
        "FILE --base LINK --tip LINK (or a MODEL) and --targets FILE.npy: every target, solved together, "
        "with success_rate, median_ms and p99_ms (solve time per target, start-up excluded). "
        "Exit 0 when solved (and confirmed), 1 when a target is not reached or a backend disagrees, "
        "2 on bad input.",
    )
    p.add_argument("model", nargs="?", help="spec file (models/*.toml); omit with --urdf")
    p.add_argument("--urdf", metavar="FILE", help="an existing URDF; the chain from --base to --tip is solved")
    p.add_argument("--base", metavar="LINK", help="with --urdf: the chain's base link (default: the URDF's root link)")
    p.add_argument("--tip", metavar="LINK", help="with --urdf: the chain's tip link")
    p.add_argument(
        "--package",
        action="append",
        default=[],
        metavar="NAME=PATH",
        help="with a .xacro --urdf: where ROS package NAME is (repeatable; $(find NAME), package://NAME)",
    )
    p.add_argument(
        "--xacro-arg",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="with a .xacro --urdf: a <xacro:arg> value (repeatable)",
    )
    p.add_argument("--target", nargs="+", metavar="X", help="one target position X Y Z [m]")
    p.add_argument("--rpy", nargs="+", metavar="R", help="its orientation roll pitch yaw [rad] (URDF fixed-axis XYZ)")
    p.add_argument("--targets", metavar="FILE.npy", help="N×4×4 poses of the tip in the base frame [m], solved together")
    p.add_argument(
        "--initial",
        metavar="FILE.npy",
        help="with --targets: N×n initial guesses in chain joint order, where "
        "each first attempt starts (default: the stored configuration whose tip pose is nearest the target)",
    )
    p.add_argument("--position-only", action="store_true", help="with --targets: reach the positions only")
    p.add_argument(
        "--tol-pos", default="1e-6", metavar="M", help="solved (and confirmed) within this position error (default 1e-6 m)"
    )
    p.add_argument("--tol-rot", default="1e-6", metavar="RAD", help="and this rotation error (default 1e-6 rad)")
    p.add_argument(
        "--per-target",
        action="store_true",
        help="with --targets: solve one target at a time on Pinocchio, each "
        "timed alone (default: all at once in numpy, time = batch time / N)",
    )
    p.add_argument("--json", metavar="OUT", help="with --targets (or --urdf): write per-target results and the summary")
    p.add_argument("--backend", help="spec mode: solver backend (default pinocchio-urdf for --target, analytic for --targets)")
    p.add_argument("--frame", help="spec mode: frame to place (default: the last tool frame)")
    p.add_argument(
        "--all-solutions",
        action="store_true",
        help=f"--target on a spec: every distinct solution from {ALL_STARTS} random starts (every closed-form branch for arm3)",
    )
    p.add_argument("--seed", type=int, default=0, help="random seed for starts and restarts (default 0)")
    return p


def _tolerance(flag: str, text: str) -> float:
    from kinverify.errors import InputError

    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{flag}: expected a number, got {text!r}") from None
    if not (value > 0 and math.isfinite(value)):
        raise InputError(f"{flag}: must be a positive finite number, got {text!r}")
    return value


def _values(name: str, values, count: int) -> list[float]:
    from kinverify.errors import InputError

    if values is None:
        return []
    if len(values) != count:
        raise InputError(f"{name} needs {count} values, got {len(values)}")
    out = []
    for v in values:
        try:
            x = float(v)
        except ValueError:
            raise InputError(f"{name}: not a number: {v!r}") from None
        if not math.isfinite(x):
            raise InputError(f"{name}: values must be finite, got {v!r}")
        if name == "--target" and abs(x) > MAX_TARGET_M:
            raise InputError(f"{name}: {v} m is more than {MAX_TARGET_M:g} m from the base (see docs/robustness.md)")
        out.append(x)
    return out


def run(args) -> int:
    from kinverify.errors import InputError

    if bool(args.model) == bool(args.urdf):
        raise InputError(
            "give a spec MODEL or --urdf FILE (with --base and --tip), not both"
            if args.model
            else "give a spec MODEL (models/*.toml) or --urdf FILE --base LINK --tip LINK"
        )
    if bool(args.target) == bool(args.targets):
        raise InputError(
            "give --target X Y Z or --targets FILE.npy" if not args.target else "give --target or --targets, not both"
        )
    if args.urdf and not args.tip:
        raise InputError("--urdf needs --tip LINK (and --base LINK, default the root link)")
    if not args.urdf and (args.base or args.tip or args.package or args.xacro_arg):
        raise InputError("--base, --tip, --package and --xacro-arg go with --urdf")
    for flag, value in (("--initial", args.initial), ("--position-only", args.position_only), ("--per-target", args.per_target)):
        if value and not args.targets:
            raise InputError(f"{flag} goes with --targets")
    args.tol_pos, args.tol_rot = _tolerance("--tol-pos", args.tol_pos), _tolerance("--tol-rot", args.tol_rot)
    if args.urdf or args.targets:
        return _batch(args)
    if args.json:
        raise InputError("--json goes with --targets or --urdf")
    from kinverify.commands.ik_single import solve_one

    return solve_one(args, _values("--target", args.target, 3), _values("--rpy", args.rpy, 3))


def _batch(args) -> int:
    import os

    import numpy as np

    from kinverify import __version__
    from kinverify.ik import IKOptions, solve_lm
    from kinverify.ik.files import json_bytes, load_initial, load_targets, results_json

    model, lower, upper, joints, where = _batch_model(args)
    if args.targets:
        targets = load_targets(args.targets)
    else:
        from kinverify.model.transforms import make_transform, rpy_to_matrix

        xyz, rpy = _values("--target", args.target, 3), _values("--rpy", args.rpy, 3)
        targets = make_transform(rpy_to_matrix(rpy) if rpy else np.eye(3), xyz)[None]
    position_only = args.position_only or (bool(args.target) and not args.rpy)
    n = len(joints)
    q0 = load_initial(args.initial, len(targets), n) if args.initial else None
    outside = 0 if q0 is None else int(np.any((q0 < lower) | (q0 > upper), axis=1).sum())
    # without initial guesses the first attempt starts from the best stored configuration (nearer than a random one)
    opts = IKOptions(tol_pos=args.tol_pos, tol_rot=args.tol_rot, seed=args.seed, start="given" if args.initial else "seeded")
    sol = solve_lm(model, targets, lower, upper, position_only, opts, q0=q0, batch=not args.per_target)
    data = results_json(
        sol,
        joints,
        lower,
        upper,
        args.tol_pos,
        args.tol_rot,
        kinverify=__version__,
        command="kinverify " + " ".join(getattr(args, "argv", [])),
        model=where,
        solver=f"lm on {sol.backend}" + (" (batched)" if sol.batched else " (per target)"),
        initial_outside_limits=outside,
    )
    kind = "position" if position_only else "full-pose"
    how = "batched: batch time / N" if sol.batched else "per target"
    print(
        f"{shown(where)}: {len(targets)} {kind} target(s), {n} joints; {data['solver']}"
        + (f"; {outside} initial guess(es) outside the limits were moved onto them" if outside else "")
    )
    print(
        f"success_rate {100 * data['success_rate']:.2f} % ({data['solved']}/{data['targets']} within {args.tol_pos:g} m"
        + ("" if position_only else f" / {args.tol_rot:g} rad")
        + f")  median_ms {data['median_ms']:.4g}  "
        f"p99_ms {data['p99_ms']:.4g}  (solve time per target, {how})"
    )
    if len(targets) == 1 and sol.solved(args.tol_pos, args.tol_rot)[0]:
        print(f"q = [{', '.join(f'{x:.9g}' for x in sol.q[0])}]")
    if args.json:
        from kinverify.io.write import write_atomic

        path = write_atomic(args.json, json_bytes(data))
        print(f"json: {shown(os.fspath(path))}")
    return 0 if data["solved"] == data["targets"] else 1


def _urdf_text(args):
    """The --urdf file's text (a xacro file compiled first: ``--package``, ``--xacro-arg``) and its
    root element, checked as file mode checks a URDF (one tree of links, finite poses) before
    the chain is walked or Pinocchio reads it."""
    from kinverify.errors import InputError
    from kinverify.filemode.read.xacro import compile_xacro, is_xacro, parse_pairs
    from kinverify.ik.files import read_text
    from kinverify.io.formats import xml_parse
    from kinverify.io.models import check_urdf_numbers, check_urdf_tree

    text = read_text(args.urdf, "--urdf")
    packages, xacro_args = parse_pairs(args.package, "--package"), parse_pairs(args.xacro_arg, "--xacro-arg")
    if is_xacro(args.urdf, text):
        text = compile_xacro(args.urdf, packages, xacro_args)[0]
    elif xacro_args:
        raise InputError(f"--xacro-arg: {args.urdf} is not a xacro file")
    root = xml_parse(text.encode(), args.urdf, "--urdf")
    if root.tag != "robot":
        raise InputError(f"--urdf: {args.urdf} is not a URDF (root element <{root.tag}>, expected <robot>)")
    check_urdf_tree(root, args.urdf, "--urdf")
    check_urdf_numbers(root, args.urdf, "--urdf")
    return text, root


def _batch_model(args):
    """``(FrameModel, lower, upper, joint names, label)`` of the URDF chain or the spec's frame."""
    import numpy as np

    from kinverify.errors import InputError
    from kinverify.ik import FrameModel, SerialChain

    if args.urdf:
        text, root = _urdf_text(args)
        chain = SerialChain.from_urdf_root(root, args.base, args.tip, args.urdf)
        where = f"{args.urdf}: {args.base or 'root'} -> {args.tip}"
        if args.per_target:
            from kinverify.backends.pinocchio_ import PinocchioBackend
            from kinverify.ik.chain import root_link

            if args.base and args.base != root_link(root, args.urdf):
                raise InputError(
                    f"--per-target solves on Pinocchio, which places frames in the root link; --base {args.base} "
                    "is not the root (drop --per-target to solve the chain in numpy)"
                )
            batched = FrameModel.from_chain(chain, "urdf", args.tip)
            model = FrameModel(PinocchioBackend.from_urdf(text, chain.names, [args.tip]), args.tip, batched.revolute)
            model.seed_model = batched
        else:
            model = FrameModel.from_chain(chain, "numpy chain", args.tip)
        return model, chain.lower, chain.upper, chain.names, where
    from kinverify.commands.ik_single import spec_model

    spec, sources, frame, _, model = spec_model(args, "pinocchio-urdf" if args.per_target else "analytic")
    return model, np.asarray(sources.lower), np.asarray(sources.upper), list(sources.joint_names), f"{spec.name}: {frame}"
