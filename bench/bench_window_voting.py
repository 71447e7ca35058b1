# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Soft voting across window sizes against each window size alone, grouped by recording.

The same simulated recordings cut at 128, 256 and 512 samples (`--data` names the three
converted datasets, shortest first; without it the set is simulated as bench_profiles
does and converted three times). The grouped folds are drawn on the recordings once and
shared by every length. Per model (`--models`: deep ones with the `modern` profile and
per-window scaling, baselines as they are) and fold, one model is trained per length; each
is scored on its own test windows, and the vote
(`tactex_classify.evaluation.window_voting`) on the 512-sample test windows. Training
seconds add up over the three lengths for the vote. Writes
bench/results/window_voting/window_voting.{json,md,png}.
"""

import argparse
import os
from pathlib import Path
import subprocess
import sys
import tempfile
import time

os.environ.setdefault('OMP_WAIT_POLICY', 'PASSIVE')

from bench_architectures import configuration, fit_timed  # noqa: E402  (one row's model)
from bench_profiles import finish_plot, keep  # noqa: E402
from bench_textures import build_dataset, TACTEX  # noqa: E402
import numpy as np  # noqa: E402

RESULTS = Path(__file__).parent / 'results' / 'window_voting'
WINDOWS = (128, 256, 512)


def run_model(name, config, datasets, folds, device, started) -> dict:
    """Per-length and voted accuracy of one model over the shared folds."""
    from tactex_classify.evaluation.window_voting import soft_vote, windows_inside
    scores = {str(w): [] for w in WINDOWS} | {'vote': []}
    seconds = {str(w): [] for w in WINDOWS}
    for index, test_trials in enumerate(folds, start=1):
        probabilities, tests = [], []
        for window, dataset in zip(WINDOWS, datasets, strict=True):
            held_out = np.isin(dataset.trial, test_trials)
            test = dataset.select(held_out)
            estimator, spent = fit_timed(config, dataset.select(~held_out), device)
            proba = estimator.predict_proba(test.X)
            probabilities.append(proba)
            tests.append(test)
            scores[str(window)].append(float(np.mean(proba.argmax(1) == test.y)))
            seconds[str(window)].append(spent)
        inner = [(proba, windows_inside(tests[-1], test))
                 for proba, test in zip(probabilities[:-1], tests[:-1], strict=True)]
        vote = soft_vote(probabilities[-1], inner)
        scores['vote'].append(float(np.mean(vote.argmax(1) == tests[-1].y)))
        print(f'[{time.monotonic() - started:7.0f} s] {name:14s} fold {index}: ' + ', '.join(
            f'{key} {100 * values[-1]:.1f} %' for key, values in scores.items()), flush=True)
    return {'name': name, 'accuracy': scores,
            'seconds': {key: float(np.mean(values)) for key, values in seconds.items()}}


def markdown(summary: dict) -> str:
    """One row per model: accuracy at each length alone and voted, with training cost."""
    lines = [f'Grouped {summary["folds"]}-fold accuracy on {summary["recordings"]} simulated '
             f'recordings (chance {100 * summary["chance"]:.1f} %); deep models: `modern` '
             'profile, per-window scaling; each length on its own test windows, the vote on '
             f'the 512-sample ones; `{summary["command"].strip()}`.', '',
             '| model | 128 alone | 256 alone | 512 alone | soft vote of the three | '
             'training s per fold (vote: sum) |', '|---|---|---|---|---|---|']
    for row in summary['rows']:
        cells = [f'{100 * np.mean(row["accuracy"][key]):.1f} ± '
                 f'{100 * np.std(row["accuracy"][key]):.1f} %'
                 for key in ('128', '256', '512', 'vote')]
        lines.append(f'| {row["name"]} | ' + ' | '.join(cells) +
                     f' | {sum(row["seconds"].values()):.0f} |')
    return '\n'.join(lines) + '\n'


def plot(summary: dict, path: Path) -> None:
    """Grouped bars: each length alone and the vote, per model."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    keys = ('128', '256', '512', 'vote')
    rows = summary['rows']
    figure, axes = plt.subplots(figsize=(8, 4.5))
    width = 0.8 / len(keys)
    for offset, key in enumerate(keys):
        positions = np.arange(len(rows)) + offset * width
        axes.bar(positions, [100 * np.mean(row['accuracy'][key]) for row in rows], width,
                 yerr=[100 * np.std(row['accuracy'][key]) for row in rows], capsize=3,
                 label=f'{key} alone' if key != 'vote' else 'soft vote')
    axes.set_xticks(np.arange(len(rows)) + width * (len(keys) - 1) / 2,
                    [row['name'] for row in rows])
    axes.set_ylabel('grouped accuracy (%)')
    finish_plot(figure, axes, summary['chance'], 'soft voting across window sizes', path)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--data', type=Path, nargs=3, metavar=('D128', 'D256', 'D512'),
                        help='the three converted datasets (default: simulate and convert)')
    parser.add_argument('--sweeps', type=int, default=10, help='sweeps per texture (10)')
    parser.add_argument('--models', default='multirocket,cnn_3',
                        help='comma-separated (multirocket,cnn_3)')
    parser.add_argument('--epochs', type=int, default=100, help='epochs at most (100)')
    parser.add_argument('--folds', type=int, default=3, help='grouped folds (3)')
    parser.add_argument('--seed', type=int, default=0)
    parser.add_argument('--device', default='cpu')
    parser.add_argument('--out', type=Path, default=RESULTS)
    args = parser.parse_args()
    from tactex_classify.data.dataset import Dataset
    from tactex_classify.evaluation.cross_validation import splits

    started = time.monotonic()
    with tempfile.TemporaryDirectory(prefix='tactex-voting-') as scratch:
        paths = args.data
        if paths is None:
            print(f'simulating 12 textures x {args.sweeps} sweeps', flush=True)
            first = build_dataset(Path(scratch), args.sweeps, steps=[])
            paths = [first] + [Path(scratch) / f'sim{w}.npz' for w in WINDOWS[1:]]
            for window, path in zip(WINDOWS[1:], paths[1:], strict=True):
                subprocess.run([TACTEX, 'convert', str(Path(scratch) / 'bags'), '--out',
                                str(path), '--window', str(window)], check=True)
        datasets = [Dataset.load(path) for path in paths]
    longest = datasets[-1]
    folds = [np.unique(longest.trial[test])
             for _, test in splits(longest, 'grouped', args.folds, args.seed)]
    rows = [run_model(name, configuration(name, args.epochs, args.seed, 1), datasets, folds,
                      args.device, started)
            for name in (n.strip() for n in args.models.split(',') if n.strip())]
    summary = {'folds': args.folds, 'epochs': args.epochs, 'seed': args.seed,
               'recordings': int(np.unique(longest.trial).size),
               'windows': {str(w): int(d.y.size) for w, d in zip(WINDOWS, datasets,
                                                                  strict=True)},
               'chance': 1 / len(longest.classes), 'device': args.device,
               'command': 'python bench/bench_window_voting.py ' + ' '.join(sys.argv[1:]),
               'seconds': round(time.monotonic() - started, 1), 'rows': rows}
    keep(args.out, 'window_voting', summary, markdown, plot)
    return 0


if __name__ == '__main__':
    sys.exit(main())
