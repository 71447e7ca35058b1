# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""madgwick_node: one output per raw IMU message, with MARG, even when mag stamps differ."""

import math
from pathlib import Path

import pytest
import yaml

pytestmark = [pytest.mark.integration, pytest.mark.ros]


def test_marg_output_never_waits_for_the_magnetometer(ros_context):
    import rclpy
    from rclpy.parameter import Parameter
    from rclpy.qos import qos_profile_sensor_data
    from sensor_msgs.msg import Imu, MagneticField

    from tactex_sensor.madgwick_node import MadgwickNode

    node = MadgwickNode(context=ros_context, parameter_overrides=[
        Parameter('use_mag', value=True)])
    probe = rclpy.create_node('madgwick_probe', context=ros_context)
    imu_pub = probe.create_publisher(Imu, 'tactile/imu/data_raw', qos_profile_sensor_data)
    mag_pub = probe.create_publisher(MagneticField, 'tactile/imu/mag', qos_profile_sensor_data)
    fused = []
    probe.create_subscription(Imu, 'tactile/imu/data', fused.append, qos_profile_sensor_data)
    executor = rclpy.executors.SingleThreadedExecutor(context=ros_context)
    executor.add_node(node)
    executor.add_node(probe)
    for _ in range(20):  # let discovery settle
        executor.spin_once(timeout_sec=0.05)
    roll = math.radians(25.0)
    sent = 0
    for i in range(300):
        stamp_ns = 10**9 + i * 8_333_333
        imu = Imu()
        imu.header.stamp.sec, imu.header.stamp.nanosec = divmod(stamp_ns, 10**9)
        imu.header.frame_id = 'sensor_link'
        imu.linear_acceleration.y = 9.81 * math.sin(roll)
        imu.linear_acceleration.z = 9.81 * math.cos(roll)
        mag = MagneticField()
        # Magnetometer stamps 3 ms late and only every third sample.
        mag_ns = stamp_ns + 3_000_000
        mag.header.stamp.sec, mag.header.stamp.nanosec = divmod(mag_ns, 10**9)
        mag.magnetic_field.x, mag.magnetic_field.y, mag.magnetic_field.z = 0.0, 2e-5, -4e-5
        if i % 3 == 0:
            mag_pub.publish(mag)
        imu_pub.publish(imu)
        sent += 1
        for _ in range(50):  # until this sample's output is through (bounded)
            executor.spin_once(timeout_sec=0.01)
            if len(fused) >= sent:
                break
    assert len(fused) >= sent - 2  # best effort on one host: at most a stray loss
    q = fused[-1].orientation
    estimated = math.atan2(2 * (q.w * q.x + q.y * q.z), 1 - 2 * (q.x * q.x + q.y * q.y))
    assert abs(math.degrees(estimated) - 25.0) < 1.0
    assert fused[-1].header.frame_id == 'sensor_link'
    node.destroy_node()
    probe.destroy_node()


def test_node_library_and_parameter_file_share_one_default_gain(ros_context):
    from tactex_sensor.madgwick import MadgwickConfig
    from tactex_sensor.madgwick_node import MadgwickNode

    node = MadgwickNode(context=ros_context)
    config = yaml.safe_load((Path(__file__).parents[2] / 'config' / 'sensor.yaml').read_text())
    in_file = config['/**/madgwick_node']['ros__parameters']
    defaults = MadgwickConfig()
    assert node.get_parameter('gain').value == in_file['gain'] == defaults.gain
    assert node.get_parameter('max_rate_rad_s').value == defaults.max_rate_rad_s
    assert in_file['max_rate_rad_s'] == pytest.approx(defaults.max_rate_rad_s, abs=1e-6)
    node.destroy_node()
