# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What each element of the `modern` training profile buys: an ablation, grouped by recording.

Simulates the uneven-texture scene (`tactex sim collect`, 12 textures x `--sweeps`) and
converts it (128-sample windows) once, or reads `--data`. Then trains one deep model
(`--model`, default cnn_3) on the same grouped folds with: the `original` profile, the
`modern` profile, modern without each of its elements in turn, and modern with
per-window scaling; the two baselines run on the same folds as the reference. Each row
gives grouped accuracy (mean and per fold), the epochs trained, seconds per fold, and
whether the training converged (`not converged` when the loss was still falling when
training stopped, `DeepClassifier.still_falling_`: the last 5 epochs' mean loss more than
2 % below the 5 before, without early stopping having ended it; or when it never fell
below chance: `unconverged_because`). Writes
bench/results/profiles/profiles.{json,md,png}; the README's table is generated from the
JSON.
"""

import argparse
import dataclasses
import json
import os
from pathlib import Path
import sys
import tempfile
import time

os.environ.setdefault('OMP_WAIT_POLICY', 'PASSIVE')

from bench_textures import build_dataset  # noqa: E402  (the texture results' one dataset build)
import numpy as np  # noqa: E402  (after the OpenMP setting)

RESULTS = Path(__file__).parent / 'results' / 'profiles'
# Each ablation: (row name, what it changes in the modern profile).
ABLATIONS = {
    'modern - augmentation': {'augmentations': ()},
    'modern - mixup': {'mixup_alpha': 0.0},
    'modern - AdamW, warm-up, cosine': {'optimizer': 'adamax', 'weight_decay': 0.0,
                                        'schedule': 'constant', 'warmup_epochs': 0},
    'modern - label smoothing': {'label_smoothing': 0.0},
    'modern - weight EMA': {'ema_decay': 0.0},
    "modern - PyTorch's BatchNorm momentum": {'batchnorm_momentum': 0.01},
    'modern - early stopping': {'early_stopping': 0},
    'modern + per-window scaling': {'scaling': 'window'},
}
BASELINE_ROWS = ('minirocket', 'multirocket', 'hydra', 'multirocket_hydra', 'extratrees')


def configurations(model: str, epochs: int, seed: int) -> dict:
    """Row name -> TrainingConfig (deep) or the baseline's name."""
    from tactex_classify.training.deep_classifier import TrainingConfig
    modern = TrainingConfig.for_profile('modern', model=model, epochs=epochs, seed=seed)
    rows = {'original': TrainingConfig.for_profile('original', model=model, epochs=epochs,
                                                   seed=seed),
            'modern': modern}
    rows.update({name: dataclasses.replace(modern, **change)
                 for name, change in ABLATIONS.items()})
    rows.update({name: name for name in BASELINE_ROWS})
    return rows


def run_fold(config, dataset, train, test, device: str = 'cpu') -> dict:
    """Fit one row on one fold (deep models on `device`); accuracy, epochs, seconds."""
    from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
    from tactex_classify.training.estimators import build_estimator
    if isinstance(config, str):
        estimator = build_estimator(TrainingConfig(model=config))
    else:
        estimator = DeepClassifier(config, device=device)
    started = time.perf_counter()
    estimator.fit(dataset.X[train], dataset.y[train], dataset.classes,
                  groups=dataset.trial[train], channels=dataset.channels)
    seconds = time.perf_counter() - started
    accuracy = float(np.mean(estimator.predict_proba(dataset.X[test]).argmax(1)
                             == dataset.y[test]))
    fold = {'accuracy': accuracy, 'seconds': round(seconds, 1)}
    if not isinstance(config, str):
        history = estimator.history_
        fold.update({'epochs': len(history), 'best_epoch': estimator.best_epoch_,
                     'stopped_early': len(history) < config.epochs,
                     'still_falling': estimator.still_falling_,
                     'unconverged': estimator.unconverged_reason()})
    return fold


def not_converged(folds: list[dict]) -> bool:
    """Whether a row's training did not converge in some fold (`unconverged_because`).

    A fold kept before that was recorded holds only `still_falling`.
    """
    return any(fold.get('unconverged') or fold.get('still_falling') for fold in folds)


def markdown(summary: dict) -> str:
    """The ablation table: a row per training (and baseline), accuracy and cost."""
    lines = [f'{summary["model"]}, grouped {summary["folds"]}-fold accuracy on '
             f'{summary["windows"]} windows of {summary["recordings"]} simulated recordings '
             f'(chance {100 * summary["chance"]:.1f} %), at most {summary["epochs"]} epochs; '
             f'`{summary["command"].strip()}`.', '',
             '| training | grouped accuracy | per fold | epochs | s per fold |',
             '|---|---|---|---|---|']
    lines += ['| ' + ' | '.join(row_cells(row)) + ' |' for row in summary['rows']]
    return '\n'.join(lines) + '\n'


def row_cells(row: dict) -> list[str]:
    """A kept row's name (marked if not converged), accuracy, folds, epochs, seconds."""
    folds = ' / '.join(f'{100 * fold["accuracy"]:.1f}' for fold in row['folds'])
    epochs = ' / '.join(str(fold['epochs']) for fold in row['folds']) \
        if row['kind'] == 'deep' else '-'
    seconds = np.mean([fold['seconds'] for fold in row['folds']])
    mark = ' (not converged)' if row['not_converged'] else ''
    return [f'{row["name"]}{mark}', f'{100 * row["accuracy"]:.1f} ± {100 * row["sd"]:.1f} %',
            folds, epochs, f'{seconds:.0f}']


