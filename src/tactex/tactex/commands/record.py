# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex record`: run the recorder node with its settings given on the command line."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
import shutil
import subprocess
import sys


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--out', type=Path, required=True, help='recording directory')
    parser.add_argument('--label', default='', help='texture class')
    parser.add_argument('--trial', type=int, default=-1, help='recording / trajectory id')
    parser.add_argument('--surface', default='', help='surface, e.g. uneven')
    parser.add_argument('--meta', action='append', default=[], metavar='KEY=VALUE',
                        help='more metadata (repeatable)')
    parser.add_argument('--split-s', type=float, default=1.0,
                        help='seconds per part bag: the most a crash can lose (1.0)')
    parser.add_argument('--compress', action='store_true', help='zstd-compress messages')


def run(args: argparse.Namespace) -> int:
    """Start recorder_node in the foreground until Ctrl-C."""
    from tactex.ros_env import ros_environment

    extra = {}
    for item in args.meta:
        key, sep, value = item.partition('=')
        if not sep or not key:
            print(f'error: --meta {item!r} is not KEY=VALUE', file=sys.stderr)
            return 1
        extra[key] = value
    executable = shutil.which('recorder_node') or str(Path(sys.executable).parent /
                                                      'recorder_node')
    command = [executable, '--ros-args', '-p', f'output:={args.out}', '-p',
               f'label:={args.label}', '-p', f'trial:={args.trial}', '-p',
               f'surface:={args.surface}', '-p', f"metadata:='{_yaml_safe(json.dumps(extra))}'",
               '-p',
               f'split_s:={args.split_s}', '-p', f'compress:={str(args.compress).lower()}']
    try:
        return subprocess.call(command, env=ros_environment())
    except KeyboardInterrupt:
        return 0


def _yaml_safe(text: str) -> str:
    """Escape single quotes for a single-quoted YAML scalar (parameter overrides are YAML)."""
    return text.replace("'", "''")
