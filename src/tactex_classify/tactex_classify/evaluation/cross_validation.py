# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Cross-validation as the original did it (leaky) and as it should be done (grouped).

`stratified`: window-level stratified k-fold, the original's scheme; overlapping windows
of one recording land on both sides, so it overstates accuracy ("leaky"). `grouped`:
stratified group k-fold by recording, so no recording is on both sides. Metrics come
from the confusion matrix summed over folds; the sequence-level decision sums the
log-probabilities of consecutive windows of a test recording.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
import time
import warnings

import numpy as np
from sklearn.model_selection import StratifiedGroupKFold, StratifiedKFold

from tactex_classify.data.dataset import Dataset
from tactex_classify.models.registry import SCHEMES
from tactex_classify.online.evidence import log_probabilities


@dataclass
class CrossValidation:
    """Out-of-fold predictions of every window and what happened per fold."""

    scheme: str
    proba: np.ndarray  # (n, classes), each window predicted by the fold that held it out
    fold: np.ndarray  # (n,) fold of each window
    histories: list[list[dict]] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)


def splits(dataset: Dataset, scheme: str, folds: int, seed: int):
    """Train/test index pairs of a scheme (grouped keeps recordings whole).

    scikit-learn's warning that a class has fewer members (windows) than folds is left
    out: what it means for a fold is noted per fold instead, by `cross_validate` (a class
    absent from its training or test windows) and tactex compare (from its training).
    """
    if scheme not in SCHEMES:
        raise ValueError(f'unknown scheme {scheme!r}; known: {", ".join(SCHEMES)}')
    with warnings.catch_warnings():
        warnings.filterwarnings('ignore', 'The least populated class in y has only',
                                UserWarning)
        if scheme == 'stratified':
            return list(StratifiedKFold(folds, shuffle=True, random_state=seed).split(
                dataset.X[:, 0, 0], dataset.y))
        return list(StratifiedGroupKFold(folds, shuffle=True, random_state=seed).split(
            dataset.X[:, 0, 0], dataset.y, dataset.trial))


def classes_absent(dataset: Dataset, indices: np.ndarray) -> list[str]:
    """The classes none of the windows at `indices` belong to, in the dataset's order."""
    present = set(dataset.y[indices].tolist())
    return [name for label, name in enumerate(dataset.classes) if label not in present]


def cross_validate(dataset: Dataset, make: Callable[[], object], scheme: str, *,
                   folds: int = 5, seed: int = 0,
                   progress: Callable[[str], None] = lambda line: None) -> CrossValidation:
    """Fit a fresh estimator per fold, predict its held-out windows."""
    recordings = len(np.unique(dataset.trial))
    if scheme == 'grouped' and recordings < folds:
        raise ValueError(f'grouped {folds}-fold needs at least {folds} recordings, the '
                         f'dataset has {recordings}')
    result = CrossValidation(scheme, np.zeros((len(dataset.y), len(dataset.classes))),
                             np.full(len(dataset.y), -1))
    for index, (train, test) in enumerate(splits(dataset, scheme, folds, seed)):
        absent, untested = classes_absent(dataset, train), classes_absent(dataset, test)
        if absent:
            result.notes.append(f'{scheme} fold {index + 1}: classes {absent} absent from '
                                'training')
        if untested:
            result.notes.append(f'{scheme} fold {index + 1}: classes {untested} absent from '
                                'test')
        progress(f'{scheme} fold {index + 1}/{folds}: {len(train)} training windows, '
                 f'{len(test)} test windows')
        estimator = make()
        estimator.fit(dataset.X[train], dataset.y[train], dataset.classes,
                      groups=dataset.trial[train], channels=dataset.channels)
        result.proba[test] = estimator.predict_proba(dataset.X[test])
        result.fold[test] = index
        right = np.mean(result.proba[test].argmax(axis=1) == dataset.y[test])
        progress(f'{scheme} fold {index + 1}/{folds}: accuracy {100 * right:.1f} % on the '
                 f'{len(test)} held-out windows')
        result.histories.append(getattr(estimator, 'history_', []))
    return result


def confusion(y_true: np.ndarray, y_pred: np.ndarray, classes: int) -> np.ndarray:
    """Counts[true, predicted]."""
    matrix = np.zeros((classes, classes), dtype=np.int64)
    np.add.at(matrix, (y_true, y_pred), 1)
    return matrix


def metrics(matrix: np.ndarray, names: list[str]) -> dict:
    """Accuracy, macro precision/recall/F1 and per-class precision/recall from counts."""
    true_positive = np.diag(matrix).astype(float)
    predicted = matrix.sum(axis=0).astype(float)
    actual = matrix.sum(axis=1).astype(float)
    precision = np.divide(true_positive, predicted, out=np.zeros_like(true_positive),
                          where=predicted > 0)
    recall = np.divide(true_positive, actual, out=np.zeros_like(true_positive),
                       where=actual > 0)
    f1 = np.divide(2 * precision * recall, precision + recall,
                   out=np.zeros_like(precision), where=(precision + recall) > 0)
    present = actual > 0
    return {'accuracy': float(true_positive.sum() / max(matrix.sum(), 1)),
            'macro_precision': float(precision[present].mean()),
            'macro_recall': float(recall[present].mean()),
            'macro_f1': float(f1[present].mean()),
            'per_class': {name: {'precision': float(p), 'recall': float(r), 'support': int(s)}
                          for name, p, r, s in zip(names, precision, recall, actual,
                                                   strict=True)}}


