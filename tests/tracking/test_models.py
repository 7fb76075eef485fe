"""The dynamics models' refusals name the library that read the file and the format it read."""

from __future__ import annotations

import pytest

from kinverify.errors import BackendError
from kinverify.tracking.models import MujocoDynamics, PinocchioDynamics

INERTIAL = '<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>'
URDF = (
    f'<robot name="r"><link name="base"/><link name="l1">{INERTIAL}</link><link name="l2">{INERTIAL}</link>'
    '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>'
    '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
    '<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.1 0 0"/><axis xyz="0 0 1"/>'
    '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
)


def test_pinocchio_on_a_urdf_moved_by_a_joint_not_compared_names_itself_and_the_urdf():
    with pytest.raises(BackendError) as err:
        PinocchioDynamics(URDF, ["j1"], [0.0])
    assert str(err.value) == (
        "pinocchio-urdf: dynamics needs the model to move by the compared joints only (1 degree of freedom), the URDF has 2"
    )


def test_mujoco_names_the_library_and_format_it_is_told_read_the_text():
    mjcf = '<mujoco><worldbody><body><joint name="j1"/><geom size="0.1" mass="1"/></body></worldbody></mujoco>'
    with pytest.raises(BackendError, match=r"^mujoco: MJCF lacks joint 'j9'$"):
        MujocoDynamics(mjcf, ["j9"])
    with pytest.raises(BackendError, match=r"^mujoco-urdf: URDF lacks joint 'j9'$"):
        MujocoDynamics(mjcf, ["j9"], library="mujoco-urdf", reads="URDF")
