# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""HYDRA's kernels normalised per channel (tactex's) against over all channels at once.

Each kernel's weights are made zero-mean and scaled to an absolute sum of 1. Over each
channel's taps (`HydraRidge.NORMALISED_AXES`, the default) a kernel ignores every
channel's level in the window; over all of a kernel's channels at once (the
normalisation HYDRA used here before 2026-11-27, and the kept GPU comparison's HYDRA
rows) the levels of the channels it reads leak into every response, so the kernel with
the largest weight sum on a channel's offset tends to win every step. Both run on the
same grouped folds and seeds as `tactex compare` draws them (the kept GPU comparison's
data by default); prints each fold's accuracy, the means and the paired difference, and
keeps results/hydra_levels.json.
"""

import argparse
import json
import os
from pathlib import Path
import sys
import time

os.environ.setdefault('OMP_NUM_THREADS', '1')

import numpy as np  # noqa: E402

from tactex_classify.data.dataset import Dataset  # noqa: E402
from tactex_classify.evaluation.cross_validation import splits  # noqa: E402
from tactex_classify.evaluation.grid_report import paired_difference  # noqa: E402
from tactex_classify.models.hydra import HydraRidge  # noqa: E402

RESULTS = Path(__file__).parent / 'results' / 'hydra_levels.json'


class JointlyNormalisedHydra(HydraRidge):
    """HYDRA with each kernel normalised over all the channels it reads at once."""

    NORMALISED_AXES = (-2, -1)


def main() -> int:
    """Both normalisations on the same folds; print and keep the accuracies."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--data', type=Path,
                        default=Path('/tmp/tactex-compare-data/sim128_first20.npz'),
                        help="a dataset (.npz); default the kept GPU comparison's")
    parser.add_argument('--folds', type=int, default=5)
    parser.add_argument('--seeds', type=int, default=1)
    args = parser.parse_args()
    dataset = Dataset.load(args.data)
    variants = {'per channel (tactex)': HydraRidge, 'all channels at once': JointlyNormalisedHydra}
    accuracy = {name: {} for name in variants}
    seconds = {name: 0.0 for name in variants}
    for seed in range(args.seeds):
        for fold, (train, test) in enumerate(splits(dataset, 'grouped', args.folds, seed), 1):
            for name, make in variants.items():
                started = time.perf_counter()
                model = make(seed=seed).fit(dataset.X[train], dataset.y[train],
                                            dataset.classes)
                predicted = model.predict_proba(dataset.X[test]).argmax(axis=1)
                seconds[name] += time.perf_counter() - started
                score = float(np.mean(predicted == dataset.y[test]))
                accuracy[name][f'{seed}-{fold}'] = score
                print(f'seed {seed} fold {fold}: {name} {100 * score:.1f} %', flush=True)
    ours, theirs = accuracy.values()
    difference = paired_difference(ours, theirs)
    for name, values in accuracy.items():
        print(f'{name}: {100 * np.mean(list(values.values())):.1f} % grouped '
              f'({len(values)} folds, {seconds[name] / len(values):.0f} s per fold)')
    print(f'per channel - all at once: {100 * difference["mean"]:+.1f} points '
          f'[{100 * difference["low"]:+.1f}, {100 * difference["high"]:+.1f}] (95 %, paired)')
    RESULTS.write_text(json.dumps({
        'data': str(args.data), 'windows': len(dataset.y), 'folds': args.folds,
        'seeds': args.seeds, 'accuracy': accuracy, 'seconds_per_fold': {
            name: seconds[name] / len(values) for name, values in accuracy.items()},
        'difference': difference}, indent=1) + '\n', encoding='utf-8')
    return 0


if __name__ == '__main__':
    sys.exit(main())
