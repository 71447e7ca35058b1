# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex description`: show the robot model, write URDF/MJCF, check the checked-in URDF."""

from __future__ import annotations

import argparse
from pathlib import Path
import sys


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--write-urdf', type=Path, metavar='PATH',
                        help='write the URDF generated from the geometry module to PATH')
    parser.add_argument('--check-urdf', type=Path, metavar='PATH',
                        help='exit 1 when the URDF at PATH differs from the generated one')
    parser.add_argument('--write-mjcf', type=Path, metavar='PATH',
                        help='write the MuJoCo model of the arm to PATH')


def run(args: argparse.Namespace) -> int:
    """Print the joint table, then do what the options ask."""
    from tactex_description.geometry import JointKind, OPEN_MANIPULATOR_X
    from tactex_description.mjcf import build_mjcf
    from tactex_description.urdf import build_urdf

    print(f'{"joint":<16}{"type":<11}{"role":<11}{"lower":>9}{"upper":>9}{"velocity":>10}')
    for joint in OPEN_MANIPULATOR_X.joints:
        if joint.kind is not JointKind.FIXED:
            print(f'{joint.name:<16}{joint.kind.value:<11}{joint.role.value:<11}'
                  f'{joint.lower:>9.4f}{joint.upper:>9.4f}{joint.velocity:>10.3f}')
    if args.write_urdf:
        args.write_urdf.write_text(build_urdf(), encoding='utf-8')
        print(f'wrote {args.write_urdf}')
    if args.write_mjcf:
        args.write_mjcf.write_text(build_mjcf(), encoding='utf-8')
        print(f'wrote {args.write_mjcf}')
    if args.check_urdf:
        if not args.check_urdf.is_file():
            print(f'error: no URDF at {args.check_urdf}', file=sys.stderr)
            return 1
        if args.check_urdf.read_text(encoding='utf-8') != build_urdf():
            print(f'error: {args.check_urdf} is stale; regenerate it with `make urdf`',
                  file=sys.stderr)
            return 1
        print(f'{args.check_urdf} matches the geometry module')
    return 0
