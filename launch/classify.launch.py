# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the online texture classifier with the tactile sensor or the simulator."""

from tactex.launching.spec import (
    Argument,
    as_float,
    config_path,
    LaunchError,
    LaunchFile,
    NodeSpec,
)


def _nodes(args):
    if not args['checkpoint']:
        raise LaunchError('checkpoint:=RUN/model is required (the folder `tactex train` '
                          'writes)')
    simulated = args['source'] == 'sim'
    if simulated:
        source = [NodeSpec('tactex_sim', 'mujoco_bridge', 'mujoco_bridge', parameters=(
            {'scene': args['scene'],
             'rate_factor': as_float('rate_factor', args['rate_factor'])},))]
    else:
        source = [NodeSpec('tactex_sensor', 'teensy_node', 'teensy_node',
                           parameters=(config_path('sensor.yaml'), {'port': args['port']}))]
    classifier = {'checkpoint': args['checkpoint'], 'runtime': args['runtime'],
                  'threshold': as_float('threshold', args['threshold']), 'use_sim_time': simulated}
    return source + [NodeSpec('tactex_classify', 'classifier_node', 'classifier_node',
                              parameters=(config_path('classify.yaml'), classifier))]


LAUNCH = LaunchFile(
    'the online texture classifier on the tactile sensor (or the simulator)',
    (Argument('checkpoint', '', 'checkpoint folder (RUN/model/ of tactex train)'),
     Argument('source', 'sensor', 'where the tactile topics come from', ('sensor', 'sim')),
     Argument('runtime', 'native', 'inference runtime', ('native', 'onnxruntime')),
     Argument('threshold', '0.99', 'decide when the largest posterior exceeds this'),
     Argument('port', '/dev/ttyACM0', 'serial device of the Teensy (source:=sensor)'),
     Argument('scene', 'uneven_texture', 'scene (source:=sim)'),
     Argument('rate_factor', '1.0', 'simulated seconds per wall second (source:=sim)')),
    _nodes)


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex classify.launch.py checkpoint:=...`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
