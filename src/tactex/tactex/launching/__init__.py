# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Launch support: one description of each launch file, run by ROS 2 launch or without it.

Each `launch/<name>.launch.py` defines `LAUNCH = LaunchFile(...)` (`spec`): its
arguments with defaults and choices, and its node set, where each node's parameters
and conditions are plain data. Two paths read that one description:
- with a full ROS 2 install, `ros2 launch tactex_bringup <name>.launch.py` calls the
  file's `generate_launch_description()`, which `ros_description` builds from `LAUNCH`
  with launch and launch_ros actions;
- without one (this workspace's PyPI install), `tactex launch <name>` has `supervisor`
  start the same node set as supervised processes (restart, stop signals, logs), with
  the middleware settings of `environment`.
`arguments` checks every launch argument by its name before any node starts, so both
paths refuse the same bad values with the same message.
"""
