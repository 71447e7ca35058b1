# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The MJCF loads in MuJoCo and its kinematics match ours."""

import mujoco
import numpy as np
import pytest

from tactex_description.geometry import JointKind, OPEN_MANIPULATOR_X
from tactex_description.kinematics import forward_kinematics
from tactex_description.mjcf import build_mjcf

MOVING = [j for j in OPEN_MANIPULATOR_X.joints if j.kind is not JointKind.FIXED]


@pytest.fixture(scope='module')
def model():
    return mujoco.MjModel.from_xml_string(build_mjcf())


def test_every_moving_joint_exists_with_our_range(model):
    for joint in MOVING:
        index = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT, joint.name)
        assert index >= 0, joint.name
        np.testing.assert_allclose(model.jnt_range[index], [joint.lower, joint.upper])


def test_mujoco_forward_kinematics_matches_ours(model):
    data = mujoco.MjData(model)
    rng = np.random.default_rng(7)
    for _ in range(50):
        positions = {j.name: rng.uniform(j.lower, j.upper) for j in MOVING if not j.mimic_of}
        for joint in MOVING:
            address = model.jnt_qposadr[mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_JOINT,
                                                           joint.name)]
            data.qpos[address] = positions[joint.mimic_of or joint.name]
        mujoco.mj_kinematics(model, data)
        for frame in ('link5', 'sensor_mount', 'sensor_link', 'sensor_edge', 'gripper_link'):
            ours = forward_kinematics(positions, frame)
            body = data.body(frame)
            np.testing.assert_allclose(body.xpos, ours[:3, 3], atol=1e-6)
            np.testing.assert_allclose(body.xmat.reshape(3, 3), ours[:3, :3], atol=1e-6)


def test_arm_and_gripper_have_position_actuators(model):
    names = {model.actuator(i).name for i in range(model.nu)}
    assert names == {'joint1', 'joint2', 'joint3', 'joint4', 'gripper'}


def test_arm_holds_a_commanded_pose(model):
    data = mujoco.MjData(model)
    goal = np.array([0.3, -0.2, 0.4, 0.5])
    data.ctrl[:4] = goal
    for _ in range(1500):
        mujoco.mj_step(model, data)
    reached = [data.joint(n).qpos[0] for n in ('joint1', 'joint2', 'joint3', 'joint4')]
    np.testing.assert_allclose(reached, goal, atol=0.02)
    assert np.all(np.isfinite(data.qpos))
