# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""mujoco_bridge: the robot's topics in simulated time, trajectories executed, ground truth."""

import math
import time

import pytest

pytestmark = [pytest.mark.integration, pytest.mark.ros]



def test_bridge_serves_topics_and_follows_a_trajectory(ros_context):
    from builtin_interfaces.msg import Duration
    from geometry_msgs.msg import PoseStamped
    import rclpy
    from rclpy.parameter import Parameter
    from rclpy.qos import qos_profile_sensor_data
    from rosgraph_msgs.msg import Clock
    from sensor_msgs.msg import FluidPressure, Imu, JointState
    from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

    from tactex_sim.mujoco_bridge_node import MujocoBridgeNode

    bridge = MujocoBridgeNode(context=ros_context, parameter_overrides=[
        Parameter('scene', value='uneven_texture'), Parameter('rate_factor', value=5.0)])
    probe = rclpy.create_node('bridge_probe', context=ros_context)
    got = {'clock': [], 'imu': [], 'joints': [], 'pressure': [], 'pose': []}
    probe.create_subscription(Clock, '/clock', got['clock'].append, 10)
    probe.create_subscription(Imu, 'tactile/imu/data_raw', got['imu'].append,
                              qos_profile_sensor_data)
    probe.create_subscription(FluidPressure, 'tactile/pressure', got['pressure'].append,
                              qos_profile_sensor_data)
    probe.create_subscription(JointState, 'joint_states', got['joints'].append, 10)
    probe.create_subscription(PoseStamped, 'sim/ground_truth/sensor_pose', got['pose'].append,
                              10)
    trajectory_pub = probe.create_publisher(JointTrajectory, 'arm/joint_trajectory', 10)
    executor = rclpy.executors.SingleThreadedExecutor(context=ros_context)
    executor.add_node(bridge)
    executor.add_node(probe)

    def spin_until(condition, timeout):
        deadline = time.monotonic() + timeout
        while not condition() and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.01)
        return condition()

    assert spin_until(lambda: len(got['imu']) > 120 and got['clock'], 10)
    sim_s = got['clock'][-1].clock.sec + 1e-9 * got['clock'][-1].clock.nanosec
    assert sim_s > 0.9  # simulated time advances (its pace is the benchmark's business)
    accel = got['imu'][-1].linear_acceleration
    assert abs(math.sqrt(accel.x ** 2 + accel.y ** 2 + accel.z ** 2) - 9.81) < 0.5
    assert got['imu'][-1].header.frame_id == 'sensor_link'
    assert 100_000 < got['pressure'][-1].fluid_pressure < 110_000
    assert got['joints'][-1].name == ['joint1', 'joint2', 'joint3', 'joint4', 'gripper']

    start = list(got['joints'][-1].position[:4])
    goal = [start[0] + 0.3] + start[1:]
    msg = JointTrajectory(joint_names=['joint1', 'joint2', 'joint3', 'joint4'], points=[
        JointTrajectoryPoint(positions=start, time_from_start=Duration(sec=0)),
        JointTrajectoryPoint(positions=goal, time_from_start=Duration(sec=1))])
    trajectory_pub.publish(msg)
    assert spin_until(lambda: abs(got['joints'][-1].position[0] - goal[0]) < 0.01, 10)
    assert got['pose'][-1].pose.position.y > 0.0  # the sensor swung to the left with joint1
    bridge.destroy_node()
    probe.destroy_node()


def test_the_patch_texture_can_be_set_while_running_and_a_wrong_one_is_refused(ros_context):
    from rclpy.parameter import Parameter

    from tactex_sim.mujoco_bridge_node import MujocoBridgeNode

    bridge = MujocoBridgeNode(context=ros_context, parameter_overrides=[
        Parameter('scene', value='uneven_texture'), Parameter('rate_factor', value=1.0)])
    try:
        ok, = bridge.set_parameters([Parameter('patch_texture', value='carpet wool')])
        assert ok.successful
        assert bridge._world._texture_name_at((0.15, 0.0)) == 'carpet wool'
        refused, = bridge.set_parameters([Parameter('patch_texture', value='velvet')])
        assert not refused.successful and 'known: ' in refused.reason
        assert bridge.get_parameter('patch_texture').value == 'carpet wool'
        assert bridge._world._texture_name_at((0.15, 0.0)) == 'carpet wool'
        assert bridge.set_parameters([Parameter('patch_texture', value='')])[0].successful
        assert bridge._world._texture_name_at((0.15, 0.0)) == 'wood'  # the scene's own
    finally:
        bridge.destroy_node()


def test_a_fault_set_while_running_silences_or_spoils_its_topics_until_cleared(ros_context):
    from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
    import rclpy
    from rclpy.parameter import Parameter
    from rclpy.qos import qos_profile_sensor_data
    from sensor_msgs.msg import Imu, JointState

    from tactex_sim.mujoco_bridge_node import MujocoBridgeNode

    bridge = MujocoBridgeNode(context=ros_context, parameter_overrides=[
        Parameter('scene', value='probe'), Parameter('rate_factor', value=5.0)])
    listener = rclpy.create_node('fault_listener', context=ros_context)
    got = {'imu': [], 'joints': []}
    listener.create_subscription(Imu, 'tactile/imu/data_raw', got['imu'].append,
                                 qos_profile_sensor_data)
    listener.create_subscription(JointState, 'joint_states', got['joints'].append, 10)
    statuses = []  # the bridge's diagnostics: a fault playing is a warning
    listener.create_subscription(DiagnosticArray, '/diagnostics', lambda m: statuses.extend(
        (s.level, s.message, s.hardware_id) for s in m.status if s.name == '/mujoco_bridge: sim'),
        10)
    executor = rclpy.executors.SingleThreadedExecutor(context=ros_context)
    executor.add_node(bridge)
    executor.add_node(listener)

    def spin(seconds):
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.01)

    def heard(fault):
        """Messages per topic in the second after the first 0.5 s under `fault`."""
        assert bridge.set_parameters([Parameter('fault', value=fault)])[0].successful
        spin(0.5)  # what was sent before
        for messages in got.values():
            messages.clear()
        spin(1.0)
        return {name: len(messages) for name, messages in got.items()}

    try:
        spin(2.0)  # discovery
        counts = heard('sensor_unplug')
        assert counts['imu'] == 0 and counts['joints'] > 0
        assert statuses[-1] == (DiagnosticStatus.WARN, "fault 'sensor_unplug' playing",
                                'mujoco:probe')
        counts = heard('servo_silence')
        assert counts['joints'] == 0 and counts['imu'] > 0
        assert heard('crc_burst')['imu'] > 0
        assert all(math.isnan(m.linear_acceleration.z) for m in got['imu'])
        assert min(heard('').values()) > 0
        assert 'fault' not in statuses[-1][1]  # (simulating, or behind on a busy machine)
        assert math.isfinite(got['imu'][-1].linear_acceleration.z)
        refused, = bridge.set_parameters([Parameter('fault', value='meteor')])
        assert not refused.successful and "'crc_burst'" in refused.reason
    finally:
        bridge.destroy_node()
        listener.destroy_node()
