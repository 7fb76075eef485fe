"""kinverify: prove that a robot arm's models agree with each other.

From one arm spec, kinverify generates URDF and MJCF, loads them into Pinocchio, MuJoCo and
yourdfpy, and compares them with its own numpy kinematics, property by property.

Conventions: metres and radians; poses ``T_world_from_frame`` (4×4); Jacobians world-aligned at
the frame origin, rows ``[linear; angular]``; quaternions ``wxyz``.
"""

__version__ = "0.1.0"

from kinverify.mujoco_gl import install_guard  # noqa: E402

install_guard()  # MuJoCo is imported when first needed; an unknown MUJOCO_GL must not stop the run, only the renderings

from kinverify.errors import BackendError, InputError, KinverifyError, SpecError  # noqa: E402
from kinverify.model.spec import ArmSpec, Geometry, Inertial, Joint, Limits, Link, Origin, Tool  # noqa: E402
from kinverify.model.specfile import load_spec, spec_from_dict  # noqa: E402

__all__ = ["ArmSpec", "BackendError", "Geometry", "Inertial", "InputError", "Joint", "KinverifyError", "Limits",
           "Link", "Origin", "SpecError", "Tool", "__version__", "load_spec", "spec_from_dict"]
