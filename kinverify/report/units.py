"""Units as the reports show them: a joint-space unit in the model's own terms."""

from __future__ import annotations

from typing import Sequence

from kinverify.results import VerifyResult
from kinverify.suites.base import joint_unit


def revolute(result: VerifyResult) -> list[bool]:
    """Per joint: revolute (True) or prismatic, from the result's joint table (all revolute when
    the table is missing)."""
    joints = result.model_info.get("joints") or []
    if len(joints) == len(result.joint_names):
        return [j.get("type", "revolute") == "revolute" for j in joints]
    return [True] * len(result.joint_names)


def display_unit(unit: str, revolute: Sequence[bool]) -> str:
    """A joint-space unit (``joint``, ``rad|m``) in the model's own terms: rad when every joint
    is revolute, m when every joint is prismatic, ``rad|m`` for a mixed arm."""
    if unit in ("joint", "rad|m") and len(revolute):
        return joint_unit(revolute)
    return unit
