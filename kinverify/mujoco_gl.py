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
