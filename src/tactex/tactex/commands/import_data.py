# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex import mun|csv`: datasets recorded elsewhere -> the tactex dataset format."""

from __future__ import annotations

import argparse

from tactex.errors import CommandError
from tactex.options import (
    check_input_folder,
    check_output_file,
    hop_samples,
    input_path,
    number,
    output_path,
    refuse_to_replace,
    text,
    window_samples,
)
from tactex_classify.models.checkpoint import SAMPLING_RATE_RANGE_HZ

DELIMITER_NAMES = {'tab': '\t', '\\t': '\t', 'comma': ',', 'semicolon': ';', 'pipe': '|'}


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('kind', choices=['mun', 'csv'],
                        help='mun: the public MUN tactile texture pickles; csv: CLASS/*.csv')
    parser.add_argument('root', type=input_path, help='folder holding the data')
    parser.add_argument('--out', type=output_path, required=True, help='dataset path (.npz)')
    parser.add_argument('--force', action='store_true',
                        help='replace an existing dataset at --out (refused without it)')
    parser.add_argument('--window', type=window_samples, default=1050,
                        help='samples per window (1050: 3 s at 350 Hz)')
    parser.add_argument('--hop', type=hop_samples, help='samples between window starts '
                        '(window/2)')
    parser.add_argument('--rate', type=number(at_least=SAMPLING_RATE_RANGE_HZ[0],
                                              at_most=SAMPLING_RATE_RANGE_HZ[1]),
                        help='csv: sampling rate (Hz), unless --time '
                        'gives it')
    parser.add_argument('--time', type=text, metavar='COLUMN',
                        help='csv: column of timestamps; gives the rate and the gaps')
    parser.add_argument('--time-unit', choices=['s', 'ms', 'us', 'ns'], default='s',
                        help='csv: unit of a numeric --time column (s)')
    parser.add_argument('--resample', type=number(at_least=SAMPLING_RATE_RANGE_HZ[0],
                                                  at_most=SAMPLING_RATE_RANGE_HZ[1]),
                        metavar='HZ',
                        help='csv: put every file onto this rate, as tactex convert --resample '
                             'does (default: keep the measured rate; files more than 2 %% '
                             'apart are refused)')
    parser.add_argument('--columns', type=text, metavar='NAME[=COLUMN],...',
                        help="csv: the dataset's channels in order; NAME alone reads the "
                             'column NAME, NAME=COLUMN renames (e.g. ax=acc_x,ay=acc_y,'
                             'az=acc_z, or pdc,pac1,ele3). Default: ax,ay,az,gx,gy,gz,mx,my,'
                             'mz,baro')
    parser.add_argument('--delimiter', metavar='CHAR',
                        help='csv: the delimiter (one character, or tab, comma, semicolon, '
                             'pipe); sniffed from the header by default')


def run(args: argparse.Namespace) -> int:
    """Import and save."""
    from tactex_classify.data.importers import import_csv, import_mun, parse_channel_specs

    out = check_output_file(args.out, suffix='.npz', companions=('.json',))
    refuse_to_replace(out, force=args.force, companions=('.json',))
    check_input_folder(args.root, 'ROOT')
    hop = args.hop or max(1, args.window // 2)
    if hop > args.window:
        raise CommandError(f'--hop {hop} is longer than --window {args.window}; use a hop '
                           '<= the window')
    if args.kind == 'mun':
        csv_only = [f'--{n}' for n in ('rate', 'time', 'columns', 'delimiter', 'resample')
                    if getattr(args, n) is not None]
        if csv_only:
            raise CommandError(f'{", ".join(csv_only)} apply to csv only; leave them out for mun')
        dataset = import_mun(args.root, window=args.window, hop=hop)
    else:
        if args.rate is None and args.time is None:
            raise CommandError('csv needs --rate HZ (the sampling rate) or --time COLUMN (a '
                               'timestamp column)')
        delimiter = args.delimiter
        if delimiter is not None:
            delimiter = DELIMITER_NAMES.get(delimiter.lower(), delimiter)
            if len(delimiter) != 1:
                raise CommandError(f'--delimiter {args.delimiter!r}: give one character or '
                                   f'one of {", ".join(DELIMITER_NAMES)}')
        columns = parse_channel_specs(args.columns) if args.columns else None
        dataset = import_csv(args.root, window=args.window, hop=hop, columns=columns,
                             rate_hz=args.rate, time_column=args.time,
                             time_unit=args.time_unit, delimiter=delimiter,
                             resample_hz=args.resample)
    path = dataset.save(out)
    print(f'wrote {path}: {dataset.describe()}')
    return 0
