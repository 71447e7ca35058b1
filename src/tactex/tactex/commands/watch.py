# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex watch`: the live texture estimates, with their evidence and decisions.

Subscribes to `texture/estimate` (classifier_node) and shows each estimate: the leading
texture and its posterior, the runner-up, the windows and contact seconds behind it, and
DECIDED once the node's threshold is passed. On a terminal the line is refreshed in place
(a decision stays on its own line); otherwise one line per estimate. Ctrl-C ends it.
"""

from __future__ import annotations

import argparse
import sys
import time

from tactex.errors import CommandError
from tactex.options import namespace


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--namespace', type=namespace, default='', metavar='NS',
                        help='namespace of classifier_node (e.g. left_arm)')
    parser.add_argument('--count', type=int, default=0, metavar='N',
                        help='stop after N estimates (0: until Ctrl-C)')
    parser.add_argument('--timeout', type=float, default=0.0, metavar='S',
                        help='stop with an error when no estimate came for S seconds (0: wait)')


def line(message) -> str:
    """One estimate as a line: leader, posterior, runner-up, evidence, decision."""
    probabilities = list(message.probabilities)
    names = list(message.class_names)
    ranked = sorted(zip(probabilities, names, strict=False), reverse=True)
    second = f', then {ranked[1][1]} {100 * ranked[1][0]:.1f} %' if len(ranked) > 1 else ''
    verdict = 'DECIDED' if message.decided else 'deciding'
    return (f'{verdict:8}  {message.label or "-"} {100 * message.confidence:.1f} %{second}; '
            f'{message.windows_used} windows, {message.contact_seconds:.1f} s of contact')


def run(args: argparse.Namespace) -> int:
    """Show estimates until --count, --timeout or Ctrl-C."""
    from tactex.ros_client import client_node, COMMAND, namespaced
    from tactex_common import topics
    from tactex_msgs.msg import TextureEstimate
    if args.count < 0 or not 0 <= args.timeout <= 86400:
        raise CommandError('--count must be >= 0 and --timeout seconds in 0..86400')
    topic = namespaced(args.namespace, topics.TEXTURE_ESTIMATE)
    in_place = sys.stdout.isatty()
    shown = 0
    last = time.monotonic()

    def heard(message) -> None:
        nonlocal shown, last
        shown, last = shown + 1, time.monotonic()
        text = line(message)
        if in_place:
            print('\r\033[K' + text, end='\n' if message.decided else '', flush=True)
        else:
            print(text, flush=True)
    try:
        with client_node('tactex_watch') as (node, executor):
            node.create_subscription(TextureEstimate, topic, heard, COMMAND)
            while not args.count or shown < args.count:
                executor.spin_once(timeout_sec=0.1)
                if args.timeout and time.monotonic() - last > args.timeout:
                    raise CommandError(f'no estimate on {topic} for {args.timeout:g} s: is '
                                       'classifier_node running there (tactex launch '
                                       'classify)?')
    finally:
        if in_place:
            print()
    return 0
