"""One probe per registered property: run the property's real suite code on arm3 with one side's
input perturbed by ``delta`` (in the property's unit) and return the resulting check.

A probe changes what one view of the model says, never the comparison: a backend whose FK or
Jacobian is offset, a dynamics model whose mass matrix or parameters are offset, an IK solver
whose answers are moved, an executed trajectory that is off the plan. The contract test
(``test_contract.py``) then asks every property to fail just over its tolerance and pass just
under it, and (for continuous measures) to report the perturbation's size as its error.
"""

from __future__ import annotations

import dataclasses
import math
import re
from functools import lru_cache
from typing import Callable

import numpy as np

from kinverify.backends import ModelSources, build_backend
from kinverify.backends.base import BackendBase, Evaluation
from kinverify.model.specfile import load_spec
from kinverify.pipeline.sampling import Samples
from kinverify.suites.base import Check, VerifyContext, VerifyOptions
from kinverify.suites.dynamics import DynamicsSuite
from kinverify.suites.ik import IKSuite
from kinverify.suites.inertia import InertiaSuite
from kinverify.suites.kinematics import KinematicsSuite
from kinverify.suites.limits import LimitsSuite
from kinverify.tracking.execute import Run
from kinverify.tracking.metrics import CRITERIA, compute_metrics
from kinverify.tracking.quintic import hold, quintic
from kinverify.tracking.track import default_trajectory, plan_check, run_check
from tests.paths import MODELS

FRAME = "link2"  # a frame in the middle of arm3's chain
IK_TARGETS = 10


@lru_cache(maxsize=1)
def arm3():
    spec = load_spec(MODELS / "arm3.toml")
    return spec, ModelSources.from_spec(spec)


def context(backends, tolerances, samples: int = 12, **extra) -> VerifyContext:
    spec, sources = arm3()
    options = VerifyOptions(samples=samples, fd_samples=samples, tolerances=dict(tolerances), extra=extra)
    q = Samples(sources.lower, sources.upper, sources.revolute, samples, options.seed)
    return VerifyContext(sources, {b.name: b for b in backends}, q, options)


def find(checks: list[Check], prop: str, subject: str | None = None, side: str | None = None) -> Check:
    hits = [
        c
        for c in checks
        if c.property == prop and (subject is None or c.frame == subject) and (side is None or side in c.backends)
    ]
    assert len(hits) >= 1, (prop, subject, side, sorted({(c.property, c.frame, c.backends) for c in checks}))
    return max(hits, key=lambda c: c.max_error)


class Perturbed(BackendBase):
    """A real backend (Pinocchio on the URDF) whose FK or Jacobian at one frame is offset:
    ``position`` [m] along world x, ``rotation`` [rad] about the frame's z, ``linear``/``angular``
    added to the Jacobian's first linear / angular entry (a Frobenius difference of that size)."""

    name = "perturbed"

    def __init__(self, frame: str = FRAME, position=0.0, rotation=0.0, linear=0.0, angular=0.0) -> None:
        self.inner = build_backend("pinocchio-urdf", arm3()[1])
        self.joint_names, self.frames = self.inner.joint_names, self.inner.frames
        self.f, self.offsets = self.frames.index(frame), (position, rotation, linear, angular)

    def evaluate(self, q, with_jacobians: bool = True) -> Evaluation:
        ev = self.inner.evaluate(q, with_jacobians)
        position, rotation, linear, angular = self.offsets
        poses = ev.poses.copy()
        poses[:, self.f, 0, 3] += position
        c, s = math.cos(rotation), math.sin(rotation)
        poses[:, self.f, :3, :3] = poses[:, self.f, :3, :3] @ np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
        jac = None
        if ev.jacobians is not None:
            jac = ev.jacobians.copy()
            jac[:, self.f, 0, 0] += linear
            jac[:, self.f, 3, 0] += angular
        return Evaluation(self.name, self.frames, poses, jac)

    def poses(self, q):
        return self.evaluate(q, with_jacobians=False).poses

    def jacobians(self, q):
        return self.evaluate(q).jacobians


