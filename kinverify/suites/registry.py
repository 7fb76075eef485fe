"""The suite registry: every property suite, in report order. ``--skip``, ``--tolerance``,
``--gate``, baselines, the report's order, the pytest plugin and the README's property table
all read it. A new suite is one module and one line here."""

from __future__ import annotations

from kinverify.errors import UnknownNameError
from kinverify.suites.base import Property, Suite
from kinverify.suites.diagnosis import DiagnosisSuite
from kinverify.suites.dynamics import DynamicsSuite
from kinverify.suites.ik import IKSuite
from kinverify.suites.inertia import InertiaSuite
from kinverify.suites.kinematics import KinematicsSuite
from kinverify.suites.limits import LimitsSuite
from kinverify.suites.pictures import PicturesSuite
from kinverify.suites.tracking import TrackingSuite
from kinverify.suites.workspace import WorkspaceSuite

SUITES: tuple[type[Suite], ...] = (
    KinematicsSuite,
    LimitsSuite,  # joint limits, URDF vs MJCF
    InertiaSuite,  # mass and inertia of each rigid body, URDF vs MJCF
    IKSuite,
    DynamicsSuite,
    TrackingSuite,
    DiagnosisSuite,  # report: hints and worst configurations of failing checks
    WorkspaceSuite,  # report: Monte-Carlo workspace
    PicturesSuite,  # report: MuJoCo renderings
)


def suite_names() -> list[str]:
    return [s.name for s in SUITES]


def get_suite(name: str) -> type[Suite]:
    for s in SUITES:
        if s.name == name:
            return s
    raise UnknownNameError("suite", name, suite_names())


def properties() -> dict[str, Property]:
    """Every reported property by name, in report order."""
    return {p.name: p for s in SUITES for p in s.properties}


def get_property(name: str) -> Property:
    props = properties()
    if name not in props:
        raise UnknownNameError("property", name, list(props))
    return props[name]
