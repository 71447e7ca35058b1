# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""rclpy for the client commands (param, status, watch): one node on a context of its own."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
import os

import rclpy
from rclpy.executors import SingleThreadedExecutor

from tactex.launching.environment import ros_environment
from tactex_common.ros import COMMAND

__all__ = ['client_node', 'COMMAND', 'namespaced']


@contextmanager
def client_node(name: str) -> Iterator[tuple[object, SingleThreadedExecutor]]:
    """(node, executor) with the middleware settings the launched nodes have; shut down after."""
    os.environ.update(ros_environment())
    context = rclpy.Context()
    rclpy.init(context=context)
    try:
        node = rclpy.create_node(name, context=context)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        yield node, executor
    finally:
        rclpy.try_shutdown(context=context)


def namespaced(namespace: str, name: str) -> str:
    """'/ns/name' (or '/name' without a namespace) for a relative topic or node name."""
    namespace = namespace.strip('/')
    return f'/{namespace}/{name}' if namespace else f'/{name}'