def analytic():
    return build_backend("analytic", arm3()[1])


def kinematics(prop: str, **offset) -> Callable[[float, dict], Check]:
    def probe(delta, tolerances):
        ctx = context([analytic(), Perturbed(**{k: delta for k in offset})], tolerances)
        side = "finite-difference" if prop == "jacobian.fd" else "analytic"
        return find(KinematicsSuite().run(ctx).checks, prop, FRAME, side)

    return probe


class _OffsetPinocchio:
    """Pinocchio's dynamics with one quantity offset by ``delta`` (first joint, first entry)."""

    def __init__(self, inner, what: str, delta: float) -> None:
        self.inner, self.what, self.delta = inner, what, delta
        self.model, self.idx_v = inner.model, inner.idx_v
        self.damping = inner.damping + (delta if what == "damping" else 0.0)
        self.friction = inner.friction + (delta if what == "friction" else 0.0)

    def _e0(self, x):
        x = np.array(x, dtype=float)
        x.flat[0] += self.delta
        return x

    def mass(self, q):
        return self._e0(self.inner.mass(q)) if self.what == "mass" else self.inner.mass(q)

    def gravity(self, q):
        return self._e0(self.inner.gravity(q)) if self.what == "gravity" else self.inner.gravity(q)

    def bias(self, q, v):
        return self._e0(self.inner.bias(q, v)) if self.what == "bias" else self.inner.bias(q, v)

    def inverse(self, q, v, a):
        return self._e0(self.inner.inverse(q, v, a)) if self.what == "inverse" else self.inner.inverse(q, v, a)

    def forward(self, q, v, tau):
        a = self.inner.forward(q, v, tau)
        if self.what != "forward":
            return a
        # an acceleration off by M⁻¹·(δ e₀): the force residual M·Δa the suite measures is δ
        return a - np.linalg.solve(self.inner.mass(q), np.eye(len(a))[0] * self.delta)


def dynamics(prop: str, what: str) -> Callable[[float, dict], Check]:
    class Suite(DynamicsSuite):
        def models(self, ctx):
            pin, mj, origin = super().models(ctx)
            if what == "armature":
                mj.armature = mj.armature + np.eye(len(mj.armature))[0] * ctx.options.extra["delta"]
                return pin, mj, origin
            return _OffsetPinocchio(pin, what, ctx.options.extra["delta"]), mj, origin

    def probe(delta, tolerances):
        ctx = context([analytic()], tolerances, samples=6, dynamics_samples=6, delta=delta)
        return find(Suite().run(ctx).checks, prop)

    return probe


def ik(prop: str) -> Callable[[float, dict], Check]:
    """IK probes: ``cross_fk`` through a confirming backend offset by δ; ``closed_form`` against
    branches moved by δ·1e-6 rad (δ in units of the ratio's allowance); ``failure_rate`` and
    ``unreachable`` with ⌈δ·n⌉ answers spoiled; ``limits`` with one answer δ beyond a limit."""

    class Suite(IKSuite):
        delta = 0.0

        def solve(self, backend, model, targets, lower, upper, position_only, options):
            sol = super().solve(backend, model, targets, lower, upper, position_only, options)
            n, d = len(sol), self.delta
            unreachable = options.max_restarts == 3  # the suite's unreachable targets
            if prop == "ik.failure_rate" and not unreachable:
                k = math.ceil(d * n - 1e-9)
                sol.pos_error[:k] = 1.0  # k answers that miss their target by 1 m
            elif prop == "ik.unreachable" and unreachable:
                sol.success[: math.ceil(d * n - 1e-9)] = True  # reported solved though beyond reach
            elif prop == "ik.limits" and not unreachable and d > 0:
                sol.q[0, 0] = upper[0] + d
            return sol

        def closed_form(self, sources, frame):
            closed = super().closed_form(sources, frame)
            shift = self.delta * 1e-6  # the allowance is 1e-6 rad + residual/σ_min

            class Shifted:
                def all_branches(self, target):
                    return closed.all_branches(target) + np.array([0.0, 0.0, shift])

                def solve(self, target):
                    return closed.solve(target)

            return Shifted() if prop == "ik.closed_form" else closed

    def probe(delta, tolerances):
        backends = [analytic(), Perturbed(frame="end_effector", position=delta)] if prop == "ik.cross_fk" else [analytic()]
        suite = Suite()
        suite.delta = delta
        ctx = context(backends, tolerances, ik_targets=IK_TARGETS)
        side = {
            "ik.cross_fk": "perturbed",
            "ik.closed_form": "closed-form",
            "ik.limits": "limits",
            "ik.unreachable": "geometry",
        }.get(prop, "analytic")
        checks = [c for c in suite.run(ctx).checks if not (prop == "ik.unreachable" and c.backends[0] == "closed-form")]
        return find(checks, prop, side=side)

    return probe


