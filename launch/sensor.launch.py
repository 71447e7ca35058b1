# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the tactile module: teensy_node (serial -> raw topics) and madgwick_node."""

from tactex.launching.spec import Arg, Argument, config_path, LaunchFile, NodeSpec

LAUNCH = LaunchFile(
    'the tactile module on a serial port, and the Madgwick filter',
    (Argument('port', '/dev/ttyACM0', 'serial device of the Teensy'),),
    (NodeSpec('tactex_sensor', 'teensy_node', 'teensy_node',
              parameters=(config_path('sensor.yaml'), {'port': Arg('port')})),
     NodeSpec('tactex_sensor', 'madgwick_node', 'madgwick_node',
              parameters=(config_path('sensor.yaml'),))))


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex sensor.launch.py port:=...`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
