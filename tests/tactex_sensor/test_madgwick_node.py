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
    # REP-145: a covariance, never all zeros ('unknown'); yaw observed with the magnetometer.
    assert list(fused[-1].orientation_covariance) == pytest.approx(
        [math.radians(2.0) ** 2, 0, 0, 0, math.radians(2.0) ** 2, 0, 0, 0,
         math.radians(2.0) ** 2])
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


def test_a_rejected_sample_warns_for_a_while_then_the_status_is_ok_again(ros_context,
                                                                         monkeypatch):
    from diagnostic_msgs.msg import DiagnosticStatus
    from sensor_msgs.msg import Imu

    from tactex_sensor import madgwick_node
    node = madgwick_node.MadgwickNode(context=ros_context)
    shown = []
    monkeypatch.setattr(node, 'publish_diagnostics',
                        lambda publisher, level, task, message, values: shown.append(
                            (level, message, values['rejected_dt'])))
    try:
        for i, stamp_ns in enumerate([10**9 + i * 8_333_333 for i in range(20)]):
            imu = Imu()
            stamp_ns += 10**9 if i >= 10 else 0  # one step of a second: not integrated
            imu.header.stamp.sec, imu.header.stamp.nanosec = divmod(stamp_ns, 10**9)
            imu.linear_acceleration.z = 9.81
            node._on_imu(imu)
        node._publish_diagnostics()
        monkeypatch.setattr(madgwick_node, 'RECENT_REJECTION_S', 0.0)  # as if long ago
        node._publish_diagnostics()
    finally:
        node.destroy_node()
    assert shown == [(DiagnosticStatus.WARN, 'samples rejected: 1 dt', 1),
                     (DiagnosticStatus.OK, 'fusing', 1)]  # (the count stays)


def test_without_the_magnetometer_yaw_is_reported_unobserved():
    from tactex_sensor.madgwick_node import orientation_covariance
    assert orientation_covariance(0.1, use_mag=False)[8] == pytest.approx(math.pi ** 2 / 3)
    assert orientation_covariance(0.1, use_mag=True)[8] == pytest.approx(0.01)
