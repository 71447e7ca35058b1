# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the online texture classifier with the tactile sensor or the simulator."""

from tactex.launching.spec import (
    Arg,
    Argument,
    config_path,
    Equals,
    Group,
    If,
    LaunchFile,
    NodeSpec,
    Unless,
)

SIMULATED = Equals('source', 'sim')

LAUNCH = LaunchFile(
    'the online texture classifier on the tactile sensor (or the simulator)',
    (Argument('checkpoint', None, 'checkpoint folder (RUN/model/ of tactex train)'),
     Argument('source', 'sensor', 'where the tactile topics come from', ('sensor', 'sim')),
     Argument('robot', 'true', 'also start the source (false: it runs already)', kind='bool'),
     Argument('runtime', 'native', 'inference runtime', ('native', 'onnxruntime')),
     Argument('threshold', '0.99', 'decide when the largest posterior exceeds this',
              kind='float'),
     Argument('port', '/dev/ttyACM0', 'serial device of the Teensy (source:=sensor)'),
     Argument('scene', 'uneven_texture', 'scene (source:=sim)'),
     Argument('rate_factor', '1.0', 'simulated seconds per wall second (source:=sim)',
              kind='float')),
    (Group((NodeSpec('tactex_sim', 'mujoco_bridge', 'mujoco_bridge', condition=If(SIMULATED),
                     parameters=({'scene': Arg('scene'), 'rate_factor': Arg('rate_factor')},)),
            NodeSpec('tactex_sensor', 'teensy_node', 'teensy_node', condition=Unless(SIMULATED),
                     parameters=(config_path('sensor.yaml'), {'port': Arg('port')}))),
           If(Arg('robot'))),
     NodeSpec('tactex_classify', 'classifier_node', 'classifier_node', parameters=(
         config_path('classify.yaml'),
         {'checkpoint': Arg('checkpoint'), 'runtime': Arg('runtime'),
          'threshold': Arg('threshold'), 'use_sim_time': SIMULATED}))))


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex classify.launch.py checkpoint:=...`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
