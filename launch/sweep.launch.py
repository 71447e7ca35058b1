# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the sweep action server with the arm and the sensor, or with the simulator.

`sim:=true` starts MuJoCo (launch/sim.launch.py, the uneven texture scene by default) and
runs the sweep node on its simulated clock; otherwise the arm driver and the tactile
module (launch/arm.launch.py, launch/sensor.launch.py) on their serial ports.
"""

from tactex.launching.spec import (
    Argument,
    config_path,
    is_true,
    LaunchFile,
    NodeSpec,
    robot_nodes,
)


def _nodes(args):
    simulated = is_true(args['sim'])
    sweep = NodeSpec('tactex_trajectory', 'sweep_node', 'sweep_node', parameters=(
        config_path('sweep.yaml'),
        {'use_sim_time': simulated, 'recording_root': args['recording_root']}))
    return [*robot_nodes(args), sweep]


LAUNCH = LaunchFile(
    'the sweep action server with the arm and the tactile module, or with MuJoCo',
    (Argument('sim', 'false', 'true: MuJoCo in place of the arm and the sensor',
              ('true', 'false')),
     Argument('scene', 'uneven_texture', 'scene of the simulator (sim:=true)'),
     Argument('rate_factor', '1.0', 'simulated seconds per wall second (sim:=true)'),
     Argument('arm_port', '/dev/ttyUSB0', 'serial device of the U2D2 / OpenCR'),
     Argument('sensor_port', '/dev/ttyACM0', 'serial device of the Teensy'),
     Argument('recording_root', 'recordings',
              'directory for the recordings of goals with record: true')),
    _nodes)


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex sweep.launch.py sim:=true`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
