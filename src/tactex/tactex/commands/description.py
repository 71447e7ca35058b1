# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex description`: show the robot model, write URDF/MJCF, check the checked-in URDF."""

from __future__ import annotations

import argparse

from tactex.errors import CommandError
from tactex.options import check_input_file, check_output_file, input_path, output_path
from tactex_common.files import read_text

MAX_URDF_BYTES = 16 * 1024**2


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('--write-urdf', type=output_path, metavar='PATH',
                        help='write the URDF generated from the geometry module to PATH')
    parser.add_argument('--check-urdf', type=input_path, metavar='PATH',
                        help='exit 1 when the URDF at PATH differs from the generated one')
    parser.add_argument('--write-mjcf', type=output_path, metavar='PATH',
                        help='write the MuJoCo model of the arm to PATH')


def run(args: argparse.Namespace) -> int:
    """Print the joint table, then do what the options ask."""
    from tactex_description.geometry import JointKind, OPEN_MANIPULATOR_X
    from tactex_description.mjcf import build_mjcf
    from tactex_description.urdf import build_urdf

    targets = [(args.write_urdf, '--write-urdf'), (args.write_mjcf, '--write-mjcf')]
    for path, option in targets:
        if path is not None:
            check_output_file(path, option)
    if args.check_urdf is not None:
        check_input_file(args.check_urdf, '--check-urdf')
        try:
            current = read_text(args.check_urdf, max_bytes=MAX_URDF_BYTES)
        except UnicodeDecodeError:
            raise CommandError(f'--check-urdf {args.check_urdf} is not a text file; give the '
                               'URDF (XML)') from None
    print(f'{"joint":<16}{"type":<11}{"role":<11}{"lower":>9}{"upper":>9}{"velocity":>10}')
    for joint in OPEN_MANIPULATOR_X.joints:
        if joint.kind is not JointKind.FIXED:
            print(f'{joint.name:<16}{joint.kind.value:<11}{joint.role.value:<11}'
                  f'{joint.lower:>9.4f}{joint.upper:>9.4f}{joint.velocity:>10.3f}')
    for (path, _), build in zip(targets, (build_urdf, build_mjcf), strict=True):
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(build(), encoding='utf-8')
            print(f'wrote {path}')
    if args.check_urdf is not None:
        if current != build_urdf():
            raise CommandError(f'--check-urdf {args.check_urdf} is stale; regenerate it with '
                               '`make urdf`')
        print(f'{args.check_urdf} matches the geometry module')
    return 0
