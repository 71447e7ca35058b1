# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Sim-to-real fine-tuning: accuracy on a shifted scene against its recordings per texture.

A stand-in for a real arm: `config/scenes/shifted_texture.toml` records the same textures
as the uneven-texture scene through a softer body, a lighter press, a faster sweep, twice
the noise and wider chip ranges. The source is the uneven-texture set
(`--source`, default simulated with `--source-sweeps` per texture); the target is the
shifted scene (`--target`, default simulated with `--target-sweeps`). `--test` recordings
per texture of the target are held out for scoring; from the rest, k recordings per
texture (`--ks`) are drawn `--draws` times. Four settings side by side, on the same draws:
- trained on the k shifted recordings alone (the deep model, `--model`);
- trained on simulation alone (the source; the same model, once);
- pretrained on simulation, then fine-tuned on the k recordings (`tactex train --init`);
- the best baseline (MultiRocket) trained on the k recordings.
Deep models train with the `modern` profile and per-window scaling for `--epochs` epochs
(no early stopping: with one recording per texture there is none to hold out); the
pretraining stops early on held-out source recordings. Writes
bench/results/sim_to_real/sim_to_real.{json,md,png}.
"""

import argparse
import dataclasses
import os
from pathlib import Path
import subprocess
import sys
import tempfile
import time

os.environ.setdefault('OMP_WAIT_POLICY', 'PASSIVE')

from bench_architectures import fit_timed  # noqa: E402  (one fit for every bench)
from bench_profiles import finish_plot, keep  # noqa: E402  (the benches' shared writers)
from bench_textures import build_dataset, TACTEX  # noqa: E402
import numpy as np  # noqa: E402

RESULTS = Path(__file__).parent / 'results' / 'sim_to_real'
SETTINGS = ('shifted alone', 'simulation alone', 'pretrained + fine-tuned',
            'MultiRocket, shifted alone')


def shifted_dataset(folder: Path, sweeps: int) -> Path:
    """Simulate the shifted scene into `folder` and convert it (128 samples)."""
    bags, data = folder / 'shifted_bags', folder / 'shifted128.npz'
    subprocess.run([TACTEX, 'sim', 'collect', '--scene', 'shifted_texture', '--sweeps',
                    str(sweeps), '--out', str(bags)], check=True)
    subprocess.run([TACTEX, 'convert', str(bags), '--out', str(data), '--window', '128'],
                   check=True)
    return data


def hold_out(dataset, per_texture: int, rng: np.random.Generator):
    """(test set, the other recordings): `per_texture` recordings of each texture held out."""
    held = []
    for label in range(len(dataset.classes)):
        recordings = np.unique(dataset.trial[dataset.y == label])
        held += list(rng.choice(recordings, size=per_texture, replace=False))
    return (dataset.select(np.isin(dataset.trial, held)),
            np.setdiff1d(np.unique(dataset.trial), held))


def draw(target, recordings: np.ndarray, k: int, rng: np.random.Generator) -> np.ndarray:
    """Window mask of k recordings per texture drawn from `recordings`."""
    chosen = []
    for label in range(len(target.classes)):
        pool = np.unique(target.trial[np.isin(target.trial, recordings) & (target.y == label)])
        chosen += list(rng.choice(pool, size=min(k, pool.size), replace=False))
    return np.isin(target.trial, chosen)


def accuracy(estimator, test) -> float:
    """Share of the test windows classified right."""
    return float(np.mean(estimator.predict_proba(test.X).argmax(1) == test.y))


def fit(config, data):
    """A deep model (TrainingConfig) or MultiRocket (None) fitted on `data`."""
    return fit_timed('multirocket' if config is None else config, data)[0]


def markdown(summary: dict) -> str:
    """Accuracy per setting against k recordings per texture of the shifted scene."""
    ks = summary['ks']
    lines = [f'Accuracy on {summary["test_windows"]} windows of {summary["test"]} held-out '
             f'recordings per texture of the shifted scene (chance '
             f'{100 * summary["chance"]:.1f} %), mean ± sd over {summary["draws"]} draws of '
             f'the k training recordings; {summary["model"]}, `modern` profile, per-window '
             f'scaling, {summary["epochs"]} epochs; pretrained on '
             f'{summary["source_recordings"]} simulated recordings of the uneven-texture '
             f'scene; `{summary["command"].strip()}`.', '',
             '| setting | ' + ' | '.join(f'k = {k}' for k in ks) + ' |',
             '|---|' + '---|' * len(ks)]
    for setting in SETTINGS:
        cells = [f'{100 * np.mean(summary["accuracy"][setting][str(k)]):.1f} ± '
                 f'{100 * np.std(summary["accuracy"][setting][str(k)]):.1f} %' for k in ks]
        lines.append(f'| {setting} | ' + ' | '.join(cells) + ' |')
    return '\n'.join(lines) + '\n'


def plot(summary: dict, path: Path) -> None:
    """A line per setting: accuracy against k, with the draws' spread."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    ks = summary['ks']
    figure, axes = plt.subplots(figsize=(8, 4.5))
    for setting in SETTINGS:
        values = [summary['accuracy'][setting][str(k)] for k in ks]
        axes.errorbar(ks, [100 * np.mean(v) for v in values],
                      yerr=[100 * np.std(v) for v in values], marker='o', capsize=3,
                      label=setting)
    axes.set_xscale('log')
    axes.set_xticks(ks, [str(k) for k in ks])
    axes.set_xlabel('recordings per texture of the shifted scene (k)')
    axes.set_ylabel('accuracy on held-out shifted recordings (%)')
    finish_plot(figure, axes, summary['chance'], 'sim-to-real fine-tuning on a shifted scene',
                path)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--source', type=Path, help='converted uneven-texture set')
    parser.add_argument('--source-sweeps', type=int, default=10)
    parser.add_argument('--target', type=Path, help='converted shifted-scene set')
    parser.add_argument('--target-sweeps', type=int, default=15)
    parser.add_argument('--test', type=int, default=5, help='held-out recordings per texture')
    parser.add_argument('--ks', default='1,2,5,10')
    parser.add_argument('--draws', type=int, default=3)
    parser.add_argument('--model', default='cnn_3')
    parser.add_argument('--epochs', type=int, default=60)
    parser.add_argument('--seed', type=int, default=0)
    parser.add_argument('--out', type=Path, default=RESULTS)
    args = parser.parse_args()
    from tactex_classify.data.dataset import Dataset
    from tactex_classify.training.deep_classifier import TrainingConfig

    started = time.monotonic()
    ks = [int(k) for k in args.ks.split(',')]
    with tempfile.TemporaryDirectory(prefix='tactex-sim-to-real-') as scratch:
        folder = Path(scratch)
        source = Dataset.load(args.source or build_dataset(folder, args.source_sweeps, []))
        target = Dataset.load(args.target or shifted_dataset(folder, args.target_sweeps))
        test, pool = hold_out(target, args.test, np.random.default_rng(args.seed))
        base = TrainingConfig.for_profile('modern', model=args.model, epochs=args.epochs,
                                          scaling='window', early_stopping=0, seed=args.seed)
        pretrained = fit(dataclasses.replace(base, early_stopping=30, epochs=100), source)
        checkpoint = pretrained.save(folder / 'pretrained',
                                     hop=int(source.info['hop']),
                                     sampling_rate_hz=float(source.info['sampling_rate_hz']))
        simulation_only = accuracy(pretrained, test)
        print(f'[{time.monotonic() - started:6.0f} s] simulation alone: '
              f'{100 * simulation_only:.1f} %', flush=True)
        scores = {setting: {str(k): [] for k in ks} for setting in SETTINGS}
        for k in ks:
            for index in range(args.draws):
                train = target.select(draw(target, pool, k, np.random.default_rng(
                    [args.seed, k, index])))
                seeded = dataclasses.replace(base, seed=args.seed + index)
                results = {
                    'shifted alone': accuracy(fit(seeded, train), test),
                    'simulation alone': simulation_only,
                    'pretrained + fine-tuned': accuracy(fit(dataclasses.replace(
                        seeded, pretrained=str(checkpoint)), train), test),
                    'MultiRocket, shifted alone': accuracy(fit(None, train), test)}
                for setting, value in results.items():
                    scores[setting][str(k)].append(value)
                print(f'[{time.monotonic() - started:6.0f} s] k={k} draw {index + 1}: ' +
                      ', '.join(f'{name} {100 * value:.1f} %'
                                for name, value in results.items()), flush=True)
    summary = {'ks': ks, 'draws': args.draws, 'test': args.test, 'model': args.model,
               'epochs': args.epochs, 'seed': args.seed, 'test_windows': int(test.y.size),
               'source_recordings': int(np.unique(source.trial).size),
               'chance': 1 / len(target.classes),
               'command': 'python bench/bench_sim_to_real.py ' + ' '.join(sys.argv[1:]),
               'seconds': round(time.monotonic() - started, 1), 'accuracy': scores}
    keep(args.out, 'sim_to_real', summary, markdown, plot)
    return 0


if __name__ == '__main__':
    sys.exit(main())
