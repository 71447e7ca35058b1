# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Joint units: joint1..4 in rad and N m, the prismatic gripper in m and N (REP-103)."""

import numpy as np
import pytest

from tactex_driver.joints import JointMap


def test_the_gripper_travels_its_ratio_per_servo_radian_and_back():
    joints = JointMap(gripper_m_per_rad=0.015)
    servo = np.array([0.1, -0.2, 0.3, 0.4, 1.0])
    np.testing.assert_allclose(joints.to_joint(servo), [0.1, -0.2, 0.3, 0.4, 0.015])
    np.testing.assert_allclose(joints.to_servo(joints.to_joint(servo)), servo)


def test_a_servo_torque_is_a_joint_torque_and_a_gripper_force():
    joints = JointMap(gripper_m_per_rad=0.015)
    effort = joints.to_joint_effort([1.0, 1.0, 1.0, 1.0, 0.3])
    # The gripper's 0.3 N m at 0.015 m per radian pushes with 20 N (power balance).
    np.testing.assert_allclose(effort, [1.0, 1.0, 1.0, 1.0, 20.0])


@pytest.mark.parametrize('ratio', [0.0, -0.01, float('nan')])
def test_a_ratio_that_is_not_positive_is_refused(ratio):
    with pytest.raises(ValueError, match='gripper_m_per_rad must be > 0'):
        JointMap(ratio)
