# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Nodes in separate processes find each other with the workspace's Fast DDS profile."""

import os
from pathlib import Path
import subprocess
import sys
import textwrap
import time
from xml.etree import ElementTree as ET

import pytest

from tactex.launching.environment import fastdds_profile_path, ros_environment

pytestmark = [pytest.mark.integration, pytest.mark.ros]

TALKER = textwrap.dedent("""
    import rclpy
    from std_msgs.msg import String
    rclpy.init()
    node = rclpy.create_node('tactex_discovery_talker')
    publisher = node.create_publisher(String, 'tactex_discovery_check', 10)
    node.create_timer(0.05, lambda: publisher.publish(String(data='hello')))
    try:
        rclpy.spin(node)
    except KeyboardInterrupt:
        pass
""")


def test_profile_announces_twenty_times_100_ms_apart():
    namespace = {'dds': 'http://www.eprosima.com'}
    root = ET.parse(fastdds_profile_path()).getroot()
    announcements = root.find('.//dds:initialAnnouncements', namespace)
    assert announcements.findtext('dds:count', namespaces=namespace) == '20'
    assert announcements.findtext('dds:period/dds:nanosec', namespaces=namespace) == '100000000'


def test_ros_environment_keeps_the_users_own_settings():
    env = ros_environment({'FASTDDS_DEFAULT_PROFILES_FILE': '/etc/mine.xml',
                           'ROS_AUTOMATIC_DISCOVERY_RANGE': 'SUBNET'})
    assert env['FASTDDS_DEFAULT_PROFILES_FILE'] == '/etc/mine.xml'
    assert env['ROS_AUTOMATIC_DISCOVERY_RANGE'] == 'SUBNET'
    assert env['RMW_IMPLEMENTATION'] == 'rmw_fastrtps_cpp'
    assert Path(ros_environment({})['FASTDDS_DEFAULT_PROFILES_FILE']).is_file()


def test_a_command_joining_a_system_discovers_on_this_host_only_as_a_launch_does():
    assert ros_environment({})['ROS_AUTOMATIC_DISCOVERY_RANGE'] == 'LOCALHOST'


def test_a_subscriber_hears_a_publisher_in_another_process():
    import rclpy
    from rclpy.context import Context
    from std_msgs.msg import String

    assert os.environ['FASTDDS_DEFAULT_PROFILES_FILE'] == fastdds_profile_path()
    talker = subprocess.Popen([sys.executable, '-c', TALKER], env=ros_environment())
    context = Context()
    rclpy.init(context=context)
    try:
        node = rclpy.create_node('tactex_discovery_listener', context=context)
        heard = []
        node.create_subscription(String, 'tactex_discovery_check',
                                 lambda msg: heard.append(msg.data), 10)
        executor = rclpy.executors.SingleThreadedExecutor(context=context)
        executor.add_node(node)
        deadline = time.monotonic() + 20.0
        while not heard and time.monotonic() < deadline:
            executor.spin_once(timeout_sec=0.1)
        assert heard and heard[0] == 'hello'
        node.destroy_node()
    finally:
        rclpy.shutdown(context=context)
        talker.terminate()
        talker.wait(timeout=10)
