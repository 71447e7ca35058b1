# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Test harness: ROS middleware settings, discovery kept on this host, quiet threads."""

import os

from tactex.ros_env import ros_environment

os.environ.update(ros_environment())
# Tests talk to nodes on this machine only.
os.environ.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
# Torch and ROS nodes share two cores: OpenMP must not spin.
os.environ.setdefault('OMP_WAIT_POLICY', 'PASSIVE')
