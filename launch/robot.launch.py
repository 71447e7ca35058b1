# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the robot: MuJoCo with sim:=true, else the tactile module and the arm.

The other launch files include this one (robot:=true, their default), so the robot is
declared once: sim.launch.py's nodes in simulation, sensor.launch.py's and arm.launch.py's
on the serial ports otherwise; view:=true adds the Foxglove live view (view_node).
"""

from tactex.launching.spec import Arg, Argument, If, Include, LaunchFile, NodeSpec, Unless

SIMULATED = If(Arg('sim'))
HARDWARE = Unless(Arg('sim'))

LAUNCH = LaunchFile(
    'the robot: MuJoCo and Madgwick (sim:=true), or the tactile module, Madgwick and the arm',
    (Argument('sim', 'false', 'MuJoCo in place of the arm and the tactile module', kind='bool'),
     Argument('scene', 'uneven_texture', 'sim:=true: scene under config/scenes/ or a .toml path'),
     Argument('rate_factor', '1.0', 'sim:=true: simulated seconds per wall second',
              kind='float'),
     Argument('patch_texture', '',
              "sim:=true: texture of every patch ('': the scene's; settable while running)"),
     Argument('sensor_port', '/dev/ttyACM0', 'sim:=false: serial device of the Teensy'),
     Argument('arm_port', '/dev/ttyUSB0', 'sim:=false: serial device of the U2D2 / OpenCR'),
     Argument('view', 'false', 'also start view_node: the live view for Foxglove on '
              'ws://127.0.0.1:8765 (config/foxglove_layout.json)', kind='bool')),
    (Include('sim', {'scene': Arg('scene'), 'rate_factor': Arg('rate_factor'),
                     'patch_texture': Arg('patch_texture')}, SIMULATED),
     Include('sensor', {'port': Arg('sensor_port')}, HARDWARE),
     Include('arm', {'port': Arg('arm_port')}, HARDWARE),
     NodeSpec('tactex', 'view_node', 'view_node', parameters=({'use_sim_time': Arg('sim')},),
              condition=If(Arg('view')))))


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex robot.launch.py sim:=true`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
