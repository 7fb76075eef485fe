"""The neutral description's look-ups (a joint, a body by name, the total mass) and an inertial
taken to the world: centre of mass turned and moved, inertia turned (R I Rᵀ), never moved."""

from __future__ import annotations

import numpy as np
import pytest

from kinverify.filemode.read.model import BodyInertial, JointDesc, ModelDesc, inertial_world


def joint(name: str) -> JointDesc:
    return JointDesc(name, "revolute", None, name + "_link", "base", np.array([0, 0, 1.0]), np.zeros(3), -1.0, 1.0)


@pytest.fixture
def desc() -> ModelDesc:
    bodies = [BodyInertial(None, 1.5, np.zeros(3), np.eye(3), "base"), BodyInertial("a", 2.25, np.zeros(3), np.eye(3), "arm")]
    return ModelDesc("urdf", "pinocchio", [joint("a"), joint("b")], {}, {}, {}, bodies)


def test_a_joint_is_found_by_its_name(desc):
    assert desc.joint("b") is desc.joints[1] and desc.joint("a") is desc.joints[0]
    with pytest.raises(StopIteration):
        desc.joint("c")
    assert desc.has_joint("a") and desc.has_joint("b") and not desc.has_joint("c")


def test_a_body_is_found_by_its_name_and_the_masses_add_up(desc):
    assert desc.body("arm") is desc.bodies[1] and desc.body("base") is desc.bodies[0] and desc.body("tool") is None
    assert desc.total_mass == 3.75 and isinstance(desc.total_mass, float)


def test_an_inertial_is_taken_to_the_world_by_the_body_pose():
    pose = np.array([[0.0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]])  # a quarter turn about z, moved
    com, inertia = inertial_world(pose, [0.5, 0, 0.25], np.diag([1.0, 2, 3]))
    assert com == pytest.approx([1, 2.5, 3.25])
    assert inertia == pytest.approx(np.diag([2.0, 1, 3]))
    _, off = inertial_world(pose, (0, 0, 0), np.array([[1.0, 0, 0.5], [0, 2, 0], [0.5, 0, 3]]))
    assert off == pytest.approx(np.array([[2.0, 0, 0], [0, 1, 0.5], [0, 0.5, 3]]))  # R I Rᵀ, not Rᵀ I R
