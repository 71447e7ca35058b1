# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch everything: the robot (or MuJoCo), probing, sweeping with recording, live classification.

The robot is launch/sim.launch.py's (or sensor.launch.py's and arm.launch.py's), the probe
node probe.launch.py's, the sweep node sweep.launch.py's and the classifier
classify.launch.py's and the identification node identify.launch.py's, so each node is
declared once. `checkpoint:=RUN/model` adds the online classifier, `bundle:=RUN/bundle`
the identification node; without either the system probes, sweeps and records (what a
dataset needs before there is a model).
"""

from tactex.launching.spec import (
    Arg,
    Argument,
    config_path,
    If,
    IfElse,
    Include,
    include_robot,
    LaunchFile,
    not_equals,
    robot_arguments,
)

NODES_ONLY = {'robot': 'false', 'sim': Arg('sim')}  # the robot is this file's own include

LAUNCH = LaunchFile(
    'everything: arm + sensor (or MuJoCo), probe, sweep with recording, live classification',
    (*robot_arguments(scene='uneven_texture', optional=False),
     Argument('checkpoint', '', "RUN/model/ of tactex train: classify live ('': no classifier)"),
     Argument('runtime', 'native', 'inference runtime of the classifier',
              ('native', 'onnxruntime')),
     Argument('threshold', '0.99', 'the classifier decides above this posterior', kind='float'),
     Argument('bundle', '', "RUN/bundle of tactex train --movements: identify by choosing "
              "movements ('': no identification)"),
     Argument('movements', config_path('movements.yaml'),
              'the movement file the bundle was trained for'),
     Argument('recording_root', 'recordings', 'folder of the recordings of sweeps'),
     Argument('pathway_file', '~/.ros/tactex/pathway.json',
              "where the probe node keeps the pathway (config/probe.yaml's)"),
     Argument('probe_on_start', 'false', 'probe with the goal of config/probe.yaml at start',
              kind='bool')),
    (include_robot(),
     Include('probe', {**NODES_ONLY, 'probe_on_start': Arg('probe_on_start'),
                       'pathway_file': Arg('pathway_file')}),
     Include('sweep', {**NODES_ONLY, 'recording_root': Arg('recording_root')}),
     Include('classify', {'robot': 'false', 'checkpoint': Arg('checkpoint'),
                          'source': IfElse('sim', 'sim', 'sensor'), 'runtime': Arg('runtime'),
                          'threshold': Arg('threshold')},
             If(not_equals('checkpoint', ''))),
     Include('identify', {'bundle': Arg('bundle'), 'movements': Arg('movements'),
                          'sim': Arg('sim')},
             If(not_equals('bundle', '')))))


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex system.launch.py sim:=true`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
