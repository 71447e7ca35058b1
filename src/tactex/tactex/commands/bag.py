# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex bag info`: what recordings hold, like `ros2 bag info`, for every format tactex reads."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
import sys

from tactex.errors import CommandError


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    sub = parser.add_subparsers(dest='bag', required=True, metavar='ACTION')
    info = sub.add_parser(
        'info', help='storage, span, and per topic: type, count, rate, jitter and gaps',
        description='What recordings hold: rosbag2 folders (sqlite3, MCAP, zstd), ROS 1 '
        'bags, lone .mcap or .db3 files, folders of part bags.')
    info.add_argument('paths', nargs='+', type=Path, metavar='RECORDING',
                      help='recordings (a folder of recordings: each one in it)')
    info.add_argument('--json', action='store_true',
                      help='one JSON document (a list, one object per recording)')
    info.add_argument('--no-timing', action='store_true',
                      help='the summary from the index only (no rates, jitter or gaps; '
                           'instant on long recordings)')


def run(args: argparse.Namespace) -> int:
    """Describe each recording."""
    from tqdm import tqdm

    from tactex_classify.data.bag_info import describe, format_text
    from tactex_classify.data.dataset import recording_paths
    from tactex_classify.errors import BagError

    for path in args.paths:
        if not path.exists():
            raise CommandError(f'RECORDING {path} does not exist')
    recordings = recording_paths(args.paths, progress=lambda line: print(line, file=sys.stderr))
    if not recordings:
        raise CommandError(f'no recordings in {", ".join(map(str, args.paths))}; give rosbag2 '
                           'folders, .bag, .mcap or .db3 files')
    described, failed = [], []
    for path in recordings:
        with tqdm(desc=path.name, unit=' msg', unit_scale=True, leave=False, disable=None,
                  file=sys.stderr) as bar:
            try:
                described.append(describe(path, timing=not args.no_timing,
                                          progress=bar.update))
            except BagError as err:
                failed.append(str(err))
    if args.json:
        print(json.dumps([info.as_json() for info in described], indent=1))
    elif described:
        print('\n\n'.join(format_text(info) for info in described))
    if len(failed) == 1 and len(recordings) == 1:
        raise CommandError(failed[0])
    for message in failed:
        print(f'warning: {message}', file=sys.stderr)
    if failed:
        raise CommandError(f'{len(failed)} of {len(recordings)} recordings cannot be read (the '
                           'warnings above say why)')
    return 0
