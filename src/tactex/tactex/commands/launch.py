# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex launch NAME [arg:=value ...]`: check every argument, then run the nodes."""

from __future__ import annotations

import argparse
import sys


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('name', nargs='?',
                        help='launch file under launch/ without .launch.py (e.g. sim), or a path')
    parser.add_argument('arguments', nargs=argparse.REMAINDER, metavar='ARG:=VALUE',
                        help='launch arguments, as ros2 launch takes them')
    parser.add_argument('--list', action='store_true',
                        help='list the launch files, or the arguments of NAME')
    parser.add_argument('--print', action='store_true', dest='print_only',
                        help='print the command line of every node and exit')
    parser.add_argument('--no-checks', action='store_true', dest='no_checks',
                        help="start hardware nodes without tactex doctor's checks of their "
                             'ports first (as checks:=false)')


FLAGS = {'--list': 'list', '--print': 'print_only', '--no-checks': 'no_checks'}


def _overrides(items: list[str], args: argparse.Namespace) -> dict[str, str]:
    """NAME:=VALUE pairs; the flags may also follow the launch file's name."""
    overrides = {}
    for item in items:
        if item in FLAGS:
            setattr(args, FLAGS[item], True)
            continue
        name, sep, value = item.partition(':=')
        if not sep or not name:
            raise ValueError(f'launch argument {item!r} is not NAME:=VALUE')
        overrides[name] = value
    return overrides


def run(args: argparse.Namespace) -> int:
    """List, print or run."""
    from tactex.launching.arguments import check_arguments
    from tactex.launching.spec import is_true, launch_directory, LaunchError, load_launch_file
    from tactex.launching.supervisor import node_command, run_launch

    try:
        if args.name is None:
            if not args.list:
                raise LaunchError('name a launch file (tactex launch --list shows them)')
            for path in sorted(launch_directory().glob('*.launch.py')):
                name = path.name.removesuffix('.launch.py')
                print(f'{name:10} {load_launch_file(name).description}')
            return 0
        launch = load_launch_file(args.name)
        overrides = _overrides(args.arguments, args)
        if args.list:
            for argument in launch.all_arguments:
                choices = f' ({"|".join(argument.choices)})' if argument.choices else ''
                print(f'{argument.name}:={argument.default!r}{choices}  {argument.description}')
            return 0
        values = launch.resolve(overrides)
        check_arguments(launch, values)
        nodes = launch.node_specs(values)
        if args.print_only:
            for spec in nodes:
                print(' '.join(node_command(spec, values['namespace'])))
            return 0
    except (LaunchError, ValueError) as err:
        print(f'error: {err}', file=sys.stderr)
        return 1
    if not args.no_checks and is_true(values['checks']) and not hardware_ready(nodes):
        return 1
    return run_launch(nodes, values)


def hardware_ready(nodes) -> bool:
    """Run the bring-up checks of the hardware nodes; print and return False when one fails."""
    from tactex.bringup import not_ready_lines
    report = not_ready_lines(nodes)
    for line in report:
        print(line, file=sys.stderr)
    return not report
