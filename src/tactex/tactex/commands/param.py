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
from tactex.options import namespace, text

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
        one.add_argument('--namespace', type=namespace, default='', metavar='NS',
                         help='namespace of NODE when NODE is a bare name (e.g. left_arm)')
        one.add_argument('--timeout', type=float, default=SERVICE_TIMEOUT_S, metavar='S',
                         help=f'seconds to wait for the node ({SERVICE_TIMEOUT_S:g})')


def full_name(node: str, namespace: str) -> str:
    """'/ns/node' from a bare or full node name and a namespace."""
    from tactex.ros_client import namespaced
    return node if node.startswith('/') else namespaced(namespace, node)


def run(args: argparse.Namespace) -> int:
    """Ask the node; print the answer."""
    if not args.timeout > 0:
        raise CommandError(f'--timeout {args.timeout}: give a number of seconds > 0')
    from tactex.ros_client import client_node, ParameterClient
    node_name = full_name(args.node, args.namespace)
    with client_node('tactex_param') as (node, executor):
        parameters = ParameterClient(node, executor, node_name, args.timeout)
        if args.action == 'list':
            for name in parameters.list_names():
                print(name)
        elif args.action == 'get':
            print(parameters.get(args.name))
        else:
            print(f'set {node_name} {args.name} to {parameters.set(args.name, args.value)!r}')
    return 0
