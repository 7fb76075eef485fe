"""``kinverify ik``: solve one IK target, print the solutions, residual and confirming backends.

Exit 0 when a solution is found and every other backend's FK confirms it, 1 when the target is
not reached (unreachable: the closest approach is printed) or a backend disagrees, 2 bad input.
"""

from __future__ import annotations

import math

CONFIRM_TOL = 1e-6  # m and rad
ALL_STARTS = 32  # random starts for --all-solutions


def add_parser(sub):
    p = sub.add_parser("ik", help="solve inverse kinematics for one target and cross-check it on every backend",
                       description="Solve IK for MODEL's tool frame with the Levenberg-Marquardt solver on one backend, "
                       "then put each solution through every other backend's FK. Position-only unless --rpy is given.")
    p.add_argument("model", help="spec file (models/*.toml)")
    p.add_argument("--target", nargs="+", required=True, metavar="X", help="target position X Y Z [m]")
    p.add_argument("--rpy", nargs="+", metavar="R", help="target orientation roll pitch yaw [rad] (URDF fixed-axis XYZ)")
    p.add_argument("--backend", help="solver backend (default pinocchio-urdf, else analytic)")
    p.add_argument("--frame", help="frame to place (default: the last tool frame)")
    p.add_argument("--all-solutions", action="store_true",
                   help=f"every distinct solution found from {ALL_STARTS} random starts (every closed-form branch for arm3)")
    p.add_argument("--seed", type=int, default=0, help="random seed for the starts (default 0)")
    return p


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
        out.append(x)
    return out


def run(args) -> int:
    import numpy as np

    from kinverify.backends import ModelSources, available_backends, build_backend, build_backends
    from kinverify.errors import InputError, UnknownNameError
    from kinverify.ik import Arm3ClosedForm, FrameModel, IKOptions, residuals, solve_lm
    from kinverify.model.specfile import load_spec
    from kinverify.model.transforms import make_transform, rpy_to_matrix

    xyz = _values("--target", args.target, 3)
    rpy = _values("--rpy", args.rpy, 3)
    spec = load_spec(args.model)
    sources = ModelSources.from_spec(spec)
    frame = args.frame or sources.frames[-1]
    if frame not in sources.frames:
        raise UnknownNameError("frame", frame, sources.frames)
    registry = available_backends()
    name = args.backend or ("pinocchio-urdf" if registry["pinocchio-urdf"].available else "analytic")
    if name not in registry:
        raise UnknownNameError("backend", name, list(registry))
    solver = build_backend(name, sources)
    if not solver.jacobian_method:
        with_jacobians = [n for n, info in registry.items() if info.available and info.backend_class.jacobian_method == "analytic"]
        raise InputError(f"backend {name!r} has no Jacobian; choose one of: {', '.join(with_jacobians)}")
    position_only = not rpy
    target = make_transform(rpy_to_matrix(rpy) if rpy else np.eye(3), xyz)
    model = FrameModel(solver, frame, sources.revolute)
    lower, upper = np.asarray(sources.lower), np.asarray(sources.upper)
    starts = ALL_STARTS if args.all_solutions else 1
    sol = solve_lm(model, np.repeat(target[None], starts, axis=0), lower, upper, position_only, IKOptions(seed=args.seed))
    kind = "position" if position_only else "pose"
    print(f"{spec.name}: {kind} target for {frame}: xyz = {_fmt(xyz)} m" + (f", rpy = {_fmt(rpy)} rad" if rpy else "")
          + f"; solver lm on {name}")
    closed = None
    if position_only:
        try:
            closed = Arm3ClosedForm.from_spec(spec, frame if frame in spec.tool_names else None)
        except InputError:
            closed = None
    ok = sol.success
    if not ok.any():
        k = int(np.argmin(sol.pos_error + sol.rot_error))
        print(f"unreachable: not solved within the budget ({int(sol.restarts[k]) + 1} starts); closest approach "
              f"{sol.pos_error[k]:.3e} m" + ("" if position_only else f", {sol.rot_error[k]:.3e} rad")
              + f" at q = {_fmt(sol.q[k])}")
        if closed is not None:
            res = closed.solve(xyz)
            print(f"closed form: {'reachable' if res.reachable else 'unreachable'}, closest approach {res.closest_distance:.3e} m")
        return 1
    solutions = _distinct(sol.q[ok], sources.revolute)
    others = [b for b in build_backends(sources) if b.name != name and frame in b.frames]
    all_confirmed = True
    for i, q in enumerate(solutions):
        pos, rot = residuals(model.poses(q[None]), target[None], position_only)
        print(f"solution {i + 1}: q = {_fmt(q)} rad  residual {pos[0]:.2e} m" + ("" if position_only else f", {rot[0]:.2e} rad"))
        confirmed, disagree = [], []
        for other in others:
            p = other.evaluate(q[None], with_jacobians=False).poses[:, other.frames.index(frame)]
            e_pos, e_rot = residuals(p, target[None], position_only or not other.has_rotation)
            (confirmed if max(e_pos[0], e_rot[0]) <= CONFIRM_TOL else disagree).append(f"{other.name} ({max(e_pos[0], e_rot[0]):.1e})")
        print(f"  confirmed by: {', '.join(confirmed) or 'none'}" + (f"; DISAGREE: {', '.join(disagree)}" if disagree else ""))
        all_confirmed &= not disagree
    if closed is not None and args.all_solutions:
        res = closed.solve(xyz)
        print(f"closed form: {len(res.solutions)} branch(es) inside the limits")
        for q in res.solutions:
            print(f"  q = {_fmt(q)} rad")
    print(f"{len(solutions)} solution(s); median {np.median(sol.time_s) * 1e3:.2f} ms, {int(sol.iterations.sum())} iterations")
    return 0 if all_confirmed else 1


def _distinct(qs, revolute, tol: float = 1e-6):
    out = []
    for q in qs:
        if not any(_joint_distance(q, p, revolute) <= tol for p in out):
            out.append(q)
    return out


def _joint_distance(a, b, revolute) -> float:
    import numpy as np

    d = a - b
    d = np.where(revolute, np.angle(np.exp(1j * d)), d)
    return float(np.abs(d).max())


def _fmt(v) -> str:
    return "[" + ", ".join(f"{float(x):.9g}" for x in v) + "]"
