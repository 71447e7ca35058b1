# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex status`: one table of what every running node reports on /diagnostics.

Listens for `--duration` seconds (every node publishes about once a second) and prints,
per status, its level, message and key values (rates, latencies, drops, states), as
`ros2 topic echo /diagnostics` would show them without a ROS install; `--namespace`
keeps the statuses of the nodes under it (a status is named `/ns/node: task`). Listening costs
the nodes nothing: they publish their diagnostics whether anyone listens or not.
"""

from __future__ import annotations

import argparse
import textwrap
import time

from tactex.errors import CommandError
from tactex.options import namespace

LEVELS = {0: 'OK', 1: 'WARN', 2: 'ERROR', 3: 'STALE'}
VALUE_WIDTH = 72


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--namespace', type=namespace, default='', metavar='NS',
                        help="only the statuses of the nodes under this namespace (e.g. "
                             "left_arm; default: every node's)")
    parser.add_argument('--duration', type=float, default=3.0, metavar='S',
                        help='seconds to listen (3)')


def table(statuses: dict[str, tuple[int, str, dict[str, str]]]) -> list[str]:
    """Lines of the status table: name, level, message, then its values, sorted by name."""
    if not statuses:
        return []
    width = max(len(name) for name in statuses)
    lines = [f'{"status":{width}}  level  message', '-' * (width + 40)]
    for name in sorted(statuses):
        level, message, values = statuses[name]
        lines.append(f'{name:{width}}  {LEVELS.get(level, str(level)):5}  {message}')
        shown = ', '.join(f'{key}={value}' for key, value in values.items())
        lines += [f'{"":{width}}         {part}' for part in textwrap.wrap(
            shown, VALUE_WIDTH, break_on_hyphens=False)]
    return lines


def run(args: argparse.Namespace) -> int:
    """Listen, then print the table (exit 1 when nothing was heard)."""
    from diagnostic_msgs.msg import DiagnosticArray

    from tactex.ros_client import client_node, COMMAND, namespaced
    from tactex_common import topics
    if not 0 < args.duration <= 3600:
        raise CommandError(f'--duration {args.duration}: give seconds in (0, 3600]')
    topic = topics.DIAGNOSTICS
    under = namespaced(args.namespace, '') if args.namespace else ''
    statuses: dict[str, tuple[int, str, dict[str, str]]] = {}

    def heard(array) -> None:
        for status in array.status:
            node = status.name.split(': ', 1)[0]
            if under and not (node.startswith(under) and '/' not in node[len(under):]):
                continue
            statuses[status.name] = (int.from_bytes(status.level, 'little')
                                     if isinstance(status.level, bytes) else int(status.level),
                                     status.message, {v.key: v.value for v in status.values})
    with client_node('tactex_status') as (node, executor):
        node.create_subscription(DiagnosticArray, topic, heard, COMMAND)
        deadline = time.monotonic() + args.duration
        while time.monotonic() < deadline:
            executor.spin_once(timeout_sec=min(0.1, max(deadline - time.monotonic(), 0.0)))
    if not statuses:
        raise CommandError(f'no diagnostics on {topic}'
                           + (f' from nodes under {under.rstrip("/")}' if under else '')
                           + f' within {args.duration:g} s: are the nodes running, under that '
                           'namespace (--namespace) and ROS_DOMAIN_ID?')
    print('\n'.join(table(statuses)))
    return 0
