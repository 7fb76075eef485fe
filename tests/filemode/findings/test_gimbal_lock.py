"""A reported transform's rpy at gimbal lock: the world turned by a half turn about (1, 0, 1)/√2 is
reported with the roll that makes the matrix (not a bare 90° pitch, its roll dropped)."""

from __future__ import annotations

import math

import numpy as np

from kinverify.filemode.pipeline import verify_files
from kinverify.model.transforms import axis_angle_to_matrix, rpy_to_matrix
from kinverify.run import VerifyOptions
from tests.filemode.pairs import generated_pair


def test_a_world_turned_half_about_x_plus_z_is_reported_with_an_rpy_that_makes_it(tmp_path):
    urdf, mjcf = generated_pair("panda")
    s = 1 / math.sqrt(2)
    mjcf = mjcf.replace('<body name="world_mount">', f'<body name="world_mount" quat="0 {s!r} 0 {s!r}">', 1)
    (tmp_path / "arm.urdf").write_text(urdf)
    (tmp_path / "arm.xml").write_text(mjcf)
    result = verify_files(
        str(tmp_path / "arm.urdf"),
        str(tmp_path / "arm.xml"),
        VerifyOptions(samples=8, fd_samples=2, backends=["pinocchio-urdf", "mujoco"], suites=["kinematics"]),
    )
    [world] = [f for f in result.findings if f.kind == "base_transform"]
    turn = axis_angle_to_matrix(np.array([1.0, 0.0, 1.0]) / math.sqrt(2), math.pi)
    rpy = world.values["rpy"]
    assert abs(rpy[1] + math.pi / 2) < 1e-9 and abs(abs(rpy[0]) - math.pi) < 1e-9
    # the MJCF's world is the URDF's turned: one way or the other round, the rpy makes that half turn
    assert np.allclose(rpy_to_matrix(rpy), turn, atol=1e-9) or np.allclose(rpy_to_matrix(rpy), turn.T, atol=1e-9)
    assert "rpy = [3.14159, -1.5708, 0]" in world.message.replace("-3.14159", "3.14159")
