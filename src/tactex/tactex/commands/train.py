# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex train`: cross-validate a model on a dataset, write the report, keep a checkpoint.

Every model, the baselines included, leaves a deployable checkpoint in RUN/model/
(`tactex_classify.models.checkpoint`): what `classifier_node` loads and `tactex export` reads.
With `--movements`, one model per movement of the file, each with its calibration and
out-of-fold evidence, in the identification bundle RUN/bundle/.
"""

from __future__ import annotations

import argparse
from dataclasses import asdict
from pathlib import Path
import time

from tactex.errors import CommandError
from tactex.options import (
    check_finite_windows,
    check_output_folder,
    fold_count,
    input_path,
    load_dataset,
    movement_file,
    output_path,
    seed_value,
    staged_folder,
)
from tactex.training_options import add_training_options, resolve_model, training_config
from tactex_classify.models.registry import (
    ALL_MODELS,
    BASELINES,
    DEEP_MODELS,
    SCHEMES,
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    parser.add_argument('data', type=input_path, help='dataset (.npz with its .json sidecar)')
    parser.add_argument('--model', choices=ALL_MODELS,
                        help="a deep model (the original's eight or a modern one) or a "
                             "baseline (default cnn_1; with --init, the checkpoint's)")
    parser.add_argument('--cv', default='both', choices=[*SCHEMES, 'both'],
                        help='grouped by recording (honest), stratified windows (the '
                             "original's, leaky), or both side by side (default)")
    parser.add_argument('--folds', type=fold_count, default=5, help='folds per scheme (5)')
    add_training_options(parser, init=True)
    parser.add_argument('--seed', type=seed_value, default=0)
    parser.add_argument('--out', type=output_path, required=True, help='run folder')
    parser.add_argument('--no-final', action='store_true',
                        help='skip training the deployable model (RUN/model/) on all windows')
    parser.add_argument('--movements', type=input_path, metavar='YAML',
                        help='train one model per movement of this file (recordings from '
                             '`tactex sim collect --movements`), each calibrated on grouped '
                             'out-of-fold sweeps (--folds), into the identification bundle '
                             'RUN/bundle/ (default model: minirocket)')
    parser.add_argument('--repeat-discount', action='store_true',
                        help="with --movements: fit a discount of a movement's repeats with "
                             'the tempering (default: every sweep counts fully)')


def run(args: argparse.Namespace) -> int:
    """Cross-validate, report, and save the final model."""
    check_output_folder(args.out)
    dataset = load_dataset(args.data, 'DATA')
    check_finite_windows(dataset, args.data)
    if args.movements:
        return _train_bundle(args, dataset)
    schemes = SCHEMES if args.cv == 'both' else (args.cv,)
    check_folds(dataset, schemes, args.folds)
    stream = None if args.no_final else deployable_stream(dataset)

    from tactex_classify.errors import ClassifyError
    from tactex_classify.evaluation.cross_validation import cross_validate
    from tactex_classify.evaluation.training_report import (
        console_summary,
        convergence_notes,
        write_report,
    )
    from tactex_classify.training.estimators import build_estimator

    args.model = resolve_model(args, dataset, default='cnn_1')
    check_model_window(args.model, dataset)
    config = training_config(args, args.model)
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
        return build_estimator(config, progress=epoch_progress)

    if args.init:
        log(f'fine-tuning: every fit starts from the weights of {args.init} '
            '(the scaler is fitted on the new training windows)')

    try:
        with staged_folder(args.out) as folder:
            results = [cross_validate(dataset, make, scheme, folds=args.folds, seed=args.seed,
                                      progress=log) for scheme in schemes]
            for result in results:
                result.notes += convergence_notes(result, len(dataset.classes), config.epochs)
            for note in (n for result in results for n in result.notes):
                log(f'note: {note}')
            for line in console_summary(dataset, results):
                log(line)
            settings = asdict(config) if args.model not in BASELINES else {
                'model': args.model, 'seed': args.seed}
            settings['folds'] = args.folds
            write_report(folder, dataset, results, title=f'{args.model} on {args.data.stem}',
                         settings=settings, data_name=str(args.data))
            if stream is not None:
                log('training the deployable model on every window')
                make().fit(dataset.X, dataset.y, dataset.classes, groups=dataset.trial,
                           channels=dataset.channels).save(folder / 'model', **stream,
                                                           trained_on=dataset.digest())
    except ValueError as err:
        raise ClassifyError(str(err)) from None
    log(f'report: {args.out / "report.md"}')
    return 0


def check_model_window(model: str, dataset) -> None:
    """Refuse a deep model that needs longer windows than the dataset's, before training.

    Raises:
        WindowError: naming --model, both lengths and the ways out.
    """
    if model in DEEP_MODELS:
        from tactex_classify.models import architectures
        architectures.check_window(model, dataset.X.shape[1])


def deployable_stream(dataset, without: str = ', or pass --no-final') -> dict:
    """The hop and sampling rate a checkpoint keeps, from the dataset's sidecar.

    `without` ends the error with the way to train without a deployable model, if any.

    Raises:
        CommandError: the sidecar lacks them (or they are not usable).
    """
    from tactex_common.numbers import is_finite_number
    hop, rate = dataset.info.get('hop'), dataset.info.get('sampling_rate_hz')
    if not isinstance(hop, int) or isinstance(hop, bool) or not 1 <= hop <= dataset.X.shape[1] \
            or not is_finite_number(rate) or rate <= 0:
        raise CommandError(f"DATA's sidecar gives hop {hop!r} and sampling_rate_hz {rate!r}; "
                           'a deployable model needs both (convert the recordings again)'
                           f'{without}')
    return {'hop': hop, 'sampling_rate_hz': float(rate)}


def check_movement_window(movements, dataset, movements_path: Path, data_path: Path) -> None:
    """Refuse a movement file whose window is not the dataset's (the bundle keeps both).

    Raises:
        CommandError: naming both files, both windows and the fix.
    """
    if movements.window != dataset.X.shape[1]:
        raise CommandError(f'--movements {movements_path} gives window {movements.window}, '
                           f'DATA {data_path} holds {dataset.X.shape[1]}-sample windows: '
                           "convert at the file's window, or give the dataset's in the file")


def check_folds(dataset, schemes, folds: int) -> None:
    """Refuse a dataset that cannot give honest folds, before any training.

    Raises:
        CommandError: fewer than two classes, or fewer recordings / windows than folds.
    """
    from collections import Counter

    import numpy as np
    counts = Counter(dataset.classes[i] for i in dataset.y.tolist())
    if len(counts) < 2:
        raise CommandError(f'DATA has {len(counts)} class(es) ({", ".join(counts)}): a '
                           'classifier needs at least two; convert recordings of more textures')
    recordings = len(np.unique(dataset.trial))
    if 'grouped' in schemes and recordings < folds:
        raise CommandError(f'--folds {folds} needs at least {folds} recordings for grouped '
                           f'cross-validation; DATA has {recordings}: lower --folds')
    if len(dataset.y) < folds:
        raise CommandError(f'--folds {folds} needs at least {folds} windows; DATA has '
                           f'{len(dataset.y)}')


def _train_bundle(args: argparse.Namespace, dataset) -> int:
    """One calibrated model per movement and the tempering exponent, as RUN/bundle/."""
    from tactex_classify.identification.bundle import save_bundle
    from tactex_classify.identification.calibration import reliability
    from tactex_classify.identification.movement_evidence import (
        cell_counts,
        check_cells,
        checked_movements,
        DEFAULT_MODEL,
        fit_movement,
        movement_evidence,
        MovementDataError,
        subset,
        trial_labels,
    )
    from tactex_classify.identification.tempering import DISCOUNTS, fit_tempering
    from tactex_classify.training.convergence import WHAT_TO_CHANGE
    from tactex_classify.training.estimators import build_estimator

    ignored = [option for option, given in (('--no-final', args.no_final),
                                            ('--cv', args.cv != 'both')) if given]
    if ignored:
        raise CommandError(f'{" and ".join(ignored)} do(es) not apply with --movements: a '
                           'bundle always keeps its final models and cross-validates grouped '
                           'by recording; leave them out')
    stream = deployable_stream(dataset, without='')
    movements = movement_file(args.movements, dataset.info.get('sampling_rate_hz'))
    fitted = []
    try:  # the data first, as tactex report identification checks it; then the model
        movement_of = checked_movements(dataset, movements)
        check_movement_window(movements, dataset, args.movements, args.data)
        counts = cell_counts(dataset.classes, trial_labels(dataset), movement_of, movements)
        fewest = min(counts.values())
        check_cells(counts, args.folds, f'--folds {args.folds}',
                    f'give --folds {fewest}, or record more sweeps' if fewest >= 2 else
                    'record at least 2 sweeps of each (with --folds 2)')
        model = resolve_model(args, dataset, default=DEFAULT_MODEL)
        check_model_window(model, dataset)
        config = training_config(args, model)
        for movement in movements.movements:
            fit = fit_movement(movement.name, subset(dataset, [
                trial for trial, name in movement_of.items() if name == movement.name]),
                lambda: build_estimator(config), folds=args.folds, seed=args.seed)
            print(f'{movement.name}: {100 * (fit.vectors.argmax(1) == fit.labels).mean():.1f} % '
                  f'of {len(fit.labels)} sweeps right out of fold, temperature '
                  f'{fit.temperature:.2f}, calibration error '
                  f'{reliability(fit.vectors, fit.labels).error:.3f}', flush=True)
            for where, why in fit.unconverged:
                print(f'note: {movement.name}: {where} not converged ({why}): '
                      f'{WHAT_TO_CHANGE[why]}', flush=True)
            fitted.append(fit)
        tempering = fit_tempering(dataset.classes, [movement_evidence(
            fit, movements.by_name(fit.name).contact_s) for fit in fitted], seed=args.seed,
            discounts=DISCOUNTS if args.repeat_discount else (0.0,))
    except MovementDataError as err:
        raise CommandError(f'DATA {args.data}: {err}') from None
    with staged_folder(args.out) as folder:
        save_bundle(folder / 'bundle', fitted, movements, tempering, **stream)
    print(f'bundle: {args.out / "bundle"} ({model} per movement, tempering '
          f'{tempering.exponent:.2f}, repeat discount {tempering.repeat_discount:g})')
    return 0
