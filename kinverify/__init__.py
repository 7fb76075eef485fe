"""kinverify: prove that a robot arm's models agree with each other.

From one arm spec, kinverify generates URDF and MJCF, loads them into Pinocchio, MuJoCo and
yourdfpy, and compares them with its own numpy kinematics, property by property.

Conventions: metres and radians; poses ``T_world_from_frame`` (4×4); Jacobians world-aligned at
the frame origin, rows ``[linear; angular]``; quaternions ``wxyz``.
"""

__version__ = "0.1.0"

from kinverify.mujoco_gl import install_guard  # noqa: E402

install_guard()  # MuJoCo is imported when first needed; an unknown MUJOCO_GL must not stop the run, only the renderings

__all__ = [
    "ArmSpec",
    "BackendError",
    "Geometry",
    "Inertial",
    "InputError",
    "Joint",
    "KinverifyError",
    "Limits",
    "Link",
    "Origin",
    "SpecError",
    "Tool",
    "__version__",
    "load_spec",
    "spec_from_dict",
]

# The names above are imported when first used (PEP 562): `import kinverify` stays light, so the
# command line handles Ctrl-C from its first milliseconds (kinverify.cli.main) instead of after numpy.
_HOMES = {
    "BackendError": "errors",
    "InputError": "errors",
    "KinverifyError": "errors",
    "SpecError": "errors",
    "load_spec": "model.specfile",
    "spec_from_dict": "model.specfile",
    **{name: "model.spec" for name in ("ArmSpec", "Geometry", "Inertial", "Joint", "Limits", "Link", "Origin", "Tool")},
}


def __getattr__(name: str):
    if name in _HOMES:
        import importlib

        value = getattr(importlib.import_module(f"kinverify.{_HOMES[name]}"), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'kinverify' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
