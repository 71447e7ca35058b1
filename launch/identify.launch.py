# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the identification node (the `identify` action) beside a running sweep node.

It drives the sweep action of launch/sweep.launch.py (or system.launch.py, which
includes this file when given `bundle:=RUN/bundle`); `sim:=true` runs it on the
simulator's clock.
"""

from tactex.launching.spec import Arg, Argument, config_path, LaunchFile, NodeSpec

LAUNCH = LaunchFile(
    'the identification node: chooses movements and drives the sweep action',
    (Argument('bundle', None, 'identification bundle (RUN/bundle of tactex train --movements)'),
     Argument('movements', config_path('movements.yaml'),
              'the movement file the bundle was trained for'),
     Argument('sim', 'false', "run on the simulator's clock", kind='bool')),
    (NodeSpec('tactex_classify', 'identify_node', 'identify_node', parameters=(
        config_path('identify.yaml'),
        {'bundle': Arg('bundle'), 'movements': Arg('movements'),
         'use_sim_time': Arg('sim')})),))


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex identify.launch.py bundle:=...`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
