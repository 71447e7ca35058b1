# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The deep-model training options `tactex train` and `tactex report identification` share.

One set of flags and defaults, so that a per-movement model the report measured is the
model `tactex train --movements` bundles when given the same flags.
"""

from __future__ import annotations

import argparse

from tactex.options import epoch_count, integer, patience_epochs
from tactex_classify.models.registry import PROFILE_NAMES
from tactex_classify.models.windows import SCALINGS

SCALING_HELP = ("per-channel Min-Max (default), z-score, or window: each window's mean "
                'removed, then z-scaled')


def add_training_options(parser: argparse.ArgumentParser, *, scaling_help: str = SCALING_HELP,
                         threads_help: str = 'torch threads (1)') -> None:
    """Register --epochs, --profile, --early-stopping, --scaling and --threads."""
    parser.add_argument('--epochs', type=epoch_count, default=250,
                        help='epochs at most (250)')
    parser.add_argument('--profile', default='original', choices=PROFILE_NAMES,
                        help="deep models: the original's training (default), or modern: "
                             'AdamW, warm-up + cosine, label smoothing, weight EMA, '
                             'augmentation with mixup, early stopping (docs/guides/training.md, '
                             'Training profiles)')
    parser.add_argument('--early-stopping', type=patience_epochs, default=None,
                        metavar='PATIENCE',
                        help='stop when the validation loss has not improved for PATIENCE '
                             'epochs, counted once the training loss leaves chance '
                             '(validation: recordings held out of the training fold; '
                             "0: off; default: the profile's, off or 30)")
    parser.add_argument('--scaling', default=None, choices=SCALINGS, help=scaling_help)
    parser.add_argument('--threads', type=integer(1, 256), default=1, help=threads_help)


def training_config(args: argparse.Namespace, model: str, **settings):
    """The `TrainingConfig` of these options for `model` (a baseline takes only the seed)."""
    from tactex_classify.training.deep_classifier import TrainingConfig
    if args.early_stopping is not None:
        settings['early_stopping'] = args.early_stopping
    return TrainingConfig.for_profile(
        args.profile, model=model, epochs=args.epochs, scaling=args.scaling or 'minmax',
        seed=args.seed, threads=args.threads, **settings)
