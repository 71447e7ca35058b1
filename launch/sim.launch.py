# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the MuJoCo bridge in place of the arm and the sensor, plus the Madgwick filter."""

from pathlib import Path

from ament_index_python.packages import get_package_share_directory
from launch import LaunchDescription
from launch.actions import DeclareLaunchArgument
from launch.substitutions import LaunchConfiguration
from launch_ros.actions import Node


def generate_launch_description() -> LaunchDescription:
    """mujoco_bridge (scene:=..., rate_factor:=...) and madgwick_node on simulated time."""
    sensor_parameters = Path(get_package_share_directory('tactex')) / 'config' / 'sensor.yaml'
    return LaunchDescription([
        DeclareLaunchArgument('scene', default_value='probe',
                              description='scene under config/scenes/'),
        DeclareLaunchArgument('rate_factor', default_value='1.0',
                              description='simulated seconds per wall second (0: max)'),
        Node(package='tactex_sim', executable='mujoco_bridge', name='mujoco_bridge',
             parameters=[{'scene': LaunchConfiguration('scene'),
                          'rate_factor': LaunchConfiguration('rate_factor')}],
             output='screen'),
        Node(package='tactex_sensor', executable='madgwick_node', name='madgwick_node',
             parameters=[str(sensor_parameters), {'use_sim_time': True}], output='screen'),
    ])
