# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch probing: the sensor and the arm (or the simulator), Madgwick, and the probe node."""

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
    'probe an unknown surface for a pathway: sensor + arm (or MuJoCo), Madgwick, probe node',
    (*robot_arguments(scene='probe'),
     Argument('probe_on_start', 'false', 'start probing with the goal of config/probe.yaml',
              kind='bool'),
     Argument('pathway_file', '~/.ros/tactex/pathway.json',
              "where the pathway is kept (config/probe.yaml's)")),
    (include_robot(If(Arg('robot'))),
     NodeSpec('tactex_probe', 'probe_node', 'probe_node', parameters=(
         config_path('probe.yaml'),
         {'probe_on_start': Arg('probe_on_start'), 'use_sim_time': Arg('sim'),
          'pathway_file': Arg('pathway_file')}))))


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex probe.launch.py sim:=true`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
