"""Suite ``tracking``: a trajectory executed in MuJoCo on the MJCF under controllers whose
model terms come from Pinocchio on the URDF (see :mod:`kinverify.tracking.track`).

Every property here is a *performance* figure of a controller on the model: shown against its
goal, never deciding whether the models agree unless gated (``--gate tracking.computed-torque``).
The seed's own loop (``seed-pid``) runs as the negative example shown in the section.
"""

from __future__ import annotations

from kinverify.errors import InputError
from kinverify.suites.base import Section, Suite, SuiteResult, VerifyContext
from kinverify.tracking.controllers import CONTROLLERS
from kinverify.tracking.track import NEGATIVE_EXAMPLE, PROPERTIES, VERIFY_CONTROLLERS, default_trajectory, track


class TrackingSuite(Suite):
    name = "tracking"
    title = "Trajectory tracking"
    properties = tuple(PROPERTIES.values())

    def run(self, ctx: VerifyContext) -> SuiteResult:
        spec = ctx.sources.spec
        if spec is None or not ctx.sources.urdf:
            return SuiteResult([], Section(self.title, "skipped: tracking needs a spec (file mode has none)"))
        if spec.floating:
            return SuiteResult(
                [],
                Section(
                    self.title,
                    "skipped: tracking needs a fixed base (this base floats: its "
                    "controllers would have to hold the whole robot up)",
                ),
            )
        controllers = ctx.options.extra.get("tracking_controllers")
        if controllers is None:
            controllers, checked = list(VERIFY_CONTROLLERS) + [NEGATIVE_EXAMPLE], list(VERIFY_CONTROLLERS)
        else:
            unknown = [c for c in controllers if c not in CONTROLLERS]
            if unknown:
                raise InputError(f"unknown controller {unknown[0]!r}; controllers: {', '.join(CONTROLLERS)}")
            checked = list(controllers)
        main = [c for c in controllers if c == "computed-torque"] or list(controllers[:1])  # one small GIF keeps the page light
        result = track(spec, ctx.sources.urdf, default_trajectory(spec), controllers, checked, animate=main, options=ctx.options)
        return SuiteResult(result.checks, result.section)
