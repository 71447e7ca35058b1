# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""rclpy for the client commands (param, status, watch): a node of their own, parameters."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
import os

from rcl_interfaces.msg import Parameter, ParameterType, ParameterValue
from rcl_interfaces.srv import GetParameters, ListParameters, SetParameters
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.parameter import get_parameter_value, parameter_value_to_python

from tactex.errors import CommandError
from tactex.launching.environment import ros_environment
from tactex_common.ros import COMMAND

__all__ = ['client_node', 'COMMAND', 'namespaced', 'ParameterClient']


@contextmanager
def client_node(name: str) -> Iterator[tuple[object, SingleThreadedExecutor]]:
    """(node, executor) with the middleware settings the launched nodes have; shut down after."""
    os.environ.update(ros_environment())
    context = rclpy.Context()
    rclpy.init(args=[], context=context)  # the command line is the command's, not ROS's
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


class ParameterClient:
    """A node's parameter services (as `ros2 param` uses them), each call within the timeout."""

    def __init__(self, client, executor, node_name: str, timeout_s: float) -> None:
        self.client, self.executor = client, executor
        self.node_name, self.timeout_s = node_name, timeout_s

    def _call(self, service_type, suffix: str, request):
        service = f'{self.node_name}/{suffix}'
        proxy = self.client.create_client(service_type, service)
        if not proxy.wait_for_service(timeout_sec=self.timeout_s):
            raise CommandError(
                f'no node {self.node_name} answers on {service} within {self.timeout_s:g} s: '
                'is it running, under that namespace (--namespace) and ROS_DOMAIN_ID, and '
                'on this machine or ROS_AUTOMATIC_DISCOVERY_RANGE?')
        future = proxy.call_async(request)
        self.executor.spin_until_future_complete(future, timeout_sec=self.timeout_s)
        if not future.done() or future.result() is None:
            raise CommandError(f'{service} did not answer within {self.timeout_s:g} s')
        return future.result()

    def list_names(self) -> list[str]:
        """The node's parameter names, sorted."""
        return sorted(self._call(ListParameters, 'list_parameters',
                                 ListParameters.Request()).result.names)

    def get(self, name: str):
        """The parameter's value as Python."""
        return parameter_value_to_python(self._value(name))

    def _value(self, name: str):
        values = self._call(GetParameters, 'get_parameters',
                            GetParameters.Request(names=[name])).values
        if not values or values[0].type == ParameterType.PARAMETER_NOT_SET:
            raise CommandError(f'{self.node_name} has no parameter {name!r}; see `tactex '
                               f'param list {self.node_name}`')
        return values[0]

    def set(self, name: str, text: str):
        """Set the parameter to `text` read as YAML (as `ros2 param set`); the value it holds.

        An integer given for a double is taken as one; an unknown name is refused before
        anything is set.
        """
        value = get_parameter_value(text)
        if self._value(name).type == ParameterType.PARAMETER_DOUBLE and \
                value.type == ParameterType.PARAMETER_INTEGER:
            value = ParameterValue(type=ParameterType.PARAMETER_DOUBLE,
                                   double_value=float(value.integer_value))
        results = self._call(SetParameters, 'set_parameters', SetParameters.Request(
            parameters=[Parameter(name=name, value=value)])).results
        if not results or not results[0].successful:
            reason = results[0].reason if results else 'no answer'
            raise CommandError(f'{self.node_name} refused {name} = {text}: {reason}')
        return self.get(name)
