# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch support: one description of each launch file, run by ROS 2 launch or without it.

Each `launch/<name>.launch.py` defines `LAUNCH = LaunchFile(...)` (`spec`): its
arguments with defaults and choices, and its entities (nodes, includes of other launch
files, groups, with conditions), in the words of ROS 2 launch but as plain data. Two
paths read that one description:
- with a full ROS 2 install, `ros2 launch tactex <name>.launch.py` calls the file's
  `generate_launch_description()`, which `ros_description` builds from `LAUNCH` with
  launch and launch_ros actions (Node, IncludeLaunchDescription, GroupAction,
  PushROSNamespace, IfCondition);
- without one (this workspace's PyPI install), `tactex launch <name>` evaluates the
  entities and has `supervisor` start the nodes as supervised processes (restart, stop
  signals, logs), with the middleware settings of `environment`.
`arguments` checks every launch argument by its name before `tactex launch` starts any
node; ROS 2 launch checks the choices and, at the nodes, the parameter ranges.
"""
