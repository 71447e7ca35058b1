# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex report accuracy-time`: what accuracy costs in time, measured across the system."""

from __future__ import annotations

import argparse
from dataclasses import replace
from pathlib import Path
import time

from tactex.options import check_output_folder, epoch_count, integer, seed_value, staged_folder


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    sub = parser.add_subparsers(dest='report', required=True, metavar='REPORT')
    accuracy = sub.add_parser(
        'accuracy-time', help='contact, compute, probing, sweep, simulation and filter time '
        'against accuracy, and the whole job, measured in one run (report.md + PNGs)')
    accuracy.add_argument('--out', type=Path, required=True, help='report folder (new)')
    accuracy.add_argument('--quick', action='store_true',
                          help='the small size (a few minutes; a test), not the default')
    accuracy.add_argument('--epochs', type=epoch_count,
                          help='epochs of the deep models (default: 3 quick, 15 default; '
                               'cnn_3 needs about 80 to learn the 12 textures)')
    accuracy.add_argument('--seed', type=seed_value, default=0)
    accuracy.add_argument('--threads', type=integer(1, 256), default=1,
                          help='torch threads while training (1)')


def run(args: argparse.Namespace) -> int:
    """Measure and write the report."""
    check_output_folder(args.out)
    from tactex.accuracy_time.runner import write_report
    from tactex.accuracy_time.sizes import DEFAULT, QUICK
    size = QUICK if args.quick else DEFAULT
    if args.epochs is not None:
        size = replace(size, epochs=args.epochs)
    started = time.monotonic()
    with staged_folder(args.out) as folder:
        results = write_report(folder, size, seed=args.seed, threads=args.threads)
    print(f'report: {args.out / "report.md"} ({(time.monotonic() - started) / 60:.1f} min, '
          f'{results["total_s"]:.0f} s measuring)', flush=True)
    return 0
