# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex convert`: recordings (rosbag2) -> a windowed dataset (.npz + JSON), no ROS needed."""

from __future__ import annotations

import argparse
from pathlib import Path
import sys


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('paths', nargs='+', type=Path, metavar='BAG_OR_DIR',
                        help='recordings, or folders holding recordings')
    parser.add_argument('--out', type=Path, required=True, help='dataset path (.npz)')
    parser.add_argument('--window', type=int, default=128, help='samples per window (128)')
    parser.add_argument('--hop', type=int, help='samples between window starts (window/2)')
    parser.add_argument('--label', help='class of recordings that carry none')
    parser.add_argument('--trial', type=int, help='recording id of a single recording')
    parser.add_argument('--all-samples', action='store_true',
                        help='keep every sample, not only "moving and in contact"')


def run(args: argparse.Namespace) -> int:
    """Convert and save."""
    from tactex_classify.dataset import convert
    from tactex_classify.errors import DatasetError

    try:
        dataset = convert(args.paths, window=args.window, hop=args.hop or args.window // 2,
                          label=args.label, trial=args.trial, all_samples=args.all_samples)
    except DatasetError as err:
        print(f'error: {err}', file=sys.stderr)
        return 1
    path = dataset.save(args.out)
    skipped = len(dataset.info['skipped'])
    print(f'wrote {path}: {len(dataset.X)} windows of {args.window} samples, '
          f'{len(dataset.classes)} classes, {len(set(dataset.trial.tolist()))} recordings'
          + (f'; {skipped} skipped (see the sidecar)' if skipped else ''))
    return 0
