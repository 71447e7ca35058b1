# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch the MuJoCo bridge in place of the arm and the sensor, plus the Madgwick filter."""

from tactex.launching.spec import Arg, Argument, config_path, LaunchFile, NodeSpec

LAUNCH = LaunchFile(
    'MuJoCo in place of the arm and the tactile module, and the Madgwick filter',
    (Argument('scene', 'probe', 'scene under config/scenes/ or a .toml path'),
     Argument('rate_factor', '1.0', 'simulated seconds per wall second (0: as fast as possible)',
              kind='float'),
     Argument('patch_texture', '',
              "texture of every patch ('': the scene's); the bridge's parameter of that name "
              'changes it while running')),
    (NodeSpec('tactex_sim', 'mujoco_bridge', 'mujoco_bridge', parameters=(
        {'scene': Arg('scene'), 'rate_factor': Arg('rate_factor'),
         'patch_texture': Arg('patch_texture')},)),
     NodeSpec('tactex_sensor', 'madgwick_node', 'madgwick_node',
              parameters=(config_path('sensor.yaml'), {'use_sim_time': True}))))


def generate_launch_description():
    """ROS 2 launch entry point (`ros2 launch tactex sim.launch.py scene:=...`)."""
    from tactex.launching.ros_description import launch_description
    return launch_description(LAUNCH)