def plot(summary: dict, path: Path) -> None:
    """A bar per row with its folds as points; chance as a line."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    rows = summary['rows']
    figure, axes = plt.subplots(figsize=(8, 0.45 * len(rows) + 1.2))
    positions = np.arange(len(rows))[::-1]
    colours = ['tab:grey' if row['kind'] == 'baseline' else
               'tab:orange' if row['name'] == 'original' else 'tab:blue' for row in rows]
    axes.barh(positions, [100 * row['accuracy'] for row in rows], color=colours, alpha=0.7)
    for position, row in zip(positions, rows, strict=True):
        axes.plot([100 * fold['accuracy'] for fold in row['folds']],
                  [position] * len(row['folds']), 'k.', markersize=4)
    axes.axvline(100 * summary['chance'], color='k', linestyle=':', label='chance')
    axes.set_yticks(positions, [row['name'] + (' *' if row['not_converged'] else '')
                                for row in rows], fontsize=8)
    axes.set_xlabel('grouped accuracy (%); * not converged')
    axes.set_title(f'{summary["model"]}: training profiles, ablated', fontsize=10)
    axes.legend(loc='lower right', fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def common_parser(doc: str, results: Path) -> argparse.ArgumentParser:
    """The options the grouped-fold benches share: data, sweeps, epochs, folds, seed, out."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument('--data', type=Path, help='a converted dataset (default: simulate one)')
    parser.add_argument('--sweeps', type=int, default=10, help='sweeps per texture (10)')
    parser.add_argument('--epochs', type=int, default=100, help='epochs at most (100)')
    parser.add_argument('--folds', type=int, default=3, help='grouped folds (3)')
    parser.add_argument('--seed', type=int, default=0)
    parser.add_argument('--out', type=Path, default=results)
    return parser


def load_or_simulate(data: Path | None, sweeps: int):
    """The dataset at `data`, or the texture set simulated and converted (128 samples)."""
    from tactex_classify.data.dataset import Dataset
    with tempfile.TemporaryDirectory(prefix='tactex-bench-') as scratch:
        if data is None:
            print(f'simulating 12 textures x {sweeps} sweeps', flush=True)
        return Dataset.load(data or build_dataset(Path(scratch), sweeps, steps=[]))


def finish_plot(figure, axes, chance: float, title: str, path: Path) -> None:
    """Chance as a dotted line, the title, the legend outside the data; save and close."""
    import matplotlib.pyplot as plt
    axes.axhline(100 * chance, color='k', linestyle=':', label='chance')
    axes.set_title(title, fontsize=10)
    axes.legend(loc='upper left', bbox_to_anchor=(1.01, 1.0), fontsize=8)
    figure.tight_layout()
    figure.savefig(path, dpi=120)
    plt.close(figure)


def keep(out: Path, stem: str, summary: dict, markdown, plot) -> None:
    """Write OUT/STEM.json, STEM.md (`markdown(summary)`) and STEM.png (`plot`)."""
    out.mkdir(parents=True, exist_ok=True)
    (out / f'{stem}.json').write_text(json.dumps(summary, indent=1) + '\n', encoding='utf-8')
    (out / f'{stem}.md').write_text(markdown(summary), encoding='utf-8')
    plot(summary, out / f'{stem}.png')
    print(f'wrote {stem}.json, {stem}.md and {stem}.png to {out}')


def main() -> int:
    parser = common_parser(__doc__, RESULTS)
    parser.add_argument('--model', default='cnn_3')
    args = parser.parse_args()
    from tactex_classify.evaluation.cross_validation import splits

    started = time.monotonic()
    dataset = load_or_simulate(args.data, args.sweeps)
    folds = splits(dataset, 'grouped', args.folds, args.seed)
    rows = []
    for name, config in configurations(args.model, args.epochs, args.seed).items():
        results = []
        for index, (train, test) in enumerate(folds, start=1):
            results.append(run_fold(config, dataset, train, test))
            last = results[-1]
            extra = (f', {last["epochs"]} epochs' + (' (still falling)'
                                                      if last['still_falling'] else '')
                     if 'epochs' in last else '')
            print(f'[{time.monotonic() - started:7.0f} s] {name:40s} fold {index}: '
                  f'{100 * last["accuracy"]:5.1f} %{extra}, {last["seconds"]:.0f} s',
                  flush=True)
        accuracies = [fold['accuracy'] for fold in results]
        rows.append({'name': name, 'kind': 'baseline' if isinstance(config, str) else 'deep',
                     'config': config if isinstance(config, str) else dataclasses.asdict(config),
                     'accuracy': float(np.mean(accuracies)), 'sd': float(np.std(accuracies)),
                     'not_converged': not_converged(results),
                     'folds': results})
    summary = {'model': args.model, 'epochs': args.epochs, 'folds': args.folds,
               'seed': args.seed, 'windows': int(dataset.y.size),
               'recordings': int(np.unique(dataset.trial).size),
               'chance': 1 / len(dataset.classes),
               'command': 'python bench/bench_profiles.py ' + ' '.join(sys.argv[1:]),
               'seconds': round(time.monotonic() - started, 1), 'rows': rows}
    keep(args.out, 'profiles', summary, markdown, plot)
    return 0


if __name__ == '__main__':
    sys.exit(main())
