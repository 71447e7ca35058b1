# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the sweep action server with the arm and the sensor, or with the simulator.

`sim:=true` starts MuJoCo (launch/sim.launch.py, the uneven texture scene by default) and
runs the sweep node on its simulated clock; otherwise the arm driver and the tactile
module (launch/arm.launch.py, launch/sensor.launch.py) on their serial ports.
"""

from tactex.launching.spec import (
    Arg,
    Argument,
    config_path,
    If,
    include_robot,
    LaunchFile,
    NodeSpec,
    robot_arguments,
)

LAUNCH = LaunchFile(
    'the sweep action server with the arm and the tactile module, or with MuJoCo',
    (*robot_arguments(scene='uneven_texture'),
     Argument('recording_root', 'recordings',
              'directory for the recordings of goals with record: true')),
    (include_robot(If(Arg('robot'))),
     NodeSpec('tactex_trajectory', 'sweep_node', 'sweep_node', parameters=(
         config_path('sweep.yaml'),
         {'use_sim_time': Arg('sim'), 'recording_root': Arg('recording_root')}))))


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex sweep.launch.py sim:=true`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
