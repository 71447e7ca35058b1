# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The deep-model training options `tactex train` and `tactex report identification` share.

One set of flags and defaults, so that a per-movement model the report measured is the
model `tactex train --movements` bundles when given the same flags.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from tactex.errors import CommandError
from tactex.options import check_input_folder, epoch_count, input_path, integer, patience_epochs
from tactex_classify.models.registry import BASELINES, PROFILE_NAMES
from tactex_classify.models.windows import SCALINGS

INIT_HELP = ('fine-tune: start a deep model from the weights of a checkpoint (e.g. trained on '
             'simulated sweeps) with the same model, window and channels; new classes get a '
             'fresh output layer')
DEFAULT_EPOCHS, DEFAULT_PROFILE = 250, 'original'
SCALING_HELP = ("per-channel Min-Max (default), z-score, or window: each window's mean "
                'removed, then z-scaled')


def add_training_options(parser: argparse.ArgumentParser, *, init: bool = False,
                         threads_help: str = 'torch threads (1)') -> None:
    """Register --epochs, --profile, --early-stopping, --scaling, --threads (and --init)."""
    if init:
        parser.add_argument('--init', type=input_path, metavar='CHECKPOINT', help=INIT_HELP)
    scaling_help = SCALING_HELP.replace('(default)', "(default; with --init, the checkpoint's)"
                                        ) if init else SCALING_HELP
    parser.add_argument('--epochs', type=epoch_count, default=DEFAULT_EPOCHS,
                        help=f'epochs at most ({DEFAULT_EPOCHS})')
    parser.add_argument('--profile', default=DEFAULT_PROFILE, choices=PROFILE_NAMES,
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


def resolve_model(args: argparse.Namespace, dataset, default: str) -> str:
    """--model, else the --init checkpoint's, else `default`; sets args.scaling's default.

    A checkpoint is checked against the dataset first (`pretrained_model`); its scaling
    becomes --scaling's default (args.scaling is set), and another --scaling is noted. A
    baseline given deep-model options is told that it trains without them.

    Raises:
        CommandError: the checkpoint refused (see `pretrained_model`).
    """
    init = getattr(args, 'init', None)
    if not init:
        model = args.model or default
        ignored = deep_only_options(args)
        if model in BASELINES and ignored:
            print(f'note: {", ".join(ignored)}: {model} is a baseline, which trains without '
                  'them (they apply to deep models); leave them out')
        return model
    model, scaling = pretrained_model(init, args.model, dataset)
    if scaling and args.scaling not in (None, scaling):
        print(f'note: --scaling {args.scaling}: {init} was trained on {scaling}-scaled '
              'windows, so its weights start from inputs of another range')
    args.scaling = args.scaling or scaling
    return model


def deep_only_options(args: argparse.Namespace) -> list[str]:
    """The deep-model options given other than their defaults, as on the command line."""
    given = [('--epochs', args.epochs, DEFAULT_EPOCHS), ('--profile', args.profile,
                                                          DEFAULT_PROFILE),
             ('--early-stopping', args.early_stopping, None), ('--scaling', args.scaling, None)]
    return [f'{option} {value}' for option, value, default in given if value != default]


def training_config(args: argparse.Namespace, model: str):
    """The `TrainingConfig` of these options for `model` (a baseline takes only the seed)."""
    from tactex_classify.training.deep_classifier import TrainingConfig
    patience = {} if args.early_stopping is None else {'early_stopping': args.early_stopping}
    return TrainingConfig.for_profile(
        args.profile, model=model, epochs=args.epochs, scaling=args.scaling or 'minmax',
        seed=args.seed, threads=args.threads,
        pretrained=str(getattr(args, 'init', None) or ''), **patience)


def pretrained_model(checkpoint: Path, model: str | None, dataset) -> tuple[str, str | None]:
    """The deep model a fine-tuning starts from (`--model` must agree) and its scaling.

    Checked before any training: the checkpoint's window, channels and rate (within 5 %)
    must be the dataset's.

    Raises:
        CommandError: the checkpoint is missing or refused, holds a baseline, another model,
            or another window, channels or rate than the dataset's.
    """
    from tactex_classify.errors import CheckpointError
    from tactex_classify.models.checkpoint import read_checkpoint
    check_input_folder(checkpoint, '--init',
                       hint='give a checkpoint folder that `tactex train` wrote (RUN/model)')
    try:
        info = read_checkpoint(checkpoint)
    except CheckpointError as err:
        raise CommandError(f'--init: {err}') from None
    if info.kind != 'deep':
        raise CommandError(f'--init: {checkpoint} holds the baseline {info.model}; only a deep '
                           'model can be fine-tuned (train the baseline on the new data alone)')
    if model is not None and model != info.model:
        raise CommandError(f'--init: {checkpoint} holds {info.model}, not --model {model}; '
                           "leave --model out to fine-tune the checkpoint's model")
    window = dataset.X.shape[1]
    if info.stream.window != window:
        raise CommandError(f'--init {checkpoint} was trained on {info.stream.window}-sample '
                           f"windows, DATA's are {window}: convert with --window "
                           f'{info.stream.window}, or start from a checkpoint of window {window}')
    if info.stream.channels != tuple(dataset.channels):
        raise CommandError(f'--init {checkpoint} was trained on channels '
                           f'{", ".join(info.stream.channels)}, DATA has '
                           f'{", ".join(dataset.channels)}: start from a checkpoint of the '
                           "dataset's channels")
    rate = dataset.info.get('sampling_rate_hz')
    if rate is not None and info.stream.mismatches(sampling_rate_hz=rate):
        raise CommandError(f'--init {checkpoint} was trained at '
                           f'{info.stream.sampling_rate_hz:g} Hz, DATA is at {rate:.4g} Hz: '
                           'convert (or import) DATA with --resample '
                           f'{info.stream.sampling_rate_hz:g}, or start from a checkpoint of '
                           f'{rate:.4g} Hz')
    return info.model, info.scaling
