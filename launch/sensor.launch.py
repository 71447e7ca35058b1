# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the tactile module: teensy_node (serial -> raw topics) and madgwick_node."""

from pathlib import Path

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description() -> LaunchDescription:
    """Both sensor nodes with config/sensor.yaml; `port:=...` overrides the serial device."""
    parameters = Path(get_package_share_directory('tactex')) / 'config' / 'sensor.yaml'
    port = LaunchConfiguration('port')
    return LaunchDescription([
        DeclareLaunchArgument('port', default_value='/dev/ttyACM0',
                              description='serial device of the Teensy'),
        Node(package='tactex_sensor', executable='teensy_node', name='teensy_node',
             parameters=[str(parameters), {'port': port}], output='screen'),
        Node(package='tactex_sensor', executable='madgwick_node', name='madgwick_node',
             parameters=[str(parameters)], output='screen'),
    ])
