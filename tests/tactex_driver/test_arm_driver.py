# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""arm_driver against the emulated servo chain: motion, bad input, vanishing servos, faults.

Every test ends by checking the emulator's record of goal positions: the arm was never
commanded outside its joint limits.
"""

import math
import time

import numpy as np
import pytest

from tactex_driver import control_table as ct
from tactex_driver.playback import JointLimits
from tactex_driver.servo_emulator import ServoChainEmulator

pytestmark = [pytest.mark.integration, pytest.mark.ros]
LIMITS = JointLimits.of_robot()
GRIPPER_M_PER_RAD = 0.015


def servo_limits_counts():
    scale = np.array([1, 1, 1, 1, 1 / GRIPPER_M_PER_RAD])
    low = ct.rad_to_position(LIMITS.lower * scale)
    high = ct.rad_to_position(LIMITS.upper * scale)
    return {servo: (int(lo), int(hi)) for servo, lo, hi in zip(range(11, 16), low, high,
                                                                strict=True)}


class Harness:
    """The driver node, a probe node and one executor, spun on demand."""

    def __init__(self, context, link):
        from diagnostic_msgs.msg import DiagnosticArray
        import rclpy
        from sensor_msgs.msg import JointState
        from std_srvs.srv import SetBool, Trigger
        from trajectory_msgs.msg import JointTrajectory

        from tactex_driver.arm_driver_node import ArmDriverNode

        self.context = context
        self.driver = ArmDriverNode(context=context, parameter_overrides=[
            rclpy.parameter.Parameter('port', value=str(link)),
            rclpy.parameter.Parameter('max_backoff_s', value=0.2)])
        self.probe = rclpy.create_node('driver_probe', context=context)
        self.states, self.diagnostics = [], []
        self.probe.create_subscription(JointState, 'joint_states', self.states.append, 10)
        self.probe.create_subscription(DiagnosticArray, 'diagnostics',
                                       lambda m: self.diagnostics.extend(m.status), 10)
        self.trajectory_pub = self.probe.create_publisher(JointTrajectory,
                                                          'arm/joint_trajectory', 10)
        self.stop_client = self.probe.create_client(Trigger, 'arm/stop')
        self.reset_client = self.probe.create_client(Trigger, 'arm/reset')
        self.torque_client = self.probe.create_client(SetBool, 'arm/torque')
        self.executor = rclpy.executors.SingleThreadedExecutor(context=context)
        self.executor.add_node(self.driver)
        self.executor.add_node(self.probe)

    def spin(self, seconds=0.0, until=None, timeout=10.0):
        deadline = time.monotonic() + (seconds if until is None else timeout)
        while time.monotonic() < deadline:
            self.executor.spin_once(timeout_sec=0.005)
            if until is not None and until():
                return True
        return until is None or until()

    def send(self, names, points):
        from builtin_interfaces.msg import Duration
        from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint
        msg = JointTrajectory(joint_names=names)
        for t, positions in points:
            sec = int(t)
            msg.points.append(JointTrajectoryPoint(
                positions=positions, time_from_start=Duration(sec=sec,
                                                              nanosec=int((t - sec) * 1e9))))
        self.trajectory_pub.publish(msg)

    def call(self, client, request):
        future = client.call_async(request)
        self.spin(until=future.done, timeout=5.0)
        return future.result()

    def position(self, joint):
        return self.states[-1].position[self.states[-1].name.index(joint)]

    def last_diagnostic(self):
        return self.diagnostics[-1] if self.diagnostics else None

    def close(self):
        self.driver.destroy_node()
        self.probe.destroy_node()


@pytest.fixture
def rig(tmp_path, ros_context):
    link = tmp_path / 'dxl'
    with ServoChainEmulator(link) as chain:
        harness = Harness(ros_context, link)
        assert harness.spin(until=lambda: len(harness.states) > 5)
        yield harness, chain
        harness.close()
        assert chain.goal_history, 'the driver never sent a goal'
        limits = servo_limits_counts()
        outside = [(servo, goal) for _, servo, goal in chain.goal_history
                   if not limits[servo][0] <= goal <= limits[servo][1]]
        assert not outside, f'goals outside the joint limits: {outside[:5]}'


ARM = ['joint1', 'joint2', 'joint3', 'joint4']


def test_joint_states_at_100_hz_with_all_joints(rig):
    harness, _ = rig
    count = len(harness.states)
    assert harness.spin(until=lambda: len(harness.states) > count + 100, timeout=20)
    stamps = np.array([m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec
                       for m in harness.states[count:]])
    # The median period is the loop's rate whatever else the machine is doing.
    assert 0.008 <= float(np.median(np.diff(stamps))) <= 0.0125
    assert harness.states[-1].name == ['joint1', 'joint2', 'joint3', 'joint4', 'gripper']


def test_executes_a_trajectory(rig):
    harness, chain = rig
    harness.send(ARM, [(0.0, [0.0, 0.0, 0.0, 0.0]), (1.0, [0.4, -0.2, 0.3, 0.1])])
    assert harness.spin(until=lambda: abs(harness.position('joint1') - 0.4) < 0.01, timeout=15)
    assert abs(harness.position('joint3') - 0.3) < 0.01
    assert harness.driver.mode.value == 'holding'


@pytest.mark.parametrize('names, points, reason', [
    (ARM, [(0.0, [math.nan, 0, 0, 0])], 'NaN'),
    (['elbow'], [(0.0, [0.1])], 'unknown joint'),
    (ARM, [(1.0, [0.1, 0, 0, 0]), (0.5, [0.2, 0, 0, 0])], 'strictly increasing'),
    (ARM, [(0.0, [0, 0, 0, 0]), (1.0, [0, 0, 3.0, 0])], 'outside'),
    (ARM, [(1.0, [1.5, 0, 0, 0])], 'first point'),
])
def test_bad_trajectories_are_refused_and_reported(rig, names, points, reason):
    harness, chain = rig
    before = len(chain.goal_history)
    harness.send(names, points)
    harness.spin(until=lambda: harness.driver.rejected_trajectories > 0, timeout=3)
    assert harness.driver.rejected_trajectories == 1
    assert reason in harness.driver.last_event
    harness.spin(until=lambda: harness.last_diagnostic() is not None
                 and 'rejected' in harness.last_diagnostic().message, timeout=3)
    assert 'rejected' in harness.last_diagnostic().message
    # Nothing of it ran: every goal since is the held pose.
    assert all(abs(ct.position_to_rad(goal)) < 0.01 for _, _, goal in
               chain.goal_history[before:])


@pytest.mark.parametrize('how', ['service', 'empty trajectory'])
def test_stop_holds_midway(rig, how):
    from std_srvs.srv import Trigger
    harness, _ = rig
    harness.send(ARM, [(0.0, [0, 0, 0, 0]), (2.0, [1.0, 0, 0, 0])])
    assert harness.spin(until=lambda: harness.position('joint1') > 0.1, timeout=15)
    if how == 'service':
        assert harness.call(harness.stop_client, Trigger.Request()).success
    else:
        harness.send(ARM, [])
    harness.spin(0.5)
    held = harness.position('joint1')
    harness.spin(1.0)
    assert 0.05 < held < 0.9 and abs(harness.position('joint1') - held) < 0.01


def test_a_servo_vanishing_mid_trajectory_holds_and_reports(rig):
    harness, chain = rig
    harness.send(ARM, [(0.0, [0, 0, 0, 0]), (2.0, [0.8, 0, 0, 0])])
    harness.spin(0.5)
    chain.silence(13)
    assert harness.spin(until=lambda: harness.last_diagnostic() is not None and
                        harness.last_diagnostic().message.startswith('disconnected'), timeout=5)
    assert 'servo 13' in harness.last_diagnostic().message
    chain.silence(13, False)
    assert harness.spin(until=lambda: harness.driver.connected, timeout=5)
    stopped = harness.position('joint1')
    harness.spin(1.5)
    assert stopped < 0.8 and abs(harness.position('joint1') - stopped) < 0.02


def test_a_corrupt_status_packet_is_counted_and_survived(rig):
    harness, chain = rig
    errors = harness.driver.communication_errors
    chain.corrupt_next_status(12)
    assert harness.spin(until=lambda: harness.driver.communication_errors > errors, timeout=3)
    assert harness.spin(until=lambda: harness.driver.connected, timeout=5)
    count = len(harness.states)
    harness.spin(0.5)
    assert len(harness.states) > count + 30


def test_overload_disables_motion_until_reset(rig):
    from std_srvs.srv import SetBool, Trigger
    harness, chain = rig
    chain.overload(12)
    assert harness.spin(until=lambda: harness.driver.mode.value == 'fault',
                        timeout=3)
    harness.send(ARM, [(0.0, [0, 0, 0, 0]), (1.0, [0.3, 0, 0, 0])])
    harness.spin(0.3)
    assert 'reset first' in harness.driver.last_event
    assert not harness.call(harness.torque_client, SetBool.Request(data=True)).success
    assert harness.call(harness.reset_client, Trigger.Request()).success
    # Rebooted servos drop off the bus for a moment (how long depends on the machine's
    # load); the driver reconnects by itself, and torque can be enabled once it has.
    deadline = time.monotonic() + 15
    while not harness.call(harness.torque_client, SetBool.Request(data=True)).success:
        assert time.monotonic() < deadline, harness.driver.last_event
        harness.spin(0.1)
    harness.send(ARM, [(0.0, [0, 0, 0, 0]), (1.0, [0.3, 0, 0, 0])])
    assert harness.spin(until=lambda: abs(harness.position('joint1') - 0.3) < 0.01, timeout=5)


def test_operating_modes_are_set_while_torque_was_off(rig):
    _, chain = rig
    modes = [chain.servos[i].table[ct.OPERATING_MODE] for i in range(11, 16)]
    assert modes == [ct.MODE_POSITION] * 4 + [ct.MODE_CURRENT_BASED_POSITION]
