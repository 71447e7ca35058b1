# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the arm driver with config/driver.yaml; `port:=...` overrides the serial device."""

from tactex.launching.spec import Arg, Argument, config_path, LaunchFile, NodeSpec

LAUNCH = LaunchFile(
    'the arm driver on a Dynamixel bus',
    (Argument('port', '/dev/ttyUSB0', 'serial device of the U2D2 / OpenCR'),),
    (NodeSpec('tactex_driver', 'arm_driver', 'arm_driver',
              parameters=(config_path('driver.yaml'), {'port': Arg('port')})),))


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex arm.launch.py port:=...`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
