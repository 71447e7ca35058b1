# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Sections 1 and 2: contact time and compute time against grouped-CV accuracy.

One simulated dataset (`tactex_sim.collect` of the uneven-texture scene, converted at
every window length with hop half a window) serves both. Section 1 cross-validates each
model at each window (grouped by recording) and scores two ways of deciding from the
out-of-fold probabilities: a fixed number of consecutive windows (summed
log-probabilities, `evaluate.sequence_accuracy`) and the live node's threshold rule
replayed through its own `Evidence` (`evaluate.threshold_decisions`). Section 2 times
training on every window and the per-window latency of the trained checkpoint in each
runtime (torch/numpy/scikit-learn and onnxruntime).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
import statistics
import time

import numpy as np

from tactex.accuracy_time.sizes import Size
from tactex_classify.models.registry import BASELINES

THRESHOLDS = (0.5, 0.7, 0.9, 0.99, 0.999, 0.9999, 1 - 1e-6, 1.0)
SCHEME = 'grouped'


@dataclass
class Data:
    """The section's bags and a dataset per window."""

    bags: Path
    datasets: dict
    rate_hz: float
    collect_s: float


def make_estimator(model: str, size: Size, *, seed: int, threads: int):
    """A fresh estimator of `model` (deep models train `size.epochs` epochs)."""
    from tactex_classify.models.baselines import MiniRocketRidge, StatsExtraTrees
    from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
    if model == 'minirocket':
        return MiniRocketRidge(seed=seed)
    if model == 'extratrees':
        return StatsExtraTrees(seed=seed)
    return DeepClassifier(TrainingConfig(model=model, epochs=size.epochs, seed=seed,
                                         threads=threads))


def build_data(scratch: Path, size: Size, log: Callable[[str], None]) -> Data:
    """Collect the sweeps and convert them at every window length of `size`."""
    from tactex_classify.data.dataset import convert
    from tactex_sim.collect import collect
    from tactex_sim.scene import load_scene, resolve_scene
    from tactex_sim.textures import TEXTURES
    scene = load_scene(resolve_scene('uneven_texture'))
    textures = list(TEXTURES)[:size.textures]
    began = time.monotonic()
    collect(scene, size.sweeps, scratch / 'bags', textures=textures,
            progress=lambda line: log(f'  collect {line}'))
    collect_s = time.monotonic() - began
    datasets = {window: convert([scratch / 'bags'], window=window, hop=window // 2,
                                progress=lambda line: None) for window in size.windows}
    for window, data in datasets.items():
        log(f'  window {window}: {len(data.y)} windows of {len(np.unique(data.trial))} '
            'recordings')
    rate = datasets[size.windows[0]].info['sampling_rate_hz']
    return Data(scratch / 'bags', datasets, rate, collect_s)


def contact_time(data: Data, size: Size, log: Callable[[str], None], *, seed: int,
                 threads: int) -> dict:
    """Section 1: per model and window, accuracy against the contact seconds of a decision."""
    from tactex_classify.evaluation.cross_validation import (
        cross_validate,
        sequence_accuracy,
        threshold_decisions,
    )
    from tactex_classify.evaluation.training_report import convergence_notes
    points, runs, skipped = [], {}, []
    for window, dataset in data.datasets.items():
        hop = window // 2
        for model in size.models:
            if not fits(model, window, len(dataset.channels)):
                skipped.append(f'{model} at window {window} (too short for its layers)')
                log(f'  {model}, window {window}: skipped, too short for its layers')
                continue
            began = time.monotonic()
            result = cross_validate(dataset, lambda m=model: make_estimator(
                m, size, seed=seed, threads=threads), SCHEME, folds=size.folds, seed=seed)
            cv_s = time.monotonic() - began
            accuracy = float(np.mean(result.proba.argmax(axis=1) == dataset.y))
            # A deep model whose training loss was still falling, or never left chance.
            unconverged = bool(convergence_notes(result, len(dataset.classes), size.epochs))
            runs[run_key(model, window)] = {'accuracy': accuracy, 'cv_s': cv_s,
                                            'not_converged': unconverged}
            log(f'  {model}, window {window}: window accuracy {100 * accuracy:.1f} % '
                f'({cv_s:.0f} s)' + (', not converged' if unconverged else ''))
            for k, sequence in sequence_accuracy(dataset, result.proba).items():
                if sequence['classes'] < len(dataset.classes):
                    break  # fewer classes than the rows before: not comparable with them
                value = sequence['accuracy']
                points.append({'model': model, 'window': window, 'not_converged': unconverged,
                               'rule': f'{k} window{"s" * (k > 1)}',
                               'windows': k, 'threshold': None,
                               'contact_s': (window + (k - 1) * hop) / data.rate_hz,
                               'accuracy': value, 'earliness': None, 'harmonic_mean': None})
            for threshold in THRESHOLDS:
                measures = threshold_decisions(dataset, result.proba, threshold, data.rate_hz)
                points.append({'model': model, 'window': window, 'not_converged': unconverged,
                               'rule': f'posterior > {threshold:.10g}' if threshold < 1
                               else 'whole contact (threshold 1)', 'windows': None,
                               'threshold': threshold,
                               'contact_s': measures['median_contact_s'],
                               'accuracy': measures['accuracy'],
                               'earliness': measures['earliness'],
                               'harmonic_mean': measures['harmonic_mean']})
    mark_pareto(points)
    return {'points': points, 'runs': runs, 'skipped': skipped}


