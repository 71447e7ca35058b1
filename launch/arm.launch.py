# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the arm driver with config/driver.yaml; `port:=...` overrides the serial device."""

from pathlib import Path

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description() -> LaunchDescription:
    """The arm_driver node."""
    parameters = Path(get_package_share_directory('tactex')) / 'config' / 'driver.yaml'
    return LaunchDescription([
        DeclareLaunchArgument('port', default_value='/dev/ttyUSB0',
                              description='serial device of the U2D2 / OpenCR'),
        Node(package='tactex_driver', executable='arm_driver', name='arm_driver',
             parameters=[str(parameters), {'port': LaunchConfiguration('port')}],
             output='screen'),
    ])
