# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Calibrated probabilities: temperature scaling, and how far from calibrated a model is.

Temperature scaling (Guo et al. 2017, "On calibration of modern neural networks", ICML)
divides the log probabilities by one temperature T before the softmax; T is fitted to
minimise the negative log likelihood of out-of-fold predictions (grouped by recording,
so no sweep calibrates itself). The expected calibration error is the mean gap between
confidence and accuracy over equal-width confidence bins, weighted by their counts
(Naeini et al. 2015); `reliability` gives the bins for the reliability plot.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tactex_classify.identification.posterior import normalised
from tactex_classify.online.evidence import log_probabilities

LOG_TEMPERATURE_RANGE = (np.log(0.05), np.log(20.0))
GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


def _checked(probabilities, labels) -> tuple[np.ndarray, np.ndarray]:
    probabilities = np.asarray(probabilities, dtype=float)
    labels = np.asarray(labels)
    if probabilities.ndim != 2 or len(probabilities) == 0:
        raise ValueError(f'probabilities must be (samples, classes) with samples, got shape '
                         f'{probabilities.shape}')
    if not np.all(np.isfinite(probabilities)) or np.any(probabilities < 0.0):
        raise ValueError('probabilities must be finite and >= 0')
    if labels.shape != (len(probabilities),) or not np.issubdtype(labels.dtype, np.integer) \
            or np.any(labels < 0) or np.any(labels >= probabilities.shape[1]):
        raise ValueError('labels must be one class index per row of probabilities')
    return probabilities, labels


def calibrated(probabilities, temperature: float) -> np.ndarray:
    """Probabilities with their logarithms divided by `temperature`, normalised again."""
    return np.exp(normalised(log_probabilities(np.asarray(probabilities, dtype=float))
                             / temperature))


def _negative_log_likelihood(logs: np.ndarray, labels: np.ndarray, temperature: float) -> float:
    scaled = normalised(logs / temperature)
    return float(-np.mean(scaled[np.arange(len(labels)), labels]))


def fit_temperature(probabilities, labels, iterations: int = 60) -> float:
    """The temperature in [0.05, 20] minimising the out-of-fold negative log likelihood.

    Golden-section search on log T (the likelihood is unimodal in it).

    Raises:
        ValueError: probabilities that are not a finite non-negative (samples, classes)
            array, or labels that are not one class index per row.
    """
    probabilities, labels = _checked(probabilities, labels)
    logs = log_probabilities(probabilities)
    low, high = LOG_TEMPERATURE_RANGE
    for _ in range(iterations):
        left, right = high - GOLDEN * (high - low), low + GOLDEN * (high - low)
        if _negative_log_likelihood(logs, labels, np.exp(left)) <= \
                _negative_log_likelihood(logs, labels, np.exp(right)):
            high = right
        else:
            low = left
    return float(np.exp((low + high) / 2.0))


@dataclass(frozen=True)
class Reliability:
    """Confidence against accuracy in equal-width bins of the top probability.

    Attributes:
        edges: bins + 1 bin edges from 0 to 1.
        confidence: mean top probability per bin (NaN where the bin is empty).
        accuracy: share of top guesses right per bin (NaN where empty).
        counts: samples per bin.
        error: the expected calibration error, 0 (calibrated) to 1.
    """

    edges: np.ndarray
    confidence: np.ndarray
    accuracy: np.ndarray
    counts: np.ndarray
    error: float


def reliability(probabilities, labels, bins: int = 10) -> Reliability:
    """The reliability bins and the expected calibration error of normalised predictions.

    Raises:
        ValueError: as `fit_temperature`, or bins < 1.
    """
    probabilities, labels = _checked(probabilities, labels)
    if bins < 1:
        raise ValueError(f'bins must be >= 1, got {bins!r}')
    total = probabilities.sum(axis=1, keepdims=True)
    shares = np.divide(probabilities, total, out=np.full_like(probabilities,
                       1.0 / probabilities.shape[1]), where=total > 0)
    top = shares.max(axis=1)
    right = (np.argmax(shares, axis=1) == labels).astype(float)
    edges = np.linspace(0.0, 1.0, bins + 1)
    which = np.clip(np.digitize(top, edges[1:-1], right=True), 0, bins - 1)
    counts = np.bincount(which, minlength=bins)
    with np.errstate(invalid='ignore', divide='ignore'):
        confidence = np.bincount(which, weights=top, minlength=bins) / counts
        accuracy = np.bincount(which, weights=right, minlength=bins) / counts
    gaps = np.where(counts > 0, np.abs(confidence - accuracy), 0.0)
    return Reliability(edges, confidence, accuracy, counts,
                       float(np.sum(gaps * counts) / len(labels)))
