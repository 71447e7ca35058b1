# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex train`: cross-validate a model on a dataset, write the report, keep a checkpoint."""

from __future__ import annotations

import argparse
from dataclasses import asdict
from pathlib import Path
import sys
import time

from tactex_classify.catalog import ALL_MODELS, BASELINES


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('data', type=Path, help='dataset (.npz with its .json sidecar)')
    parser.add_argument('--model', default='cnn_1', choices=ALL_MODELS,
                        help='one of the eight models of the original, or a baseline')
    parser.add_argument('--cv', default='both', choices=['grouped', 'stratified', 'both'],
                        help='grouped by recording (honest), stratified windows (the '
                             "original's, leaky), or both side by side (default)")
    parser.add_argument('--folds', type=int, default=5)
    parser.add_argument('--epochs', type=int, default=250)
    parser.add_argument('--early-stopping', type=int, default=0, metavar='PATIENCE',
                        help='stop when the validation loss has not improved for PATIENCE '
                             'epochs (validation: recordings held out of the training fold)')
    parser.add_argument('--scaling', default='minmax', choices=['minmax', 'standard'])
    parser.add_argument('--seed', type=int, default=0)
    parser.add_argument('--threads', type=int, default=1, help='torch threads (1)')
    parser.add_argument('--out', type=Path, required=True, help='run folder')
    parser.add_argument('--no-final', action='store_true',
                        help='skip training the deployable model on all windows')


def run(args: argparse.Namespace) -> int:
    """Cross-validate, report, and save the final model."""
    from tactex_classify.baselines import MiniRocketRidge, StatsExtraTrees
    from tactex_classify.classifier import DeepClassifier, TrainingConfig
    from tactex_classify.dataset import Dataset
    from tactex_classify.errors import ClassifyError
    from tactex_classify.evaluate import cross_validate, SCHEMES
    from tactex_classify.report import write_report

    config = TrainingConfig(model=args.model, epochs=args.epochs,
                            early_stopping=args.early_stopping, scaling=args.scaling,
                            seed=args.seed, threads=args.threads)
    started = time.monotonic()

    def log(line: str) -> None:
        print(f'[{time.monotonic() - started:7.1f} s] {line}', flush=True)

    def epoch_progress(record: dict) -> None:
        if record['epoch'] == 1 or record['epoch'] % 10 == 0 or record['epoch'] == args.epochs:
            extra = (f', val acc {100 * record["val_accuracy"]:.1f} %'
                     if 'val_accuracy' in record else '')
            log(f'  epoch {record["epoch"]}/{args.epochs}: loss {record["train_loss"]:.4f}, '
                f'acc {100 * record["train_accuracy"]:.1f} %{extra}')

    def make():
        if args.model == 'minirocket':
            return MiniRocketRidge(seed=args.seed)
        if args.model == 'extratrees':
            return StatsExtraTrees(seed=args.seed)
        return DeepClassifier(config, progress=epoch_progress)

    try:
        dataset = Dataset.load(args.data)
        schemes = SCHEMES if args.cv == 'both' else (args.cv,)
        results = [cross_validate(dataset, make, scheme, folds=args.folds, seed=args.seed,
                                  progress=log) for scheme in schemes]
        settings = asdict(config) if args.model not in BASELINES else {
            'model': args.model, 'seed': args.seed}
        settings['folds'] = args.folds
        report = write_report(args.out, dataset, results,
                              title=f'{args.model} on {args.data.stem}', settings=settings,
                              data_name=str(args.data))
        if not args.no_final and args.model not in BASELINES:
            log('training the deployable model on every window')
            make().fit(dataset.X, dataset.y, dataset.classes,
                       groups=dataset.trial).save(args.out / 'model')
    except (ClassifyError, ValueError) as err:
        print(f'error: {err}', file=sys.stderr)
        return 1
    log(f'report: {report}')
    return 0
