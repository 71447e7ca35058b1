# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Training cost on this machine's CPU: the loop before and after, threads against cells.

1. Epochs/s of each of the eight models through `DeepClassifier.fit` as it was before
   the comparison work (classifier.py at commit BEFORE, read from git) and as it is now,
   in the same run, alternating which goes first, on one training fold of the 128-sample
   synthetic set (or random windows of its shape); the final weights of both are
   compared bit for bit (the same training, only faster or not).
2. Two cores: one cell with 1 thread, one cell with 2 threads, and two cells at once
   with 1 thread each (two processes), as epochs/s summed over the cells running.
3. Evaluation overhead: the time to classify the test fold and, with early stopping,
   the held-out recordings each epoch, against an epoch of training.

Writes bench/results/training.md and bench/results/training.json.
"""

import argparse
import importlib.util
import json
import os
from pathlib import Path
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np

RESULTS = Path(__file__).parent / 'results'
ROOT = Path(__file__).resolve().parents[1]
BEFORE = '753bc03'  # main before `tactex compare`: the training loop as it was
CLASSIFIER = 'src/tactex_classify/tactex_classify/classifier.py'  # its path at BEFORE
MODELS = ('cnn_bilstm_1', 'cnn_bilstm_2', 'cnn_bilstm_3', 'cnn_1', 'cnn_2', 'cnn_3',
          'bilstm_1', 'bilstm_2')
# One epoch of each configuration in a child process (its own threads, its own clock).
CHILD = """
import json, sys, time
import numpy as np
from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
model, threads, path = sys.argv[1], int(sys.argv[2]), sys.argv[3]
with np.load(path) as arrays:
    X, y = arrays['X'], arrays['y']
