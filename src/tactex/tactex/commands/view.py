# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex view`: the live system in Foxglove, through a WebSocket server (view_node).

Runs view_node's ViewNode in this process until Ctrl-C: the tactile channels, the arm (its URDF and
joint transforms), the probed pathway, the sweep state and the texture estimates, on
ws://HOST:PORT. In Foxglove: Open connection, Foxglove WebSocket, that URL; then import
the layout config/foxglove_layout.json. `view:=true` on a launch starts the same node.
"""

from __future__ import annotations

import argparse

from tactex.options import integer, namespace, text


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--namespace', type=namespace, default='', metavar='NS',
                        help="the system's namespace (e.g. left_arm)")
    parser.add_argument('--host', type=text, default='127.0.0.1', metavar='ADDRESS',
                        help='address to listen on (default 127.0.0.1; 0.0.0.0 opens it to '
                             'the network, with no authentication)')
    parser.add_argument('--port', type=integer(0, 65535), default=8765, metavar='PORT',
                        help='TCP port (default 8765, 0: any free one)')


def run(args: argparse.Namespace) -> int:
    """Serve until a stop signal; a host or port it cannot listen on is one error line."""
    import os

    from tactex.launching.environment import ros_environment
    from tactex.view.server import serve
    os.environ.update(ros_environment())
    ros_args = ['--ros-args', '-p', f'host:={args.host}', '-p', f'port:={args.port}']
    if args.namespace.strip('/'):
        ros_args += ['-r', '__ns:=/' + args.namespace.strip('/')]
    serve(ros_args)
    return 0
