# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch everything: the robot (or MuJoCo), probing, sweeping with recording, live classification.

The robot is launch/sim.launch.py's (or sensor.launch.py's and arm.launch.py's), the probe
node probe.launch.py's, the sweep node sweep.launch.py's and the classifier
classify.launch.py's, so each node is declared once. `checkpoint:=RUN/model` adds the
online classifier; without one the system probes, sweeps and records (what a dataset
needs before there is a model).
"""

from tactex.launching.spec import Argument, is_true, LaunchFile, load_launch_file, robot_nodes


def _nodes(args):
    simulated = is_true(args['sim'])
    nodes = [*robot_nodes(args, patch_texture=args['patch_texture']),
             load_launch_file('probe').node('probe_node', {
                 'sim': args['sim'], 'probe_on_start': args['probe_on_start'],
                 'pathway_file': args['pathway_file']}),
             load_launch_file('sweep').node('sweep_node', {
                 'sim': args['sim'], 'recording_root': args['recording_root']})]
    if args['checkpoint']:
        nodes.append(load_launch_file('classify').node('classifier_node', {
            'checkpoint': args['checkpoint'], 'source': 'sim' if simulated else 'sensor',
            'runtime': args['runtime'], 'threshold': args['threshold']}))
    return nodes


LAUNCH = LaunchFile(
    'everything: arm + sensor (or MuJoCo), probe, sweep with recording, live classification',
    (Argument('sim', 'false', 'MuJoCo in place of the arm and the tactile module',
              ('true', 'false')),
     Argument('checkpoint', '', "RUN/model/ of tactex train: classify live ('': no classifier)"),
     Argument('runtime', 'native', 'inference runtime of the classifier',
              ('native', 'onnxruntime')),
     Argument('threshold', '0.99', 'the classifier decides above this posterior'),
     Argument('recording_root', 'recordings', 'folder of the recordings of sweeps'),
     Argument('pathway_file', '', "where the probe node keeps the pathway ('': "
              "config/probe.yaml's)"),
     Argument('probe_on_start', 'false', 'probe with the goal of config/probe.yaml at start',
              ('true', 'false')),
     Argument('scene', 'uneven_texture', 'sim:=true: scene under config/scenes/ or a .toml path'),
     Argument('rate_factor', '1.0', 'sim:=true: simulated seconds per wall second'),
     Argument('patch_texture', '',
              "sim:=true: texture of every patch ('': the scene's; settable while running)"),
     Argument('sensor_port', '/dev/ttyACM0', 'sim:=false: serial device of the Teensy'),
     Argument('arm_port', '/dev/ttyUSB0', 'sim:=false: serial device of the U2D2 / OpenCR')),
    _nodes)


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex system.launch.py sim:=true`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