def tracking(controller: str) -> Callable[[float, dict], Check]:
    """The executed trajectory is the plan with joint 1 off by a constant: RMS error = that offset
    (for goals relative to the move, δ is a fraction of the move)."""

    def probe(delta, tolerances):
        spec = arm3()[0]
        tr = default_trajectory(spec)
        plan = hold(quintic(tr.q0, tr.q1, 0.5, 0.01), 0.2)
        move = float(np.linalg.norm(plan.q[-1] - plan.q[0]))
        offset = delta * move if CRITERIA[controller].relative else delta
        q = plan.q + np.eye(spec.dof)[0] * offset
        run = Run(controller, plan, 0.5, q, plan.qd.copy(), np.zeros_like(plan.q))
        return run_check(spec, run, compute_metrics(spec, run), VerifyOptions(tolerances=dict(tolerances)))

    return probe


def tracking_plan(delta, tolerances):
    """A plan whose end is δ beyond joint 1's upper limit."""
    spec = arm3()[0]
    q1 = np.array(spec.upper) * 0.4  # well inside the speed limits too
    plan = quintic(np.zeros(spec.dof), q1, 1.0, 0.01)
    plan = dataclasses.replace(
        plan,
        q=plan.q + np.outer(np.linspace(0, 1, len(plan.t)), np.eye(spec.dof)[0]) * (spec.upper[0] - q1[0] + delta) * (delta > 0),
    )
    return plan_check(spec, plan, VerifyOptions(tolerances=dict(tolerances)))


def _edit_urdf(pattern: str, delta: float) -> Callable[[str], str]:
    """Add ``delta`` to the first number the (one-group) ``pattern`` captures in arm3's URDF."""

    def edit(urdf: str) -> str:
        new, n = re.subn(pattern, lambda m: m[0].replace(m[1], repr(float(m[1]) + delta), 1), urdf, count=1, flags=re.S)
        assert n == 1, pattern
        return new

    return edit


# one side's statement of a parameter, in arm3's URDF (link1 sits unrotated at q = 0)
URDF_EDITS = {
    "limits.position": r'<joint name="joint1".*?upper="([^"]+)"',
    "limits.effort": r'<joint name="joint1".*?effort="([^"]+)"',
    "limits.velocity": r'<joint name="joint1".*?velocity="([^"]+)"',
    "inertia.mass": r'<link name="link1">.*?<mass value="([^"]+)"',
    "inertia.com": r'<link name="link1">.*?<origin xyz="([^ "]+)',
    "inertia.tensor": r'<link name="link1">.*?ixx="([^"]+)"',
}


def urdf_parameter(prop: str, suite) -> Callable[[float, dict], Check]:
    """The suite on arm3 with the URDF's statement of ``prop`` moved by delta (in its unit)."""

    def probe(delta, tolerances):
        ctx = context([analytic()], tolerances)
        sources = dataclasses.replace(ctx.sources, urdf=_edit_urdf(URDF_EDITS[prop], delta)(ctx.sources.urdf))
        return find(suite().run(dataclasses.replace(ctx, sources=sources)).checks, prop)

    return probe


