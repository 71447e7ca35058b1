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


def test_a_trajectory_that_arrives_late_runs_from_its_stamp(controller):
    # The sender started a 1 s move at t = 1.0 and replaced it at t = 1.5 by a hold where
    # it then was (0.1); the hold arrives 0.2 s late, when this side is at 0.14 of the move.
    controller.execute(ARM, [0.0, 1.0], [[0.0, 0, 0, 0], [0.2, 0, 0, 0]], [[], []],
                       now_s=1.0, start_s=1.0)
    at_stamp = controller.goal(1.5)[0]
    held = float(controller._trajectory.sample(0.5)[0])
    controller.execute(ARM, [0.05], [[held, 0, 0, 0]], [[]], now_s=1.7, start_s=1.5)
    assert controller.goal(1.7)[0] == pytest.approx(at_stamp, abs=1e-9)
    # A stamp from the future, or older than MAX_LATENESS_S, counts as now.
    controller.execute(ARM, [1.0], [[held, 0, 0, 0]], [[]], now_s=3.0, start_s=9.0)
    assert controller.goal(3.0)[0] == pytest.approx(held, abs=1e-9)


def test_a_stamped_message_is_judged_where_the_arm_was_commanded_at_its_stamp():
    from builtin_interfaces.msg import Duration, Time
    from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

    def moving():
        arm = ArmController(JointLimits.of_robot())
        arm.update_measured(np.zeros(5))
        arm.torque_on(0.0)
        arm.execute(ARM, [0.0, 1.0], [[0.0, 0, 0, 0], [0.4, 0, 0, 0]], [[], []], now_s=10.0)
        return arm

    arm = moving()
    was = float(arm._trajectory.sample(0.3)[0])  # commanded at t = 10.3
    hold_there = JointTrajectory(joint_names=list(ARM), points=[JointTrajectoryPoint(
        positions=[was, 0.0, 0.0, 0.0], time_from_start=Duration(nanosec=50_000_000))])
    # Arriving at 10.7, when this side has moved on by more than the 0.1 rad tolerance:
    assert float(arm._trajectory.sample(0.7)[0]) - was > 0.1
    ok, report = arm.execute_message(hold_there, now_s=10.7)
    assert not ok and 'first point is' in report  # unstamped: judged now, refused
    hold_there.header.stamp = Time(sec=10, nanosec=300_000_000)
    ok, report = moving().execute_message(hold_there, now_s=10.7)
    assert ok, report  # stamped: judged at its stamp, accepted
