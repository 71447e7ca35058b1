# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex report`: what accuracy costs in time, and identification replayed offline.

`accuracy-time` measures it across the system; `identification` replays the choice of
each next movement on held-out recordings of every texture under every movement.
"""

from __future__ import annotations

import argparse
from dataclasses import replace
import time

from tactex.errors import CommandError
from tactex.options import (
    check_finite_windows,
    check_input_file,
    check_output_folder,
    epoch_count,
    fold_count,
    input_path,
    integer,
    load_dataset,
    movement_file,
    MOVEMENTS_HINT,
    number,
    output_path,
    seed_value,
    staged_folder,
)
from tactex.training_options import add_training_options, resolve_model, training_config
from tactex_classify.identification.selection import COMPARED, POLICIES  # numpy only


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    sub = parser.add_subparsers(dest='report', required=True, metavar='REPORT')
    accuracy = sub.add_parser(
        'accuracy-time', help='contact, compute, probing, sweep, simulation and filter time '
        'against accuracy, and the whole job, measured in one run (report.md + PNGs)')
    accuracy.add_argument('--out', type=output_path, required=True, help='report folder (new)')
    accuracy.add_argument('--quick', action='store_true',
                          help='the small size (a few minutes; a test), not the default')
    accuracy.add_argument('--epochs', type=epoch_count,
                          help='epochs of the deep models (default: 3 quick, 15 default; '
                               'cnn_3 needs about 80 to learn the 12 textures)')
    accuracy.add_argument('--seed', type=seed_value, default=0)
    accuracy.add_argument('--threads', type=integer(1, 256), default=1,
                          help='torch threads while training (1)')
    identification = sub.add_parser(
        'identification', help='replay active identification and the comparison policies on '
        'held-out recordings of every texture under every movement (identification.md + PNGs)')
    identification.add_argument('data', type=input_path,
                                help='dataset converted from `tactex sim collect --movements` '
                                     '(.npz with its sidecar)')
    identification.add_argument('--out', type=output_path, required=True,
                                help='report folder (new)')
    identification.add_argument('--movements', type=input_path, metavar='YAML',
                                help='the movement file the recordings were made with '
                                     '(default config/movements.yaml)')
    identification.add_argument('--policies', type=_policies, default=COMPARED,
                                metavar='P[,P...]', help='comma-separated, of '
                                f'{", ".join(POLICIES)} (default {",".join(COMPARED)})')
    identification.add_argument('--threshold', type=number(at_most=1.0), default=0.99,
                                help="stop when the leading texture's posterior exceeds this "
                                     "(default 0.99, the live node's)")
    identification.add_argument('--budget-movements', type=integer(1, 1000),
                                help='at most this many movements per identification')
    identification.add_argument('--budget-seconds', type=number(), metavar='S',
                                help='at most this many contact seconds per identification')
    identification.add_argument('--seeds', type=integer(1, 1000), default=10,
                                help='episodes per (fold, texture), each with its own draw of '
                                     'the held-out sweeps (10)')
    identification.add_argument('--folds', type=fold_count, default=3,
                                help='folds grouped by recording (3)')
    identification.add_argument('--repeats', type=integer(1, 100), default=1,
                                help='partitions into folds, each dealt from its own shuffle '
                                     'and replayed (repeated cross-validation; default 1): '
                                     'with few recordings per texture and movement, which '
                                     'share a fold moves the figures by several points')
    identification.add_argument('--inner-folds', type=fold_count, default=3,
                                help='folds within the training recordings for the evidence '
                                     'and its calibration (3)')
    identification.add_argument('--model', help="the per-movement model (default minirocket; "
                                                 "with --init, the checkpoint's)")
    add_training_options(identification, init=True)  # a deep model trains as in tactex train
    identification.add_argument('--seed', type=seed_value, default=0)
    identification.add_argument('--repeat-discount', action='store_true',
                                help="fit a discount of a movement's repeats with the "
                                     'tempering (default: every sweep counts fully)')


def _policies(text: str) -> tuple[str, ...]:
    names = tuple(name.strip() for name in text.split(','))
    unknown = [name for name in names if name not in POLICIES]
    if unknown or len(set(names)) != len(names):
        raise argparse.ArgumentTypeError(f'must be distinct names of {", ".join(POLICIES)}'
                                         f' separated by commas, got {text!r}')
    return names


def run(args: argparse.Namespace) -> int:
    """Measure and write the report."""
    check_output_folder(args.out)
    if args.report == 'identification':
        return _identification(args)
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


def _identification(args: argparse.Namespace) -> int:
    """Replay identification on held-out recordings and write the report."""
    from tactex.commands.train import check_model_window, check_movement_window
    from tactex_classify.identification.movement_evidence import (
        checked_movements,
        DEFAULT_MODEL,
        MovementDataError,
    )
    from tactex_classify.identification.offline import replay, ReplaySettings
    from tactex_classify.identification.report import write_report
    from tactex_classify.identification.selection import Budget, check_threshold
    from tactex_classify.models.registry import ALL_MODELS
    from tactex_common.share import share_directory

    if args.model is not None and args.model not in ALL_MODELS:
        raise CommandError(f'--model: unknown model {args.model!r}; known: '
                           f'{", ".join(ALL_MODELS)}')
    path = args.movements or share_directory('tactex') / 'config' / 'movements.yaml'
    check_input_file(path, '--movements', hint=MOVEMENTS_HINT)  # before the slower dataset
    dataset = load_dataset(args.data, 'DATA')
    check_finite_windows(dataset, args.data)
    try:
        check_threshold(args.threshold, len(dataset.classes))
    except ValueError as err:
        raise CommandError(f'DATA {args.data}: --{err}') from None
    movements = movement_file(path, dataset.info.get('sampling_rate_hz'))
    shortest = min(movement.contact_s for movement in movements.movements)
    if args.budget_seconds is not None and args.budget_seconds < shortest:
        raise CommandError(f'--budget-seconds {args.budget_seconds:g} is shorter than every '
                           f'movement: the shortest contact lasts {shortest:.2f} s; give at '
                           'least that')
    try:  # the recordings' movements first: a dataset without them needs collecting again
        checked_movements(dataset, movements)
    except MovementDataError as err:
        raise CommandError(f'DATA {args.data}: {err}') from None
    check_movement_window(movements, dataset, path, args.data)
    model = resolve_model(args, dataset, default=DEFAULT_MODEL)
    check_model_window(model, dataset)
    settings = ReplaySettings(
        policies=args.policies, folds=args.folds, inner_folds=args.inner_folds,
        seeds=args.seeds, training=training_config(args, model), seed=args.seed,
        repeat_discount=args.repeat_discount, repeats=args.repeats,
        budget=Budget(args.threshold, args.budget_movements, args.budget_seconds))
    started = time.monotonic()
    try:
        with staged_folder(args.out) as folder:
            table = write_report(folder, replay(dataset, movements, settings), settings)
    except MovementDataError as err:
        raise CommandError(f'DATA {args.data}: {err}') from None
    for policy, row in table['policies'].items():
        print(f'{policy:12s} {100 * row["accuracy"]:5.1f} % right, median '
              f'{row["median_contact_s"]:.1f} s of contact, {row["median_movements"]:.0f} '
              f'movement{"" if row["median_movements"] == 1 else "s"}')
    print(f'report: {args.out / "identification.md"} '
          f'({(time.monotonic() - started) / 60:.1f} min)', flush=True)
    return 0