def sequence_accuracy(dataset: Dataset, proba: np.ndarray) -> dict[int, dict]:
    """Accuracy of deciding a recording from k consecutive windows (summed log-probs).

    For k = 1, 2, 4, ... up to the longest recording, every run of k consecutive
    windows of every recording is one decision. Only recordings of at least k windows
    count, so each k also gives how many (`recordings`) and of how many classes
    (`classes`): a row that lost a class is not comparable with the rows before it.
    """
    log_proba = log_probabilities(proba)
    per_recording = []
    for trial in np.unique(dataset.trial):
        members = np.flatnonzero(dataset.trial == trial)
        members = members[np.argsort(dataset.t0[members], kind='stable')]
        per_recording.append((log_proba[members], int(dataset.y[members[0]])))
    longest = max(len(lp) for lp, _ in per_recording)
    result = {}
    k = 1
    while k <= longest:
        correct = total = 0
        long_enough = [(lp, label) for lp, label in per_recording if len(lp) >= k]
        for lp, label in long_enough:
            cumulative = np.cumsum(np.vstack([np.zeros(lp.shape[1]), lp]), axis=0)
            sums = cumulative[k:] - cumulative[:-k]
            correct += int(np.sum(sums.argmax(axis=1) == label))
            total += len(sums)
        result[k] = {'accuracy': correct / total, 'recordings': len(long_enough),
                     'classes': len({label for _, label in long_enough})}
        k *= 2
    return result


def decision_measures(decisions: list[tuple[bool, float, float]]) -> dict:
    """Accuracy, median contact seconds, earliness and TEASER's harmonic mean of decisions.

    Args:
        decisions: one (correct, contact seconds at the decision, earliness) per sweep;
            earliness is the share of the sweep's windowed contact used (0..1).

    Returns:
        accuracy, median_contact_s, earliness (mean), harmonic_mean of accuracy and
        1 - earliness (Schafer & Leser 2020), and the number of sweeps.
    """
    correct = np.array([d[0] for d in decisions], float)
    contact = np.array([d[1] for d in decisions])
    earliness = np.array([d[2] for d in decisions])
    accuracy, early = float(correct.mean()), float(earliness.mean())
    harmonic = 2 * accuracy * (1 - early) / (accuracy + 1 - early) if accuracy + 1 - early \
        else 0.0
    return {'accuracy': accuracy, 'median_contact_s': float(np.median(contact)),
            'earliness': early, 'harmonic_mean': harmonic, 'sweeps': len(decisions)}


def decide_recordings(dataset: Dataset, proba_of: Callable[[int], np.ndarray],
                      threshold: float, rate_hz: float) -> list[dict]:
    """The live node's decision on each recording, its windows fed in time order.

    Each recording's windows go to the same `Evidence` the live node uses until an
    estimate meets `threshold`; without one, the last estimate is the decision (made at
    the end of contact, as TEASER forces one).

    Args:
        dataset: the windows (`t0` orders them; `y` gives the truth).
        proba_of: window index -> its class probabilities (computed on demand).
        threshold: the decision threshold.
        rate_hz: the sampling rate (a window covers its samples' periods).

    Returns:
        Per recording: correct, contact_s at the decision, earliness (the share of the
        recording's windowed contact used) and wall_s (time spent on its windows).
    """
    from tactex_classify.online.evidence import Evidence, EvidenceSettings, union_seconds
    period_ns = int(round(1e9 / rate_hz))
    span_ns = (dataset.X.shape[1] - 1) * period_ns
    settings = EvidenceSettings(threshold=threshold)
    starts_ns = np.round(dataset.t0 * 1e9).astype(np.int64)
    decisions = []
    for trial in np.unique(dataset.trial):
        members = np.flatnonzero(dataset.trial == trial)
        members = members[np.argsort(starts_ns[members], kind='stable')]
        evidence = Evidence(len(dataset.classes), period_ns, settings)
        began = time.perf_counter()
        for index in members:
            estimate = evidence.add(proba_of(index), starts_ns[index],
                                    starts_ns[index] + span_ns)
            if estimate.decided:
                break
        wall = time.perf_counter() - began
        total = union_seconds([(starts_ns[i], starts_ns[i] + span_ns + period_ns)
                               for i in members])
        decisions.append({'correct': estimate.class_id == int(dataset.y[members[0]]),
                          'contact_s': estimate.contact_seconds,
                          'earliness': min(1.0, estimate.contact_seconds / total),
                          'wall_s': wall})
    return decisions


def threshold_decisions(dataset: Dataset, proba: np.ndarray, threshold: float,
                        rate_hz: float) -> dict:
    """`decision_measures` of the live rule at `threshold` on out-of-fold probabilities."""
    decisions = decide_recordings(dataset, proba.__getitem__, threshold, rate_hz)
    return decision_measures([(d['correct'], d['contact_s'], d['earliness'])
                              for d in decisions])
