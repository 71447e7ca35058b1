# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch probing: the sensor and the arm (or the simulator), Madgwick, and the probe node."""

from tactex.launching.spec import (
    Argument,
    config_path,
    is_true,
    LaunchFile,
    NodeSpec,
    robot_nodes,
)


def _nodes(args):
    sim = is_true(args['sim'])
    settings = {'probe_on_start': is_true(args['probe_on_start']), 'use_sim_time': sim}
    if args['pathway_file']:
        settings['pathway_file'] = args['pathway_file']
    probe = NodeSpec('tactex_probe', 'probe_node', 'probe_node',
                     parameters=(config_path('probe.yaml'), settings))
    return [*robot_nodes(args), probe]


LAUNCH = LaunchFile(
    'probe an unknown surface for a pathway: sensor + arm (or MuJoCo), Madgwick, probe node',
    (Argument('sim', 'false', 'MuJoCo in place of the arm and the tactile module',
              ('true', 'false')),
     Argument('probe_on_start', 'false', 'start probing with the goal of config/probe.yaml',
              ('true', 'false')),
     Argument('pathway_file', '', "where the pathway is kept ('': config/probe.yaml's)"),
     Argument('scene', 'probe', 'sim:=true: scene under config/scenes/ or a .toml path'),
     Argument('rate_factor', '1.0', 'sim:=true: simulated seconds per wall second'),
     Argument('sensor_port', '/dev/ttyACM0', 'sim:=false: serial device of the Teensy'),
     Argument('arm_port', '/dev/ttyUSB0', 'sim:=false: serial device of the U2D2 / OpenCR')),
    _nodes)


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex probe.launch.py sim:=true`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
