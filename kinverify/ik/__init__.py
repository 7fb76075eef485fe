"""Inverse kinematics: solvers on any backend, and their cross-validation.

- :func:`solve_lm`: Levenberg-Marquardt with joint limits and restarts from a seed table, on any
  backend with FK + Jacobians (:class:`FrameModel`); batched over all targets on the analytic
  backend and on a :class:`SerialChain` read from any URDF (:mod:`kinverify.ik.batch`), target
  by target elsewhere (:mod:`kinverify.ik.single`).
- :func:`solve_seed_pinv`: the seed tutorial's pseudo-inverse IK, the baseline ``seed-pinv``.
- :class:`Arm3ClosedForm`: every closed-form branch for ``arm3``-shaped arms.
- :mod:`kinverify.suites.ik`: the ``ik`` property suite of ``kinverify verify``.
"""

from kinverify.ik.chain import SerialChain
from kinverify.ik.closed_form import Arm3ClosedForm, ClosedFormResult
from kinverify.ik.frame_model import FrameModel, pose_errors, residuals
from kinverify.ik.lm import IKOptions, IKSolutions, solve_lm
from kinverify.ik.seed_pinv import solve_seed_pinv
from kinverify.ik.seeds import SeedTable
from kinverify.ik.targets import reach_bound, reachable_targets, unreachable_targets

__all__ = [
    "Arm3ClosedForm",
    "ClosedFormResult",
    "FrameModel",
    "IKOptions",
    "IKSolutions",
    "SeedTable",
    "SerialChain",
    "pose_errors",
    "reach_bound",
    "reachable_targets",
    "residuals",
    "solve_lm",
    "solve_seed_pinv",
    "unreachable_targets",
]
