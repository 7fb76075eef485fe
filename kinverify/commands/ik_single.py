"""``kinverify ik MODEL --target X Y Z [--rpy R P Y]``: one target on a spec, its solutions, their
residual and the backends whose FK confirms them (see :mod:`kinverify.commands.ik`).

The solve starts once the solver backend's library is loaded; the confirming backends' libraries
(MuJoCo, yourdfpy: seconds of imports) are loaded after it.
"""

from __future__ import annotations

from kinverify.text import shown

CONFIRM_TOL = 1e-6  # m and rad
ALL_STARTS = 32  # random starts for --all-solutions


def spec_model(args, default: str):
    """``(spec, sources, frame, backend name, FrameModel)`` for ``args.model``; an InputError for
    a floating base, an unknown frame or a backend without Jacobians. Only the solver backend's
    library is imported (and the analytic chain's, for restart seeds)."""
    from kinverify.backends import ModelSources, available_backends, build_backend
    from kinverify.errors import InputError, UnknownNameError
    from kinverify.ik import FrameModel
    from kinverify.model.specfile import load_spec

    spec = load_spec(args.model)
    if spec.floating:
        raise InputError(
            f"{args.model}: the base floats, so moving it reaches every target; IK is not run for floating-base models"
        )
    sources = ModelSources.from_spec(spec)
    frame = args.frame or sources.frames[-1]
    if frame not in sources.frames:
        raise UnknownNameError("frame", frame, sources.frames)
    name = args.backend or default
    solver = build_backend(name, sources)
    if not solver.jacobian_method:
        with_jacobians = [
            n for n, info in available_backends().items() if info.available and info.backend_class.jacobian_method == "analytic"
        ]
        raise InputError(f"backend {name!r} has no Jacobian; choose one of: {', '.join(with_jacobians)}")
    model = FrameModel(solver, frame, sources.revolute)
    if model.chain is None:  # restart seeds from the spec's chain (any FK of the frame gives usable seeds)
        model.seed_model = FrameModel(build_backend("analytic", sources), frame, sources.revolute)
    return spec, sources, frame, name, model


def solve_one(args, xyz: list[float], rpy: list[float]) -> int:
    import numpy as np

    from kinverify.backends import backend_info, build_backends
    from kinverify.errors import InputError
    from kinverify.ik import Arm3ClosedForm, IKOptions, residuals, solve_lm
    from kinverify.model.transforms import make_transform, rpy_to_matrix

    # only the solver's library is imported before the solve; the confirming backends load after it
    default = "pinocchio-urdf" if backend_info("pinocchio-urdf").available else "analytic"
    spec, sources, frame, name, model = spec_model(args, default)
    position_only = not rpy
    target = make_transform(rpy_to_matrix(rpy) if rpy else np.eye(3), xyz)
    lower, upper = np.asarray(sources.lower), np.asarray(sources.upper)
    starts = ALL_STARTS if args.all_solutions else 1
    # one solution: start from the best stored configuration; every solution: 32 different random starts
    opts = IKOptions(seed=args.seed, start="given" if args.all_solutions else "seeded")
    sol = solve_lm(model, np.repeat(target[None], starts, axis=0), lower, upper, position_only, opts)
    kind = "position" if position_only else "pose"
    print(
        f"{shown(spec.name)}: {kind} target for {shown(frame)}: xyz = {_fmt(xyz)} m"
        + (f", rpy = {_fmt(rpy)} rad" if rpy else "")
        + f"; solver lm on {name}"
    )
    closed = None
    if position_only:
        try:
            closed = Arm3ClosedForm.from_spec(spec, frame if frame in spec.tool_names else None)
        except InputError:
            closed = None
    tol_pos, tol_rot = getattr(args, "tol_pos", CONFIRM_TOL), getattr(args, "tol_rot", CONFIRM_TOL)
    ok = sol.solved(tol_pos, tol_rot)
    if not ok.any():
        k = int(np.argmin(sol.pos_error + sol.rot_error))
        print(
            f"unreachable: not solved within the budget ({int(sol.restarts[k]) + 1} starts); closest approach "
            f"{sol.pos_error[k]:.3e} m" + ("" if position_only else f", {sol.rot_error[k]:.3e} rad") + f" at q = {_fmt(sol.q[k])}"
        )
        if closed is not None:
            res = closed.solve(xyz)
            print(
                f"closed form: {'reachable' if res.reachable else 'unreachable'}, closest approach {res.closest_distance:.3e} m"
            )
        return 1
    solutions = _distinct(sol.q[ok], sources.revolute)
    for i, q in enumerate(solutions):  # the answer first: the confirming libraries take seconds to import
        pos, rot = residuals(model.poses(q[None]), target[None], position_only)
        print(
            f"solution {i + 1}: q = {_fmt(q)} rad  residual {pos[0]:.2e} m" + ("" if position_only else f", {rot[0]:.2e} rad"),
            flush=True,
        )
    others = [b for b in build_backends(sources) if b.name != name and frame in b.frames]
    all_confirmed = True
    for i, q in enumerate(solutions):
        confirmed: list[str]
        disagree: list[str]
        confirmed, disagree = [], []
        for other in others:
            p = other.evaluate(q[None], with_jacobians=False).poses[:, other.frames.index(frame)]
            e_pos, e_rot = residuals(p, target[None], position_only or not other.has_rotation)
            agrees = e_pos[0] <= tol_pos and e_rot[0] <= tol_rot
            (confirmed if agrees else disagree).append(f"{other.name} ({max(e_pos[0], e_rot[0]):.1e})")
        print(
            f"solution {i + 1} confirmed by: {', '.join(confirmed) or 'none'}"
            + (f"; DISAGREE: {', '.join(disagree)}" if disagree else "")
        )
        all_confirmed &= not disagree
    if closed is not None and args.all_solutions:
        res = closed.solve(xyz)
        print(f"closed form: {len(res.solutions)} branch(es) inside the limits")
        for q in res.solutions:
            print(f"  q = {_fmt(q)} rad")
    print(f"{len(solutions)} solution(s); median {np.median(sol.time_s) * 1e3:.2f} ms, {int(sol.iterations.sum())} iterations")
    return 0 if all_confirmed else 1


def _distinct(qs, revolute, tol: float = 1e-6):
    out: list = []
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
