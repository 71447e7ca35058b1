# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Modern architectures beside the original's best, grouped by recording, with their cost.

The same simulated set and grouped folds as bench/bench_profiles.py (12 textures x
`--sweeps`, 128-sample windows; or `--data`). Each deep model in `--models` trains with
the `modern` profile and per-window scaling (the ablation's best), at most `--epochs`;
MultiRocket and MiniRocket run on the same folds as the reference. Each row gives grouped
accuracy (mean, per fold), epochs, training seconds per fold, inference milliseconds per
window, and `not converged` where the loss was still falling at the last epoch.

Rows are kept as they finish in RESULTS/architectures.json, so a run resumes: rows whose
model, epochs, folds and dataset match are not trained again, and a costly model (on two
CPU cores InceptionTime trains about 18 s per epoch on this set, its ensemble five times
that) can be added later or on a GPU (`--device cuda`). Writes architectures.{json,md,png};
the README's table is generated from the JSON.
"""

import dataclasses
import hashlib
import json
import os
from pathlib import Path
import sys
import time

os.environ.setdefault('OMP_WAIT_POLICY', 'PASSIVE')

from bench_profiles import (  # noqa: E402  (the grouped-fold benches' shared parts)
    common_parser,
    finish_plot,
    keep,
    load_or_simulate,
    not_converged,
    row_cells,
    run_fold,
)
import numpy as np  # noqa: E402

RESULTS = Path(__file__).parent / 'results' / 'architectures'
REFERENCES = ('multirocket', 'minirocket')


def configuration(model: str, epochs: int, seed: int, device_threads: int):
    """The row's training: modern profile and per-window scaling, or a baseline's name."""
    from tactex_classify.models.registry import BASELINES
    from tactex_classify.training.deep_classifier import TrainingConfig
    if model in BASELINES:
        return model
    return TrainingConfig.for_profile('modern', model=model, epochs=epochs, seed=seed,
                                      scaling='window', threads=device_threads)


def fit_timed(config, data, device: str = 'cpu', state_file: Path | None = None,
              progress=None):
    """(estimator, seconds): a deep model (TrainingConfig) or baseline (its name) fitted.

    A deep model reports each epoch to `progress` (if given), keeps its state in
    `state_file` (if given) and resumes from it; the seconds then include the training
    done before the resume.
    """
    from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
    from tactex_classify.training.estimators import build_estimator
    estimator = build_estimator(TrainingConfig(model=config)) if isinstance(config, str) \
        else DeepClassifier(config, device=device, state_file=state_file, progress=progress)
    started = time.perf_counter()
    estimator.fit(data.X, data.y, data.classes, groups=data.trial, channels=data.channels)
    return estimator, time.perf_counter() - started + getattr(estimator, 'resumed_seconds_', 0)


def inference_ms(config, dataset, train, device: str) -> float:
    """Milliseconds per window to classify a batch of 256, after fitting one epoch."""
    from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
    from tactex_classify.training.estimators import build_estimator
    quick = build_estimator(TrainingConfig(model=config)) if isinstance(config, str) else \
        DeepClassifier(dataclasses.replace(config, epochs=1, early_stopping=0), device=device)
    subset = train[:512]
    quick.fit(dataset.X[subset], dataset.y[subset], dataset.classes,
              groups=dataset.trial[subset], channels=dataset.channels)
    batch = dataset.X[train[:256]]
    quick.predict_proba(batch)
    started = time.perf_counter()
    for _ in range(3):
        quick.predict_proba(batch)
    return 1000 * (time.perf_counter() - started) / (3 * len(batch))


def markdown(summary: dict) -> str:
    """The table: a row per model, accuracy, epochs and cost."""
    lines = [f'Grouped {summary["folds"]}-fold accuracy on {summary["windows"]} windows of '
             f'{summary["recordings"]} simulated recordings (chance '
             f'{100 * summary["chance"]:.1f} %); deep models: `modern` profile, per-window '
             f'scaling, at most {summary["epochs"]} epochs, on {summary["device"]}; '
             f'`{summary["command"].strip()}`.', '',
             '| model | grouped accuracy | per fold | epochs | training s per fold | '
             'inference ms per window |', '|---|---|---|---|---|---|']
    lines += ['| ' + ' | '.join(row_cells(row) + [f'{row["inference_ms"]:.2f}']) + ' |'
              for row in summary['rows']]
    if summary.get('not_run'):
        lines += ['', 'Not run yet: ' + ', '.join(summary['not_run']) + '.']
    return '\n'.join(lines) + '\n'


def plot(summary: dict, path: Path) -> None:
    """Accuracy against training cost, one point per model with its folds' spread."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(figsize=(8, 5))
    for index, row in enumerate(summary['rows']):
        seconds = np.mean([fold['seconds'] for fold in row['folds']])
        axes.errorbar(seconds, 100 * row['accuracy'], yerr=100 * row['sd'],
                      fmt='^' if row['kind'] == 'baseline' else 'o', color=f'C{index % 10}',
                      capsize=3, label=row['name'] + (' *' if row['not_converged'] else ''))
    axes.set_xscale('log')
    axes.set_xlabel('training seconds per fold (log)')
    axes.set_ylabel('grouped accuracy (%); * not converged')
    finish_plot(figure, axes, summary['chance'], 'architectures: accuracy against training '
                'cost (triangles: baselines)', path)


def _kept(path: Path, key: dict) -> dict:
    """Rows kept by an earlier run of the same setup (dataset, folds, epochs, device)."""
    if not path.is_file():
        return {}
    kept = json.loads(path.read_text(encoding='utf-8'))
    if {name: kept.get(name) for name in key} != key:
        return {}
    return {row['name']: row for row in kept['rows']}


def _summary(key: dict, dataset, rows: list[dict], kept: dict) -> dict:
    """What architectures.json keeps: the setup, this run's rows, then rows kept before."""
    from tactex_classify.models.registry import MODERN_MODELS
    done = {row['name'] for row in rows}
    rows = rows + [row for name, row in kept.items() if name not in done]
    return {**key, 'windows': int(dataset.y.size),
            'recordings': int(np.unique(dataset.trial).size),
            'chance': 1 / len(dataset.classes),
            'command': 'python bench/bench_architectures.py ' + ' '.join(sys.argv[1:]),
            'rows': rows, 'not_run': [name for name in ('cnn_3',) + MODERN_MODELS
                                      if name not in {row['name'] for row in rows}]}


def main() -> int:
    from tactex_classify.models.registry import MODERN_MODELS
    parser = common_parser(__doc__, RESULTS)
    parser.add_argument('--models', default=','.join(('cnn_3',) + MODERN_MODELS),
                        help='comma-separated deep models (default: cnn_3 and every modern)')
    parser.add_argument('--device', default='cpu', help="'cpu' or 'cuda'")
    parser.add_argument('--threads', type=int, default=1, help='torch threads per fit (1)')
    args = parser.parse_args()
    from tactex_classify.evaluation.cross_validation import splits

    started = time.monotonic()
    dataset = load_or_simulate(args.data, args.sweeps)
    digest = hashlib.sha256(dataset.X.tobytes()).hexdigest()[:16]
    folds = splits(dataset, 'grouped', args.folds, args.seed)
    key = {'dataset': digest, 'folds': args.folds, 'epochs': args.epochs, 'seed': args.seed,
           'device': args.device}
    args.out.mkdir(parents=True, exist_ok=True)
    json_path = args.out / 'architectures.json'
    kept = _kept(json_path, key)
    wanted = [name.strip() for name in args.models.split(',') if name.strip()]
    rows = []
    for name in wanted + [name for name in REFERENCES if name not in wanted]:
        if name in kept:
            rows.append(kept[name])
            print(f'{name}: kept from an earlier run', flush=True)
            continue
        config = configuration(name, args.epochs, args.seed, args.threads)
        results = []
        for index, (train, test) in enumerate(folds, start=1):
            results.append(run_fold(config, dataset, train, test, device=args.device))
            last = results[-1]
            print(f'[{time.monotonic() - started:7.0f} s] {name:26s} fold {index}: '
                  f'{100 * last["accuracy"]:5.1f} %, {last["seconds"]:.0f} s', flush=True)
        accuracies = [fold['accuracy'] for fold in results]
        rows.append({'name': name, 'kind': 'baseline' if isinstance(config, str) else 'deep',
                     'config': config if isinstance(config, str) else dataclasses.asdict(config),
                     'accuracy': float(np.mean(accuracies)), 'sd': float(np.std(accuracies)),
                     'not_converged': not_converged(results),
                     'inference_ms': inference_ms(config, dataset, folds[0][0], args.device),
                     'folds': results})
        summary = _summary(key, dataset, rows, kept)
        json_path.write_text(json.dumps(summary, indent=1) + '\n', encoding='utf-8')
    keep(args.out, 'architectures', _summary(key, dataset, rows, kept), markdown, plot)
    print(f'{time.monotonic() - started:.0f} s')
    return 0


if __name__ == '__main__':
    sys.exit(main())
