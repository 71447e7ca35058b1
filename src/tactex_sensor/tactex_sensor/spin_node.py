# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The `main` every tactex node shares: init, spin until shutdown, always clean up."""

from __future__ import annotations

from collections.abc import Callable

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node


def spin(make_node: Callable[[], Node], args: list[str] | None = None) -> None:
    """Create the node and spin it; Ctrl-C or an external shutdown ends it cleanly."""
    rclpy.init(args=args)
    node = None
    try:
        node = make_node()
        rclpy.spin(node)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        if node is not None:
            node.destroy_node()
        rclpy.try_shutdown()
