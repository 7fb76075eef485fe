"""Import MuJoCo even when ``MUJOCO_GL`` names a GL backend that cannot load.

``import mujoco`` raises for a value it does not know (``RuntimeError``) and for a known backend
whose library is missing (e.g. ``osmesa`` without libOSMesa: ``AttributeError`` from PyOpenGL),
which would take the whole run down (backends, dynamics, tracking). kinverify's main process
never renders: the pictures suite and the tracking animation render in child processes. So when
the import fails, the main process imports MuJoCo again with GL disabled and restores the
variable; the children inherit the original value, fail, and their failure becomes a
"rendering unavailable" note in the report. MuJoCo's compiled modules, loaded before its GL
import failed, are reused by the second import, not loaded twice.
"""

from __future__ import annotations

import os
import platform
import sys

# mujoco/rendering/classic/gl_context.py: the values it accepts (anything else raises on import)
_NO_GL = {"disable", "disabled", "off", "false", "0"}
_ACCEPTED = _NO_GL | {"enable", "enabled", "on", "true", "1", "glfw", ""}
_PLATFORM = {"Linux": {"glx", "egl", "osmesa"}, "Windows": {"wgl"}, "Darwin": {"cgl"}}

IMPORT_ERROR = ""  # why MuJoCo could not be imported with the user's MUJOCO_GL ("" when it could)


def accepted(value: str) -> bool:
    """Whether MuJoCo knows this ``MUJOCO_GL`` value (it may still fail to load it)."""
    return value.lower().strip() in _ACCEPTED | _PLATFORM.get(platform.system(), set())


def import_mujoco_despite_bad_gl() -> None:
    """Import MuJoCo now if ``MUJOCO_GL`` asks for GL; with GL disabled if that import fails."""
    global IMPORT_ERROR
    value = os.environ.get("MUJOCO_GL")
    if value is None or value.lower().strip() in _NO_GL | {""} or "mujoco" in sys.modules:
        return
    try:
        import mujoco  # noqa: F401
        return
    except ModuleNotFoundError as err:
        if err.name == "mujoco":
            return  # no MuJoCo at all: its backends report themselves unavailable
        IMPORT_ERROR = f"{type(err).__name__}: {err}"
    except Exception as err:  # RuntimeError (unknown value), AttributeError/ImportError (GL library missing)
        IMPORT_ERROR = f"{type(err).__name__}: {err}"
    os.environ["MUJOCO_GL"] = "disable"
    try:
        import mujoco  # noqa: F401,F811
    except Exception:
        pass  # MuJoCo is broken beyond GL: its backends report themselves unavailable
    finally:
        os.environ["MUJOCO_GL"] = value


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
        proc = subprocess.run([sys.executable, "-m", module], input=json.dumps(request), capture_output=True,
                              text=True, env=env, timeout=timeout_s)
    except (OSError, subprocess.TimeoutExpired) as err:
        return [], f"rendering unavailable: {err}"
    if proc.returncode != 0:
        lines = [line for line in proc.stderr.strip().splitlines() if line.strip()]
        return [], (f"rendering unavailable (MUJOCO_GL={env['MUJOCO_GL']}): "
                    f"{lines[-1] if lines else f'renderer exit code {proc.returncode}'}")
    try:
        return [base64.b64decode(s, validate=True) for s in json.loads(proc.stdout)], ""
    except (ValueError, TypeError) as err:
        return [], f"rendering unavailable: bad output from the renderer ({err})"
