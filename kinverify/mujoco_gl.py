"""Import MuJoCo even when ``MUJOCO_GL`` names a GL backend that cannot load, and only when needed.

``import mujoco`` raises for a value it does not know (``RuntimeError``) and for a known backend
whose library is missing (e.g. ``osmesa`` without libOSMesa: ``AttributeError`` from PyOpenGL),
which would take the whole run down (backends, dynamics, tracking). kinverify's main process
never renders: the pictures suite and the tracking animation render in child processes.

``import kinverify`` does not import MuJoCo (it costs about a second of start-up that ``--help``
or ``kinverify ik --urdf`` do not need); it installs :class:`MujocoGuard`, which watches for the
first ``import mujoco`` (by kinverify or anyone): when ``MUJOCO_GL`` asks for GL and MuJoCo's
module fails to execute, it records why (:data:`IMPORT_ERROR`) and executes it again with GL
disabled, then restores the variable. The rendering children inherit the original value, fail,
and their failure becomes a "rendering unavailable" note in the report. MuJoCo's compiled
modules, loaded before its GL import failed, are reused by the second execution.
"""

from __future__ import annotations

import importlib.abc
import importlib.util
import os
import platform
import re
import sys

from kinverify.errors import library_reason

# mujoco/rendering/classic/gl_context.py: the values it accepts (anything else raises on import)
_NO_GL = {"disable", "disabled", "off", "false", "0"}
_ACCEPTED = _NO_GL | {"enable", "enabled", "on", "true", "1", "glfw", ""}
_PLATFORM = {"Linux": {"glx", "egl", "osmesa"}, "Windows": {"wgl"}, "Darwin": {"cgl"}}

IMPORT_ERROR = ""  # why MuJoCo could not be imported with the user's MUJOCO_GL ("" when it could)


def accepted(value: str) -> bool:
    """Whether MuJoCo knows this ``MUJOCO_GL`` value (it may still fail to load it)."""
    return value.lower().strip() in _ACCEPTED | _PLATFORM.get(platform.system(), set())


class MujocoGuard(importlib.abc.MetaPathFinder):
    """A finder that finds nothing itself: on the first ``import mujoco`` with GL asked for, it
    hands back MuJoCo's own spec with the loader wrapped in :class:`_GlFallbackLoader`."""

    def find_spec(self, name, path=None, target=None):
        if name != "mujoco":
            return None
        uninstall_guard()  # once: the spec below comes from the other finders
        value = os.environ.get("MUJOCO_GL")
        if value is None or value.lower().strip() in _NO_GL | {""}:
            return None
        spec = importlib.util.find_spec(name)
        if spec is None or spec.loader is None:
            return None  # no MuJoCo at all: its backends report themselves unavailable
        spec.loader = _GlFallbackLoader(spec.loader)
        return spec


class _GlFallbackLoader(importlib.abc.Loader):
    def __init__(self, loader) -> None:
        self.loader = loader

    def create_module(self, spec):
        return self.loader.create_module(spec)

    def exec_module(self, module) -> None:
        global IMPORT_ERROR
        module.__loader__ = module.__spec__.loader = self.loader  # the module keeps MuJoCo's own loader
        value = os.environ["MUJOCO_GL"]
        try:
            self.loader.exec_module(module)
            return
        except Exception as err:  # RuntimeError (unknown value), AttributeError/ImportError (GL library missing)
            IMPORT_ERROR = f"{type(err).__name__}: {err}"
        os.environ["MUJOCO_GL"] = "disable"
        try:
            self.loader.exec_module(module)  # if MuJoCo is broken beyond GL this raises: backends unavailable
        finally:
            os.environ["MUJOCO_GL"] = value


def install_guard() -> None:
    """Watch for the first ``import mujoco`` (idempotent; nothing to do once it is imported)."""
    if "mujoco" not in sys.modules and not any(isinstance(f, MujocoGuard) for f in sys.meta_path):
        sys.meta_path.insert(0, MujocoGuard())


def uninstall_guard() -> None:
    sys.meta_path[:] = [f for f in sys.meta_path if not isinstance(f, MujocoGuard)]


def render_in_child(module: str, request: dict, timeout_s: float) -> tuple[list[bytes], str]:
    """Run ``python -m module`` with ``request`` as JSON on stdin and ``MUJOCO_GL`` defaulting to
    ``egl``; the child prints a JSON list of base64 images. Returns ``(images, "")``, or
    ``([], reason)`` starting with "rendering unavailable" when GL or the child fails."""
    import base64
    import json
    import subprocess

    env = dict(os.environ)
    env.setdefault("MUJOCO_GL", "egl")
    try:
        proc = subprocess.run(
            [sys.executable, "-m", module], input=json.dumps(request), capture_output=True, text=True, env=env, timeout=timeout_s
        )
    except (OSError, subprocess.TimeoutExpired) as err:
        return [], f"rendering unavailable: {err}"
    if proc.returncode != 0:
        lines = [line for line in proc.stderr.strip().splitlines() if line.strip()]
        # a traceback ends with the exception: "Type: message" and the message's further lines
        start = max(
            (i for i, line in enumerate(lines) if re.match(r"[A-Za-z_][\w.]*(Error|Exception)\b", line)), default=len(lines) - 1
        )
        reason = library_reason("\n".join(lines[start:])) if lines else f"renderer exit code {proc.returncode}"
        return [], f"rendering unavailable (MUJOCO_GL={env['MUJOCO_GL']}): {reason}"
    try:
        return [base64.b64decode(s, validate=True) for s in json.loads(proc.stdout)], ""
    except (ValueError, TypeError) as err:
        return [], f"rendering unavailable: bad output from the renderer ({err})"
