# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex predict`: a checkpoint applied to recordings or datasets, as classifier_node would."""

from __future__ import annotations

import argparse
import sys

from tactex.errors import CommandError
from tactex.options import (
    check_input_folder,
    check_output_folder,
    input_path,
    integer,
    number,
    output_path,
    staged_folder,
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Register the options of this subcommand."""
    from tactex_classify.online.evidence import EvidenceSettings
    from tactex_classify.online.live import CONTACT_SOURCES
    from tactex_classify.online.runtime import RUNTIMES
    defaults = EvidenceSettings()
    parser.add_argument('checkpoint', type=input_path, metavar='CHECKPOINT',
                        help='checkpoint folder (RUN/model/ of `tactex train`): torch, '
                             'MiniRocket, ExtraTrees, or ONNX with --runtime onnxruntime')
    parser.add_argument('inputs', nargs='+', type=input_path, metavar='RECORDING_OR_DATASET',
                        help='recordings (any format `tactex bag info` reads; a folder: each '
                             'recording in it) or datasets (.npz with its sidecar)')
    parser.add_argument('--out', type=output_path, help='folder for recordings.csv, windows.csv, '
                        'summary.json and confusion.png (new; without it only printed)')
    parser.add_argument('--runtime', choices=RUNTIMES, default='native',
                        help='what runs the model (native: torch, numpy or scikit-learn)')
    parser.add_argument('--threshold', type=number(at_least=0.0, at_most=1.0),
                        default=defaults.threshold,
                        help=f'decide above this posterior probability ({defaults.threshold})')
    parser.add_argument('--min-windows', type=integer(1, 10_000), default=defaults.min_windows,
                        help=f'windows before a decision ({defaults.min_windows})')
    parser.add_argument('--change-nats', type=number(), default=defaults.change_nats,
                        help=f'CUSUM threshold of a texture change ({defaults.change_nats})')
    parser.add_argument('--contact', choices=CONTACT_SOURCES, default='auto',
                        help='what keeps samples, as classifier_node (auto)')
    parser.add_argument('--hop', type=integer(0, 100_000), default=0,
                        help="samples between windows (0: the checkpoint's)")
    parser.add_argument('--topic', action='append', default=[], metavar='ROLE=TOPIC',
                        help='read a role from another topic, e.g. imu=/my/imu; repeatable')


def run(args: argparse.Namespace) -> int:
    """Replay every input; print and (with --out) write what the classifier said."""
    from tqdm import tqdm

    from tactex_classify.data.bags import parse_topic_remaps
    from tactex_classify.data.dataset import Dataset, recording_paths
    from tactex_classify.errors import ClassifyError
    from tactex_classify.online.evidence import EvidenceSettings
    from tactex_classify.online.live import LiveSettings, LiveWindows
    from tactex_classify.online.replay import replay_dataset, replay_recording
    from tactex_classify.online.runtime import load_predictor

    check_input_folder(args.checkpoint, 'CHECKPOINT')
    if args.out is not None:
        check_output_folder(args.out)
    for path in args.inputs:
        if not path.exists():
            raise CommandError(f'RECORDING_OR_DATASET {path} does not exist')
        if path.suffix.lower() == '.csv':
            raise CommandError(f'RECORDING_OR_DATASET {path} is a CSV table: make its folder '
                               'of CLASS/*.csv a dataset with `tactex import csv`, which '
                               'predict then reads')
    remaps = parse_topic_remaps(args.topic)
    predictor = load_predictor(args.checkpoint, args.runtime)
    info = predictor.info
    evidence = EvidenceSettings(args.threshold, args.min_windows, args.change_nats)
    if args.hop > info.stream.window:
        raise CommandError(f"--hop {args.hop} is longer than the checkpoint's window "
                           f'{info.stream.window}: give at most {info.stream.window} (0: the '
                           f"checkpoint's {info.stream.hop})")
    try:
        live = LiveSettings(hop=args.hop, contact=args.contact)
    except ValueError as err:
        raise CommandError(str(err)) from None
    datasets = [p for p in args.inputs if p.suffix == '.npz']
    recordings = recording_paths([p for p in args.inputs if p.suffix != '.npz'],
                                 progress=lambda line: print(line, file=sys.stderr))
    if not datasets and not recordings:
        tables = [p for p in args.inputs if p.is_dir() and any(p.rglob('*.csv'))]
        raise CommandError('no recordings or datasets in '
                           f'{", ".join(map(str, args.inputs))}'
                           + ('; CSV tables become a dataset with `tactex import csv`, '
                              'which predict then reads' if tables else ''))
    if recordings:
        try:
            LiveWindows(info.stream, live)
        except ValueError as err:
            raise CommandError(f'CHECKPOINT {args.checkpoint}: {err}; recordings cannot feed '
                               'it: apply it to a dataset with these channels') from None
    if args.hop and datasets:
        print("warning: --hop applies to recordings; a dataset's windows are cut already",
              file=sys.stderr)
    results, failed, in_sample = [], [], []
    for path in datasets:
        dataset = Dataset.load(path)
        if dataset.X.shape[1] != info.stream.window:
            raise CommandError(f'RECORDING_OR_DATASET {path} holds {dataset.X.shape[1]}-sample '
                               f'windows, CHECKPOINT {args.checkpoint} takes '
                               f'{info.stream.window}: convert the recordings with --window '
                               f'{info.stream.window}, or give a checkpoint trained on '
                               f'{dataset.X.shape[1]}-sample windows')
        if info.trained_on and dataset.digest() == info.trained_on:
            in_sample.append(str(path))
            print(f'warning: {path} is the dataset {args.checkpoint} was trained on: its '
                  'accuracy here is in-sample, not what the model does on new recordings '
                  '(tactex train cross-validated it grouped by recording)', file=sys.stderr)
        results += replay_dataset(predictor, dataset, str(path), evidence)
    for path in recordings:
        with tqdm(desc=path.name, unit=' IMU samples', unit_scale=True, leave=False,
                  disable=None, file=sys.stderr) as bar:
            try:
                results.append(replay_recording(predictor, path, live=live, evidence=evidence,
                                                remaps=remaps, progress=bar.update))
            except ClassifyError as err:
                failed.append(str(err))
    if failed and len(failed) == len(recordings) and not datasets:
        raise CommandError(failed[0] if len(failed) == 1 else
                           f'none of {len(failed)} recordings could be classified: {failed[0]}')
    for message in failed:
        print(f'warning: skipped {message}', file=sys.stderr)
    _print(results, info)
    if args.out is not None:
        from tactex_classify.evaluation.prediction_report import write_report
        settings = {'checkpoint': str(args.checkpoint), 'model_id': info.model_id,
                    'runtime': predictor.runtime, 'threshold': args.threshold,
                    'min_windows': args.min_windows, 'change_nats': args.change_nats,
                    'contact': args.contact, 'hop': args.hop or info.stream.hop,
                    'skipped': failed, 'trained_on_these': in_sample}
        with staged_folder(args.out) as folder:
            write_report(folder, results, list(info.classes), settings)
        print(f'wrote {args.out}/ (recordings.csv, windows.csv, summary.json'
              + (', confusion.png' if any(r.label for r in results) else '') + ')')
    return 0


def _print(results, info) -> None:
    """One line per recording, then the accuracy grouped by recording when labelled."""
    from tactex_classify.evaluation.prediction_report import scores
    for r in results:
        decided = (f'{r.decision} after {r.decided_s:.2f} s' if r.decision is not None else
                   'no decision')
        label = f' (label {r.label})' if r.label else ''
        why = '' if r.windows else ' (' + (', '.join(
            f'{k} {v}' for k, v in r.faults.items() if isinstance(v, int) and v) or
            (f'at most {r.longest_contact} samples in contact at a time, shorter than one '
             f'window of {info.stream.window}' if r.longest_contact else
             'no sample in contact')) + ')'
        print(f'{r.name}: {decided}, {len(r.windows)} windows{why}{label}')
    summary = scores(results, list(info.classes))
    if summary is not None and summary['labels_not_in_model']:
        unknown = summary['labels_not_in_model']
        print(f'warning: label(s) {", ".join(unknown)} are not classes of {info.model_id} '
              f'({", ".join(info.classes)}): their recordings can never be right and count as '
              'wrong below', file=sys.stderr)
    if summary is not None:
        print(f'accuracy by recording: {100 * summary["accuracy"]:.1f} % of '
              f'{summary["recordings"]} ({summary["undecided"]} without a decision), '
              f'{info.model_id}')
