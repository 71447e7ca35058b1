# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex param list|get|set`: a running node's parameters over rclpy, no `ros2` CLI needed.

The node's own parameter services answer (rcl_interfaces: list_parameters,
get_parameters, set_parameters), as `ros2 param` uses them; a value is read as YAML, as
`ros2 param set` reads it, and the node's descriptor ranges decide whether it is taken.
"""

from __future__ import annotations

import argparse

from tactex.errors import CommandError
from tactex.options import text

SERVICE_TIMEOUT_S = 5.0


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    sub = parser.add_subparsers(dest='action', required=True, metavar='ACTION')
    for action, help_text in (('list', "the node's parameter names"),
                              ('get', "a parameter's value"),
                              ('set', 'set a parameter (the node checks its range)')):
        one = sub.add_parser(action, help=help_text, description=help_text)
        one.add_argument('node', type=text, metavar='NODE',
                         help='node name (e.g. classifier_node) or full name (/ns/name)')
        if action != 'list':
            one.add_argument('name', type=text, metavar='NAME', help='parameter name')
        if action == 'set':
            one.add_argument('value', metavar='VALUE',
                             help='new value, read as YAML: 0.5, true, 7, text, [1, 2]')
        one.add_argument('--namespace', default='', metavar='NS',
                         help='namespace of NODE when NODE is a bare name (e.g. left_arm)')
        one.add_argument('--timeout', type=float, default=SERVICE_TIMEOUT_S, metavar='S',
                         help=f'seconds to wait for the node ({SERVICE_TIMEOUT_S:g})')


def full_name(node: str, namespace: str) -> str:
    """'/ns/node' from a bare or full node name and a namespace."""
    from tactex.ros_client import namespaced
    return node if node.startswith('/') else namespaced(namespace, node)


def as_type_of(current, value):
    """`value` as a double where the parameter is one and an integer was given (5 -> 5.0)."""
    from rcl_interfaces.msg import ParameterType, ParameterValue
    if current.type == ParameterType.PARAMETER_DOUBLE and \
            value.type == ParameterType.PARAMETER_INTEGER:
        return ParameterValue(type=ParameterType.PARAMETER_DOUBLE,
                              double_value=float(value.integer_value))
    return value


def run(args: argparse.Namespace) -> int:
    """Ask the node; print the answer."""
    from rclpy.parameter import get_parameter_value, parameter_value_to_python

    if not args.timeout > 0:
        raise CommandError(f'--timeout {args.timeout}: give a number of seconds > 0')
    from tactex.ros_client import client_node
    node_name = full_name(args.node, args.namespace)
    with client_node('tactex_param') as (client, executor):
        caller = _Caller(client, executor, node_name, args.timeout)
        if args.action == 'list':
            for name in caller.list_names():
                print(name)
        elif args.action == 'get':
            print(parameter_value_to_python(caller.get(args.name)))
        else:
            current = caller.get(args.name)  # an unknown name is refused before any set
            caller.set(args.name, as_type_of(current, get_parameter_value(args.value)),
                       args.value)
            print(f'set {node_name} {args.name} to '
                  f'{parameter_value_to_python(caller.get(args.name))!r}')
    return 0


class _Caller:
    """The node's parameter services, each call bounded by the timeout."""

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
        from rcl_interfaces.srv import ListParameters
        return sorted(self._call(ListParameters, 'list_parameters',
                                 ListParameters.Request()).result.names)

    def get(self, name: str):
        from rcl_interfaces.msg import ParameterType
        from rcl_interfaces.srv import GetParameters
        values = self._call(GetParameters, 'get_parameters',
                            GetParameters.Request(names=[name])).values
        if not values or values[0].type == ParameterType.PARAMETER_NOT_SET:
            raise CommandError(f'{self.node_name} has no parameter {name!r}; see `tactex '
                               f'param list {self.node_name}`')
        return values[0]

    def set(self, name: str, value, given: str) -> None:
        from rcl_interfaces.msg import Parameter
        from rcl_interfaces.srv import SetParameters
        results = self._call(SetParameters, 'set_parameters', SetParameters.Request(
            parameters=[Parameter(name=name, value=value)])).results
        if not results or not results[0].successful:
            reason = results[0].reason if results else 'no answer'
            raise CommandError(f'{self.node_name} refused {name} = {given}: {reason}')
