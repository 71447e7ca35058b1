# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Emulated Teensy -> teensy_node -> madgwick_node, through garbage, CRC errors and an unplug."""

import math
import os
from pathlib import Path
import subprocess
import sys
import time

import numpy as np
import pytest
from support.processes import stop

from tactex.launching.environment import ros_environment

pytestmark = [pytest.mark.integration, pytest.mark.ros, pytest.mark.slow]
BIN = Path(sys.executable).parent



def spin_until(context, node, condition, timeout_s):
    import rclpy
    executor = rclpy.executors.SingleThreadedExecutor(context=context)
    executor.add_node(node)
    deadline = time.monotonic() + timeout_s
    while not condition() and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.05)
    executor.remove_node(node)
    return condition()


def test_nodes_publish_through_faults_and_a_disconnect(tmp_path, ros_context):
    from diagnostic_msgs.msg import DiagnosticArray
    import rclpy
    from rclpy.qos import qos_profile_sensor_data
    from sensor_msgs.msg import FluidPressure, Imu

    link = tmp_path / 'teensy'
    env = ros_environment()
    # The nodes start first and wait for the port (a loaded machine may take seconds to
    # start them); the emulator's faults come after the node has surely connected.
    nodes = [subprocess.Popen([BIN / 'teensy_node', '--ros-args', '-p', f'port:={link}',
                               '-p', 'diagnostics_period_s:=0.5'], env=env),
             subprocess.Popen([BIN / 'madgwick_node'], env=env)]
    emulator = None
    raw, fused, pressure, diagnostics = [], [], [], []
    try:
        node = rclpy.create_node('sensor_test_listener', context=ros_context)
        node.create_subscription(Imu, 'tactile/imu/data_raw', raw.append, qos_profile_sensor_data)
        node.create_subscription(Imu, 'tactile/imu/data', fused.append, qos_profile_sensor_data)
        node.create_subscription(FluidPressure, 'tactile/pressure', pressure.append,
                                 qos_profile_sensor_data)
        # teensy_node's statuses are checked; madgwick_node's only show that it is up.
        madgwick_up = []
        node.create_subscription(DiagnosticArray, 'diagnostics', lambda m: (
            diagnostics.extend(s for s in m.status if s.name == '/teensy_node: teensy'),
            madgwick_up.extend(s for s in m.status if s.name == '/madgwick_node: madgwick')),
            10)
        assert spin_until(ros_context, node, lambda: diagnostics and madgwick_up, 120.0)
        emulator = subprocess.Popen(
            [BIN / 'tactex', 'emulate', 'teensy', '--rate', '200', '--link', str(link),
             '--roll', '20', '--duration', '30', '--start-time-us', '4293000000',
             '--fault', 'garbage@5:200', '--fault', 'crc@5.5:3',
             '--fault', 'disconnect@10:1.0'],
            env=env, stdout=subprocess.PIPE, text=True)
        assert 'teensy emulator on' in emulator.stdout.readline()
        assert spin_until(ros_context, node, lambda: len(fused) > 200, 20.0)
        # Units and frames per the design: gravity in m/s^2, pressure in Pa, sensor_link.
        msg = raw[-1]
        assert msg.header.frame_id == 'sensor_link'
        assert msg.orientation_covariance[0] == -1.0
        accel = np.array([msg.linear_acceleration.x, msg.linear_acceleration.y,
                          msg.linear_acceleration.z])
        assert abs(np.linalg.norm(accel) - 9.81) < 0.3
        assert 100_000 < pressure[-1].fluid_pressure < 102_000
        # The filter sees the 20 degree roll.
        q = fused[-1].orientation
        roll = math.atan2(2 * (q.w * q.x + q.y * q.z), 1 - 2 * (q.x * q.x + q.y * q.y))
        assert abs(math.degrees(roll) - 20.0) < 2.0
        # Unplug at 10 s for 1 s: diagnostics count it and the reconnect, streaming resumes.
        def values():
            return {kv.key: kv.value for kv in diagnostics[-1].values}
        assert spin_until(ros_context, node, lambda: int(values()['disconnects']) >= 1
                          and int(values()['connects']) >= 2, 20.0)
        count = len(raw)
        assert spin_until(ros_context, node, lambda: len(raw) > count + 200, 15.0)
        last = {kv.key: kv.value for kv in diagnostics[-1].values}
        assert int(last['crc_errors']) >= 3
        assert int(last['discarded_bytes']) >= 1
        assert int(last['disconnects']) >= 1 and int(last['connects']) >= 2
        # Stamps are monotonic within the stream after the reconnect.
        stamps = [m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec for m in raw[count:]]
        assert all(b > a for a, b in zip(stamps, stamps[1:], strict=False))
        node.destroy_node()
    finally:
        # Stopping never raises here, so a failure above is the one reported.
        stubborn = stop(nodes + ([emulator] if emulator else []))
    assert not stubborn, f'still running 10 s after SIGTERM: {stubborn}'
    assert os.path.lexists(link) is False


def test_a_missing_sensor_is_named_with_its_fix_not_left_silent(tmp_path):
    log = tmp_path / 'teensy.log'
    with open(log, 'w') as err:
        node = subprocess.Popen([BIN / 'teensy_node', '--ros-args', '-p',
                                 f'port:={tmp_path / "ttyNONE"}'], env=ros_environment(),
                                stderr=err)
        try:
            deadline = time.monotonic() + 20
            while 'no sensor stream' not in log.read_text() and time.monotonic() < deadline:
                time.sleep(0.2)
        finally:
            stop([node])
    text = log.read_text()
    assert f'no sensor stream: disconnected: cannot open {tmp_path / "ttyNONE"}' in text
    assert 'dialout group' in text and 'sim:=true' in text
