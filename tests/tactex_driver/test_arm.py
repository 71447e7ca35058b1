# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The controller's modes: hold, execute, stop, fault and torque, with explicit times."""

import numpy as np
import pytest

from tactex_driver.arm import ArmController, Mode
from tactex_driver.errors import TrajectoryRejected
from tactex_driver.playback import JointLimits

ARM = ['joint1', 'joint2', 'joint3', 'joint4']


@pytest.fixture
def controller():
    arm = ArmController(JointLimits.of_robot())
    arm.update_measured(np.zeros(5))
    arm.torque_on(0.0)
    return arm


def test_torque_off_sends_nothing_and_refuses_trajectories():
    arm = ArmController(JointLimits.of_robot())
    arm.update_measured(np.zeros(5))
    assert arm.goal(0.0) is None
    with pytest.raises(TrajectoryRejected, match='torque is off'):
        arm.execute(ARM, [1.0], [[0.1, 0, 0, 0]], [[]], 0.0)


def test_holds_the_measured_pose_after_torque_on(controller):
    np.testing.assert_allclose(controller.goal(5.0), np.zeros(5))
    assert controller.mode is Mode.HOLDING


def test_executes_then_holds_the_last_point(controller):
    controller.execute(ARM, [0.0, 1.0], [[0, 0, 0, 0], [0.2, 0.1, 0, 0]], [[], []], now_s=10.0)
    assert controller.mode is Mode.EXECUTING
    np.testing.assert_allclose(controller.goal(10.5)[:2], [0.1, 0.05], atol=0.02)
    np.testing.assert_allclose(controller.goal(11.0)[:2], [0.2, 0.1])
    assert controller.mode is Mode.HOLDING
    np.testing.assert_allclose(controller.goal(20.0)[:2], [0.2, 0.1])


def test_stop_holds_where_the_arm_is_commanded(controller):
    controller.execute(ARM, [0.0, 1.0], [[0, 0, 0, 0], [0.2, 0, 0, 0]], [[], []], now_s=0.0)
    midway = controller.goal(0.5)
    controller.stop(0.5)
    np.testing.assert_allclose(controller.goal(3.0), midway)
    assert controller.mode is Mode.HOLDING


def test_an_empty_trajectory_message_stops_where_the_arm_is_commanded_when_it_arrives(
        controller):
    # A sender cannot know where a moving arm is commanded when its message arrives; an
    # empty trajectory (ROS's stop) holds exactly there, neither refused nor counted.
    from trajectory_msgs.msg import JointTrajectory
    controller.execute(ARM, [0.0, 1.0], [[0, 0, 0, 0], [0.2, 0, 0, 0]], [[], []], now_s=0.0)
    arrived = controller.goal(0.7)
    ok, report = controller.execute_message(JointTrajectory(joint_names=ARM), now_s=0.7)
    assert ok and 'stopping' in report
    np.testing.assert_allclose(controller.goal(3.0), arrived)
    assert controller.mode is Mode.HOLDING and controller.rejected == 0


def test_a_new_trajectory_replaces_the_running_one_from_the_commanded_pose(controller):
    controller.execute(ARM, [0.0, 1.0], [[0, 0, 0, 0], [0.2, 0, 0, 0]], [[], []], now_s=0.0)
    midway = controller.goal(0.5)
    controller.execute(ARM, [1.0], [[0.0, 0, 0, 0]], [[]], now_s=0.5)
    np.testing.assert_allclose(controller.goal(0.5), midway)
    np.testing.assert_allclose(controller.goal(1.5), np.zeros(5))


def test_fault_stops_all_motion_until_reset(controller):
    controller.execute(ARM, [0.0, 1.0], [[0, 0, 0, 0], [0.2, 0, 0, 0]], [[], []], now_s=0.0)
    controller.fault('servo 12: overload')
    assert controller.goal(0.5) is None
    with pytest.raises(TrajectoryRejected, match='reset first'):
        controller.execute(ARM, [1.0], [[0.0, 0, 0, 0]], [[]], now_s=1.0)
    with pytest.raises(TrajectoryRejected, match='reset first'):
        controller.torque_on(1.0)
    controller.reset()
    assert controller.mode is Mode.TORQUE_OFF
    controller.torque_on(2.0)
    assert controller.goal(2.0) is not None


def test_a_rejected_trajectory_stops_the_running_one_and_is_counted(controller):
    controller.execute(ARM, [0.0, 1.0], [[0, 0, 0, 0], [0.2, 0, 0, 0]], [[], []], now_s=0.0)
    midway = controller.goal(0.5)
    with pytest.raises(TrajectoryRejected, match='NaN'):
        controller.execute(ARM, [1.0], [[np.nan, 0, 0, 0]], [[]], now_s=0.5)
    assert controller.rejected == 1 and controller.mode is Mode.HOLDING
    assert controller.last_event.startswith('rejected trajectory')
    np.testing.assert_allclose(controller.goal(2.0), midway)