classifier = DeepClassifier(TrainingConfig(model=model, epochs=1, threads=threads))
start = time.perf_counter()
classifier.fit(X, y, [str(c) for c in range(12)])
print(json.dumps({'seconds': time.perf_counter() - start}))
"""


def old_classifier():
    """classifier.py as of BEFORE, imported under another name."""
    source = subprocess.run(['git', 'show', f'{BEFORE}:{CLASSIFIER}'], cwd=ROOT, check=True,
                            capture_output=True, text=True).stdout
    # The architectures it imports moved since (the same code, a new module path).
    source = source.replace('from tactex_classify.models import',
                            'from tactex_classify.models.architectures import')
    folder = Path(tempfile.mkdtemp(prefix='tactex-before-'))
    (folder / 'classifier_before.py').write_text(source, encoding='utf-8')
    spec = importlib.util.spec_from_file_location('classifier_before',
                                                  folder / 'classifier_before.py')
    module = importlib.util.module_from_spec(spec)
    sys.modules['classifier_before'] = module
    spec.loader.exec_module(module)
    return module


def training_fold(data: Path | None) -> tuple[np.ndarray, np.ndarray, str]:
    """The first grouped training fold of the synthetic set, or random windows like it."""
    if data is None:
        rng = np.random.default_rng(0)
        return (rng.normal(size=(3120, 128, 10)).astype(np.float32),
                rng.integers(0, 12, 3120), 'random windows, 3120 x 128 x 10')
    from tactex_classify.data.dataset import Dataset
    from tactex_classify.evaluation.cross_validation import splits
    dataset = Dataset.load(data)
    train, _ = splits(dataset, 'grouped', 5, 0)[0]
    return dataset.X[train], dataset.y[train], f'{data.name}, grouped fold 1 of 5: ' \
        f'{len(train)} windows x {dataset.X.shape[1]} x {dataset.X.shape[2]}'


def loop_before_after(X, y, models) -> list[dict]:
    """Epochs/s of the old and the new loop per model, and whether the weights agree."""
    import torch

    from tactex_classify.training import deep_classifier as after
    before = old_classifier()
    classes = [str(c) for c in range(12)]
    rows = []
    for index, model in enumerate(models):
        timed, weights = {}, {}
        order = (('before', before), ('after', after))
        for name, module in order if index % 2 == 0 else order[::-1]:
            fitted = module.DeepClassifier(module.TrainingConfig(model=model, epochs=1))
            start = time.perf_counter()
            fitted.fit(X, y, classes)
            timed[name] = time.perf_counter() - start
            weights[name] = fitted.model_.state_dict()
        same = all(torch.equal(weights['before'][k], weights['after'][k])
                   for k in weights['before'])
        rows.append({'model': model, 'before_epochs_per_s': 1 / timed['before'],
                     'after_epochs_per_s': 1 / timed['after'],
                     'speedup': timed['before'] / timed['after'], 'same_weights': same})
        print(f'{model:<13} before {1 / timed["before"]:.4f} epochs/s, after '
              f'{1 / timed["after"]:.4f} ({timed["before"] / timed["after"]:.2f}x), same '
              f'weights: {same}', flush=True)
    return rows


def parallel(X, y, models) -> list[dict]:
    """Epochs/s summed over cells: 1 cell x 1 thread, 1 x 2 threads, 2 cells x 1 thread."""
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / 'fold.npz'
        np.savez(path, X=X, y=y)
        env = {**os.environ, 'OMP_WAIT_POLICY': 'PASSIVE'}
        for model in models:
            row = {'model': model}
            for label, threads, cells in (('1 cell x 1 thread', 1, 1),
                                          ('1 cell x 2 threads', 2, 1),
                                          ('2 cells x 1 thread', 1, 2)):
                children = [subprocess.Popen([sys.executable, '-c', CHILD, model, str(threads),
                                              str(path)], stdout=subprocess.PIPE, text=True,
                                             env=env) for _ in range(cells)]
                seconds = [json.loads(child.communicate()[0])['seconds'] for child in children]
                row[label] = sum(1 / s for s in seconds)
                print(f'{model:<13} {label}: {row[label]:.4f} epochs/s', flush=True)
            rows.append(row)
    return rows


def evaluation_overhead(X, y, model: str) -> dict:
    """Seconds to classify a test fold (a quarter of the training windows) and one epoch."""
    from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
    classifier = DeepClassifier(TrainingConfig(model=model, epochs=1))
    start = time.perf_counter()
    classifier.fit(X, y, [str(c) for c in range(12)])
    epoch_s = time.perf_counter() - start
    test = X[:len(X) // 4]
    start = time.perf_counter()
    classifier.predict_proba(test)
    predict_s = time.perf_counter() - start
    return {'model': model, 'epoch_s': epoch_s, 'test_windows': len(test),
            'predict_s': predict_s, 'validation_share': predict_s * 0.4 / epoch_s}


def main() -> int:
    """Measure, print, and keep the results."""
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument('--data', type=Path, help='the 128-sample synthetic set (.npz)')
    parser.add_argument('--models', nargs='+', default=list(MODELS))
    parser.add_argument('--parallel-models', nargs='+', default=['cnn_3', 'cnn_bilstm_2'])
    args = parser.parse_args()
    X, y, described = training_fold(args.data)
    load = os.getloadavg()
    loop = loop_before_after(X, y, args.models)
    cells = parallel(X, y, args.parallel_models)
    overhead = evaluation_overhead(X, y, 'cnn_3')
    record = {'data': described, 'before_commit': BEFORE, 'loop': loop, 'parallel': cells,
              'evaluation': overhead, 'cpus': os.cpu_count(), 'machine': platform.machine(),
              'load_before': load, 'load_after': os.getloadavg()}
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / 'training.json').write_text(json.dumps(record, indent=2) + '\n',
                                           encoding='utf-8')
    lines = ['# Training cost on the CPU (bench/bench_training.py)', '',
             f'Data: {described}. {os.cpu_count()} cores shared with other work (load average '
             f'{load[0]:.1f} at the start, {record["load_after"][0]:.1f} at the end).', '',
             f'| model | epochs/s before ({BEFORE}) | epochs/s after | after / before | same '
             'weights |', '|---|---|---|---|---|']
    lines += [f'| {r["model"]} | {r["before_epochs_per_s"]:.4f} | {r["after_epochs_per_s"]:.4f} '
              f'| {r["speedup"]:.2f}x | {"yes" if r["same_weights"] else "no"} |' for r in loop]
    labels = ('1 cell x 1 thread', '1 cell x 2 threads', '2 cells x 1 thread')
    lines += ['', '| model | ' + ' | '.join(f'{label} (epochs/s)' for label in labels)
              + ' | 2 cells / 1 cell x 2 threads |', '|---|---|---|---|---|']
    lines += [f'| {r["model"]} | ' + ' | '.join(f'{r[label]:.4f}' for label in labels)
              + f' | {r[labels[2]] / r[labels[1]]:.2f}x |' for r in cells]
    lines += ['', f'Evaluation ({overhead["model"]}): classifying {overhead["test_windows"]} '
              f'test windows takes {overhead["predict_s"]:.2f} s against '
              f'{overhead["epoch_s"]:.1f} s for an epoch; checking held-out recordings each '
              'epoch (early stopping, 10 % of the recordings) adds about '
              f'{100 * overhead["validation_share"]:.1f} % to an epoch.', '']
    (RESULTS / 'training.md').write_text('\n'.join(lines), encoding='utf-8')
    print('\n'.join(lines))
    return 0


if __name__ == '__main__':
    sys.exit(main())
