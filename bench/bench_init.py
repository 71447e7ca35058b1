# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Keras-faithful initial weights against PyTorch's defaults: epochs to 95 % training accuracy.

On the synthetic texture set (`--data`: e.g. the one `bench/bench_textures.py --keep-data
PATH` kept; without it, the set is built as bench_textures builds it), each of the eight
models is trained as the original trained them (Adamax, lr
1e-3, clipping, batch 32, Min-Max scaling) from both initialisations and the same seeds,
and the first epoch whose training accuracy reaches 95 % is noted (or "not within" the
cap, with the training accuracy the run ended at). To fit a shared CPU, training uses a
subset of whole recordings per class (stated in the output). Prints the table with the
ratio PyTorch / Keras measured in the same run; writes bench/results/init.md and
bench/results/init.json.
"""

import argparse
import json
from pathlib import Path
import sys
import tempfile
import time

from bench_textures import build_dataset
import numpy as np

from tactex_classify.data.dataset import Dataset
from tactex_classify.models.architectures import MODELS
from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig

RESULTS = Path(__file__).parent / 'results'
TARGET = 0.95


class _Reached(Exception):
    """Raised from the progress callback to stop training once the target is reached."""


def epochs_to_target(X, y, classes, model: str, init: str, seed: int, cap: int
                     ) -> tuple[int | None, list[float]]:
    """First epoch with training accuracy >= TARGET (None within `cap`), and the curve."""
    curve: list[float] = []

    def progress(record: dict) -> None:
        curve.append(record['train_accuracy'])
        if record['train_accuracy'] >= TARGET:
            raise _Reached(record['epoch'])
    config = TrainingConfig(model=model, epochs=cap, seed=seed, init=init)
    try:
        DeepClassifier(config, progress=progress).fit(X, y, classes)
    except _Reached as reached:
        return int(reached.args[0]), curve
    return None, curve


def cell(result: dict, cap: int) -> str:
    """Epochs to the target, or `>cap (accuracy reached)`."""
    if result['epochs']:
        return str(result['epochs'])
    return f'>{cap} ({100 * result["final_train_accuracy"]:.0f} %)'


def subset(dataset: Dataset, recordings_per_class: int, seed: int) -> np.ndarray:
    """Indices of the windows of `recordings_per_class` whole recordings of every class."""
    rng = np.random.default_rng(seed)
    keep = []
    for label in range(len(dataset.classes)):
        trials = np.unique(dataset.trial[dataset.y == label])
        keep += rng.choice(trials, min(recordings_per_class, trials.size), replace=False).tolist()
    return np.flatnonzero(np.isin(dataset.trial, keep))


def main() -> int:
    """Train every model from both initialisations and print/write the table."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--data', type=Path, help='synthetic set (.npz); default: build it')
    parser.add_argument('--models', nargs='+', default=list(MODELS), choices=list(MODELS))
    parser.add_argument('--seeds', type=int, nargs='+', default=[0, 1])
    parser.add_argument('--recordings-per-class', type=int, default=6)
    parser.add_argument('--cap', type=int, default=50, help='most epochs per run')
    args = parser.parse_args()
    if args.data is None:
        with tempfile.TemporaryDirectory() as folder:
            dataset = Dataset.load(build_dataset(Path(folder), 25, []))
    else:
        dataset = Dataset.load(args.data)
    rows = subset(dataset, args.recordings_per_class, seed=0)
    X, y = dataset.X[rows], dataset.y[rows]
    recordings = len(np.unique(dataset.trial[rows]))
    print(f'{args.data or "synthetic set"}: {rows.size} windows of {recordings} recordings '
          f'({args.recordings_per_class} per class), cap {args.cap} epochs', flush=True)
    results = []
    for model in args.models:
        for seed in args.seeds:
            for init in ('pytorch', 'keras'):
                start = time.monotonic()
                epochs, curve = epochs_to_target(X, y, dataset.classes, model, init, seed,
                                                 args.cap)
                results.append({'model': model, 'seed': seed, 'init': init, 'epochs': epochs,
                                'final_train_accuracy': curve[-1], 'curve': curve,
                                'seconds': round(time.monotonic() - start, 1)})
                print(f'{model} seed {seed} {init}: '
                      f'{epochs if epochs else f"not within {args.cap}"} epochs, training '
                      f'accuracy {100 * curve[-1]:.1f} % ({results[-1]["seconds"]} s)',
                      flush=True)
    lines = ['| model | PyTorch init: epochs to 95 % | Keras init: epochs to 95 % | '
             'ratio PyTorch / Keras |', '|---|---|---|---|']
    for model in args.models:
        epochs = {init: [r['epochs'] for r in results if r['model'] == model
                         and r['init'] == init] for init in ('pytorch', 'keras')}
        cells = [', '.join(cell(r, args.cap) for r in results
                           if r['model'] == model and r['init'] == init)
                 for init in ('pytorch', 'keras')]
        capped = {init: [e or args.cap for e in epochs[init]] for init in epochs}
        ratio = np.mean(capped['pytorch']) / np.mean(capped['keras'])
        lines.append(f'| {model} | {cells[0]} | {cells[1]} | {ratio:.2f} |')
    text = '\n'.join(lines)
    print(text)
    header = (f'# Initialisation and convergence (bench/bench_init.py)\n\n'
              f'{rows.size} windows of {args.recordings_per_class} recordings per class of '
              f'the synthetic set, seeds {args.seeds}, at most {args.cap} epochs; a ratio '
              f'counts an unreached target as {args.cap} epochs.\n\n')
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / 'init.md').write_text(header + text + '\n', encoding='utf-8')
    (RESULTS / 'init.json').write_text(json.dumps(
        {'windows': int(rows.size), 'recordings_per_class': args.recordings_per_class,
         'seeds': args.seeds, 'cap': args.cap, 'target': TARGET, 'models': args.models,
         'data': str(args.data) if args.data else None, 'results': results},
        indent=1) + '\n', encoding='utf-8')
    return 0


if __name__ == '__main__':
    sys.exit(main())
