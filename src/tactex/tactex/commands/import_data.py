# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex import mun|csv`: datasets recorded elsewhere -> the tactex dataset format."""

from __future__ import annotations

import argparse
from pathlib import Path
import sys


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('kind', choices=['mun', 'csv'],
                        help='mun: the public MUN tactile texture pickles; csv: CLASS/*.csv')
    parser.add_argument('root', type=Path, help='folder holding the data')
    parser.add_argument('--out', type=Path, required=True, help='dataset path (.npz)')
    parser.add_argument('--window', type=int, default=1050,
                        help='samples per window (1050: 3 s at 350 Hz)')
    parser.add_argument('--hop', type=int, help='samples between window starts (window/2)')
    parser.add_argument('--rate', type=float, help='csv: sampling rate (Hz)')
    parser.add_argument('--columns', default='',
                        help='csv: CHANNEL=COLUMN pairs, e.g. ax=acc_x,baro=pressure')


def run(args: argparse.Namespace) -> int:
    """Import and save."""
    from tactex_classify.errors import DatasetError
    from tactex_classify.importers import import_csv, import_mun, parse_column_mapping

    hop = args.hop or args.window // 2
    try:
        if args.kind == 'mun':
            dataset = import_mun(args.root, window=args.window, hop=hop)
        else:
            if args.rate is None:
                raise DatasetError('csv needs --rate (the sampling rate in Hz)')
            dataset = import_csv(args.root, rate_hz=args.rate, window=args.window, hop=hop,
                                 columns=parse_column_mapping(args.columns))
    except DatasetError as err:
        print(f'error: {err}', file=sys.stderr)
        return 1
    path = dataset.save(args.out)
    print(f'wrote {path}: {len(dataset.X)} windows, {len(dataset.classes)} classes')
    return 0
