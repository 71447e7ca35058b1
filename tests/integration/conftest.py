# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Fixtures of the node tests: a ROS context of the test's own, shut down after it."""

import pytest


@pytest.fixture
def ros_context():
    import rclpy
    from rclpy.context import Context
    context = Context()
    rclpy.init(context=context)
    yield context
    rclpy.shutdown(context=context)