PROBES: dict[str, Callable[[float, dict], Check]] = {
    "fk.position": kinematics("fk.position", position=1),
    "fk.rotation": kinematics("fk.rotation", rotation=1),
    "jacobian.linear": kinematics("jacobian.linear", linear=1),
    "jacobian.angular": kinematics("jacobian.angular", angular=1),
    "jacobian.fd": kinematics("jacobian.fd", linear=1),
    "dynamics.mass_matrix": dynamics("dynamics.mass_matrix", "mass"),
    "dynamics.gravity": dynamics("dynamics.gravity", "gravity"),
    "dynamics.bias": dynamics("dynamics.bias", "bias"),
    "dynamics.inverse": dynamics("dynamics.inverse", "inverse"),
    "dynamics.forward": dynamics("dynamics.forward", "forward"),
    "dynamics.damping": dynamics("dynamics.damping", "damping"),
    "dynamics.friction": dynamics("dynamics.friction", "friction"),
    "dynamics.armature": dynamics("dynamics.armature", "armature"),
    "ik.failure_rate": ik("ik.failure_rate"),
    "ik.cross_fk": ik("ik.cross_fk"),
    "ik.limits": ik("ik.limits"),
    "ik.closed_form": ik("ik.closed_form"),
    "ik.unreachable": ik("ik.unreachable"),
    **{f"tracking.{c}": tracking(c) for c in CRITERIA},
    "tracking.plan": tracking_plan,
    **{p: urdf_parameter(p, LimitsSuite) for p in ("limits.position", "limits.effort", "limits.velocity")},
    **{p: urdf_parameter(p, InertiaSuite) for p in ("inertia.mass", "inertia.com", "inertia.tensor")},
}

# Properties whose error is a count over a few items (k/n): probed at a tolerance on the grid so
# "just under" lands exactly on it (which must pass: an error equal to the tolerance passes).
QUANTIZED = {"ik.failure_rate": 1 / IK_TARGETS, "ik.unreachable": 1 / 5}

# The smallest real difference each property must catch at its default tolerance: a requirement
# on sensitivity (a threshold loosened at its source, by a factor of 1000, lets these through).
MUST_CATCH = {
    "fk.position": 1e-7,  # m: a 0.1 µm offset of one frame
    "fk.rotation": 1e-7,  # rad
    "jacobian.linear": 1e-7,
    "jacobian.angular": 1e-7,
    "jacobian.fd": 1e-4,  # a Jacobian entry wrong by 1e-4 against the backend's own FK
    "dynamics.mass_matrix": 1e-6,
    "dynamics.gravity": 1e-6,
    "dynamics.bias": 1e-6,  # kg·m², N·m on arm3
    "dynamics.inverse": 1e-6,
    "dynamics.forward": 1e-6,
    "dynamics.damping": 1e-6,
    "dynamics.friction": 1e-6,
    "dynamics.armature": 1e-6,
    "ik.failure_rate": 1 / IK_TARGETS,  # one target of ten missed
    "ik.cross_fk": 1e-5,  # m: an IK answer 10 µm off in another backend's FK
    "ik.limits": 1e-9,
    "ik.unreachable": 1 / 5,
    "ik.closed_form": 10.0,  # ten times the allowance (1e-5 rad from the nearest branch)
    "tracking.computed-torque": 1e-3,  # rad RMS
    "tracking.pd+gravity": 0.5,
    "tracking.position": 0.5,
    "tracking.seed-pid": 0.5,  # half the move
    "tracking.plan": 1e-9,
    "limits.position": 1e-6,  # rad: a bound 1 µrad apart
    "limits.effort": 1e-6,
    "limits.velocity": 1e-6,  # N·m, rad/s
    "inertia.mass": 1e-6,  # kg: a milligram
    "inertia.com": 1e-6,  # m: a micrometre
    "inertia.tensor": 1e-8,  # kg·m²
}
