# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The environment every tactex ROS process starts with: middleware and discovery profile."""

from __future__ import annotations

from collections.abc import Mapping
import os

from tactex_common.share import share_directory

RMW_IMPLEMENTATION = 'rmw_fastrtps_cpp'


def fastdds_profile_path() -> str:
    """Return the path of the workspace's Fast DDS profile (fast initial discovery)."""
    return str(share_directory('tactex') / 'config' / 'fastdds_profile.xml')


def ros_environment(base: Mapping[str, str] | None = None) -> dict[str, str]:
    """Return `base` (default: os.environ) with the tactex middleware settings added.

    Discovery stays on this host, as a launch's default (`discovery:=localhost`), so the
    commands that join a running system (view, record, the goal and parameter clients)
    find nodes here and are found from nowhere else. Settings the user already made are
    kept: a user's own profile, RMW or discovery range wins.
    """
    env = dict(os.environ if base is None else base)
    env.setdefault('RMW_IMPLEMENTATION', RMW_IMPLEMENTATION)
    env.setdefault('FASTDDS_DEFAULT_PROFILES_FILE', fastdds_profile_path())
    env.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
    return env
