"""Inverse kinematics: solvers on any backend, and their cross-validation.

- :func:`solve_lm`: damped least squares / Levenberg-Marquardt with joint limits and random
  restarts, on any backend with FK + Jacobians (:class:`FrameModel`); batched on ``analytic``.
- :func:`solve_seed_pinv`: the seed tutorial's pseudo-inverse IK, the baseline ``seed-pinv``.
- :class:`Arm3ClosedForm`: every closed-form branch for ``arm3``-shaped arms.
- :mod:`kinverify.ik.suite`: the ``ik`` property suite of ``kinverify verify``.
"""

from kinverify.ik.closed_form import Arm3ClosedForm, ClosedFormResult
from kinverify.ik.frame_model import FrameModel, pose_errors, residuals
from kinverify.ik.lm import IKOptions, IKSolutions, solve_lm
from kinverify.ik.seed_pinv import solve_seed_pinv
from kinverify.ik.targets import reach_bound, reachable_targets, unreachable_targets

__all__ = ["Arm3ClosedForm", "ClosedFormResult", "FrameModel", "IKOptions", "IKSolutions", "pose_errors",
           "reach_bound", "reachable_targets", "residuals", "solve_lm", "solve_seed_pinv", "unreachable_targets"]
