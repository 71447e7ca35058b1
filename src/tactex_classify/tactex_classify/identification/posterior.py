# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The belief over textures, in log space, and its tempered update after one movement.

After a movement whose model (calibrated, out of fold) gives class probabilities q, the
log posterior gains tau * log q(k) - log Z(k) for every texture k, and is normalised
again. The movements are taken as independent given the texture; the exponent tau (one,
fitted by `tempering`) keeps that assumption from making the belief overconfident. Z(k)
is what the movement's model gives texture k on average over its out-of-fold sweeps (the
mean of q(k)^tau, each true texture weighted alike), so a model that favours a texture
whatever it touches adds no evidence for it, and a movement whose outputs never depend
on the texture leaves the belief where it was. Probabilities are floored as the live
evidence floors them (`online.evidence.log_probabilities`): a zero never vetoes a
texture, so one confidently wrong sweep costs a bounded number of nats that later sweeps
can repay.
"""

import numpy as np

from tactex_classify.online.evidence import log_probabilities


def log_sum_exp(values: np.ndarray, axis: int = -1) -> np.ndarray:
    """log(sum(exp(values))) along `axis`, without overflow (finite values expected)."""
    peak = np.max(values, axis=axis, keepdims=True)
    return np.squeeze(peak, axis=axis) + np.log(np.sum(np.exp(values - peak), axis=axis))


def normalised(log_weights: np.ndarray) -> np.ndarray:
    """Log weights shifted so that their exponentials sum to one (along the last axis)."""
    return log_weights - log_sum_exp(log_weights)[..., None]


def uniform(classes: int) -> np.ndarray:
    """The log of the uniform belief over `classes` textures."""
    return np.full(classes, -np.log(classes))


def entropy(log_posterior: np.ndarray) -> np.ndarray:
    """Entropy in nats of normalised log posteriors (along the last axis)."""
    probability = np.exp(log_posterior)
    return -np.sum(np.where(probability > 0.0, probability * log_posterior, 0.0), axis=-1)


def divergence(log_after: np.ndarray, log_before: np.ndarray) -> np.ndarray:
    """KL(after || before) in nats between normalised log beliefs, along the last axis (>= 0)."""
    after = np.exp(log_after)
    return np.maximum(np.sum(np.where(after > 0.0, after * (log_after - log_before), 0.0),
                             axis=-1), 0.0)


def checked_probabilities(probabilities, classes: int) -> np.ndarray:
    """One model answer as a float vector of `classes` finite values >= 0.

    Raises:
        ValueError: another shape, a NaN, an infinity or a negative value.
    """
    vector = np.asarray(probabilities, dtype=float)
    if vector.shape != (classes,):
        raise ValueError(f'expected {classes} class probabilities, got shape {vector.shape}')
    if not np.all(np.isfinite(vector)) or np.any(vector < 0.0):
        raise ValueError(f'class probabilities must be finite and >= 0, got {vector}')
    return vector


def tempered_log_likelihoods(probabilities: np.ndarray, tempering: float) -> np.ndarray:
    """The terms tau * log q, q floored: the update's term before the movement's normaliser."""
    return tempering * log_probabilities(probabilities)


def updated(log_posterior: np.ndarray, log_likelihood: np.ndarray) -> np.ndarray:
    """The normalised log posterior after adding one movement's log likelihood."""
    return normalised(log_posterior + log_likelihood)