def fits(model: str, window: int, channels: int) -> bool:
    """`model` takes windows of `window` samples (pooling deep models need a minimum)."""
    if model in BASELINES:
        return True
    from tactex_classify.models.architectures import MODELS
    try:
        MODELS[model](window, channels, 2)
    except ValueError:
        return False
    return True


def run_key(model: str, window: int) -> str:
    """The key of a model's cross-validation at a window in section 1's `runs`."""
    return f'{model}, window {window}'


def mark_pareto(points: list[dict]) -> None:
    """Set `pareto` on every point: no other point is as fast and more accurate (or both).

    A point of a model that did not converge is never ranked, so never on the front.
    """
    from tactex_classify.evaluation.grid_report import pareto_front
    ranked = [point for point in points if not point.get('not_converged')]
    front = {id(point) for point in pareto_front(
        ranked, lambda point: (point['contact_s'], point['accuracy']))}
    for point in points:
        point['pareto'] = id(point) in front


def compute_time(data: Data, section1: dict, size: Size, scratch: Path,
                 log: Callable[[str], None], *, seed: int, threads: int) -> dict:
    """Section 2: training time on every window and per-window latency in each runtime."""
    from tactex_classify.models.checkpoint import read_checkpoint
    from tactex_classify.online.runtime import export_onnx, load_predictor, ONNX_KINDS
    window = 128 if 128 in size.windows else size.windows[len(size.windows) // 2]
    dataset = data.datasets[window]
    rows = []
    for model in size.models:
        estimator = make_estimator(model, size, seed=seed, threads=threads)
        began = time.perf_counter()
        estimator.fit(dataset.X, dataset.y, dataset.classes, groups=dataset.trial,
                      channels=dataset.channels)
        train_s = time.perf_counter() - began
        folder = estimator.save(scratch / 'models' / model, hop=window // 2,
                                sampling_rate_hz=data.rate_hz)
        runtimes = ['native']
        if read_checkpoint(folder).kind in ONNX_KINDS:
            export_onnx(folder)
            runtimes.append('onnxruntime')
        latency = {}
        for runtime in runtimes:
            predictor = load_predictor(folder, runtime, threads=1)
            latency[predictor.runtime] = time_predictor(predictor, dataset.X, size.latency_calls)
        run = section1['runs'][run_key(model, window)]
        rows.append({'model': model, 'window': window, 'deep': model not in BASELINES,
                     'accuracy': run['accuracy'], 'cv_s': run['cv_s'],
                     'not_converged': run.get('not_converged', False),
                     'train_s': train_s, 'windows': len(dataset.y), 'latency': latency})
        log(f'  {model}: trained in {train_s:.1f} s; per window ' + ', '.join(
            f'{name} {1e3 * value["single_s"]:.2f} ms' for name, value in latency.items()))
    return {'window': window, 'rows': rows}


def time_predictor(predictor, windows: np.ndarray, calls: int) -> dict:
    """Median seconds of one single-window call, and per window in batches of 64."""
    single = windows[:1]
    predictor.predict_proba(single)  # warm up (lazy initialisation, caches)
    times = []
    for index in range(calls):
        window = windows[index % len(windows)][None]
        began = time.perf_counter()
        predictor.predict_proba(window)
        times.append(time.perf_counter() - began)
    batch = windows[:64]
    began = time.perf_counter()
    predictor.predict_proba(batch)
    return {'single_s': statistics.median(times),
            'batched_s': (time.perf_counter() - began) / len(batch)}
