# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex convert`: recordings (rosbag2, ROS 1, MCAP) -> a windowed dataset (.npz + JSON)."""

from __future__ import annotations

import argparse

from tactex.errors import CommandError
from tactex.options import (
    check_output_file,
    hop_samples,
    input_path,
    number,
    output_path,
    refuse_to_replace,
    text,
    trial_id,
    window_samples,
)
from tactex_classify.models.checkpoint import SAMPLING_RATE_RANGE_HZ
from tactex_common.channels import CHANNELS


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('paths', nargs='+', type=input_path, metavar='BAG_OR_DIR',
                        help='recordings (rosbag2 folders, ROS 1 .bag, .mcap or .db3 '
                        'files), or folders holding recordings')
    parser.add_argument('--out', type=output_path, required=True, help='dataset path (.npz)')
    parser.add_argument('--force', action='store_true',
                        help='replace an existing dataset at --out (refused without it)')
    parser.add_argument('--renumber', action='store_true',
                        help='give recordings whose trial id another already has the next '
                             'free ids (reported; refused without it)')
    parser.add_argument('--window', type=window_samples, default=128,
                        help='samples per window (128)')
    parser.add_argument('--hop', type=hop_samples, help='samples between window starts '
                        '(window/2)')
    parser.add_argument('--label', type=text,
                        help='class of the recordings that carry no label (never replaces one)')
    parser.add_argument('--trial', type=trial_id, help='recording id of a single recording')
    parser.add_argument('--all-samples', action='store_true',
                        help='keep every sample, not only "sliding in contact" (needed for '
                             'recordings without sweep/active, joint states or ground truth)')
    parser.add_argument('--resample', type=number(at_most=SAMPLING_RATE_RANGE_HZ[1]),
                        metavar='HZ',
                        help='convert every recording onto this rate: each gap-free run '
                             'interpolated onto a uniform grid at its measured rate, then '
                             'resampled with an anti-aliasing polyphase filter (default: keep '
                             'the measured rate; recordings of different rates are refused)')
    parser.add_argument('--channels', metavar='NAME,...',
                        help=f'the dataset channels, of {",".join(CHANNELS)} (default: '
                             'every channel all recordings have)')
    parser.add_argument('--topic', action='append', default=[], metavar='ROLE=TOPIC',
                        help='read a role from another topic, e.g. imu=/my/imu (roles: imu, '
                             'mag, pressure, active, metadata, joints); repeatable. Without '
                             'it topics are found under any namespace')


def run(args: argparse.Namespace) -> int:
    """Convert and save."""
    from tactex_classify.data.bags import parse_topic_remaps
    from tactex_classify.data.dataset import convert
    from tactex_classify.data.sources import is_recording

    out = check_output_file(args.out, suffix='.npz', companions=('.json',))
    refuse_to_replace(out, force=args.force, companions=('.json',))
    hop = args.hop or max(1, args.window // 2)
    if hop > args.window:
        raise CommandError(f'--hop {hop} is longer than --window {args.window}; use a hop '
                           '<= the window')
    for path in args.paths:
        if not path.exists():
            raise CommandError(f'BAG_OR_DIR {path} does not exist')
        if not (path.is_dir() or is_recording(path)):
            raise CommandError(f'BAG_OR_DIR {path} is no recording; give a rosbag2 folder, a '
                               'ROS 1 .bag, an .mcap or .db3 file, or a folder of recordings')
    channels = None
    if args.channels is not None:
        channels = [c.strip() for c in args.channels.split(',')]
        unknown = [c for c in channels if c not in CHANNELS]
        if unknown or not all(channels):
            raise CommandError(f'--channels {args.channels!r}: unknown channel(s) {unknown}; '
                               f'bags have {",".join(CHANNELS)}')
    dataset = convert(args.paths, window=args.window, hop=hop, label=args.label,
                      trial=args.trial, all_samples=args.all_samples, channels=channels,
                      remaps=parse_topic_remaps(args.topic), renumber=args.renumber,
                      resample_hz=args.resample)
    path = dataset.save(out)
    skipped = len(dataset.info['skipped'])
    print(f'wrote {path}: {dataset.describe()}'
          + (f'; {skipped} skipped (see the sidecar)' if skipped else ''))
    return 0
