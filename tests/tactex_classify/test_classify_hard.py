# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Scaling, softmax and deep-model probabilities under any finite windows and logits."""

import functools

from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
import numpy as np
import pytest
from support.hard_values import anything, finite

from tactex_classify.models.baselines import MiniRocketRidge
from tactex_classify.models.hydra import HydraRidge
from tactex_classify.models.multirocket import MultiRocketRidge
from tactex_classify.models.registry import AUGMENTATIONS
from tactex_classify.models.windows import ChannelScaler, SCALED_LIMIT, SCALINGS, softmax
from tactex_classify.training.convergence import (
    stalled_at_chance,
    still_falling,
    unconverged_because,
)
from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig

pytestmark = pytest.mark.hard_case

float32_finite = st.floats(width=32, allow_nan=False, allow_infinity=False)
windows = hnp.arrays(np.float32, st.tuples(st.integers(1, 4), st.integers(1, 6),
                                           st.integers(1, 3)), elements=float32_finite)


@settings(max_examples=150)
@given(windows, st.sampled_from(SCALINGS))
def test_a_scaler_fitted_on_any_finite_windows_maps_them_into_a_finite_range(X, kind):
    scaler = ChannelScaler(kind).fit(X)
    assert np.all(np.isfinite(scaler.offset)) and np.all(np.array(scaler.scale) > 0)
    scaled = scaler.transform(X)
    assert np.all(np.isfinite(scaled)) and np.all(np.abs(scaled) <= SCALED_LIMIT)
    if kind == 'minmax':
        assert scaled.min() >= -1e-6 and scaled.max() <= 1 + 1e-6


@settings(max_examples=100)
@given(windows, hnp.arrays(np.float32, st.tuples(st.integers(0, 3), st.integers(1, 6),
                                                 st.integers(1, 3)), elements=float32_finite),
       st.sampled_from(SCALINGS))
def test_transforming_any_finite_windows_stays_finite_and_clipped(train, other, kind):
    other = np.resize(other, (len(other), *train.shape[1:]))
    scaled = ChannelScaler(kind).fit(train).transform(other)
    assert scaled.shape == other.shape
    assert np.all(np.isfinite(scaled)) and np.all(np.abs(scaled) <= SCALED_LIMIT)


@given(st.sampled_from([np.nan, np.inf, -np.inf]), st.sampled_from(SCALINGS))
def test_a_scaler_refuses_non_finite_windows(bad, kind):
    X = np.zeros((2, 4, 3), np.float32)
    X[1, 2, 0] = bad
    with pytest.raises(ValueError, match='NaN or inf'):
        ChannelScaler(kind).fit(X)


def test_a_scaler_refuses_no_windows():
    with pytest.raises(ValueError, match='no data'):
        ChannelScaler().fit(np.zeros((0, 4, 3), np.float32))


@settings(max_examples=200)
@given(hnp.arrays(np.float64, st.tuples(st.integers(0, 5), st.integers(1, 6)),
                  elements=finite()))
def test_softmax_of_any_finite_logits_is_a_distribution_keeping_the_winner(logits):
    probabilities = softmax(logits)
    assert probabilities.shape == logits.shape
    assert np.all(np.isfinite(probabilities)) and np.all(probabilities >= 0)
    np.testing.assert_allclose(probabilities.sum(axis=1), 1.0, atol=1e-12)
    if len(logits):
        winners = probabilities[np.arange(len(logits)), logits.argmax(axis=1)]
        np.testing.assert_array_equal(winners, probabilities.max(axis=1))


@given(hnp.arrays(np.float64, st.tuples(st.integers(1, 4), st.integers(1, 5)),
                  elements=anything()).filter(lambda a: not np.all(np.isfinite(a))))
def test_softmax_refuses_non_finite_logits(logits):
    with pytest.raises(ValueError, match='finite'):
        softmax(logits)


SMALL_MODELS = {'cnn_1': lambda: DeepClassifier(TrainingConfig('cnn_1', epochs=1, seed=0)),
                'minirocket': lambda: MiniRocketRidge(dilations=2, biases_per_kernel=2),
                'multirocket': lambda: MultiRocketRidge(dilations=2, biases_per_kernel=2),
                'hydra': lambda: HydraRidge(groups=4, kernels_per_group=4)}


@functools.lru_cache(maxsize=len(SMALL_MODELS))
def _small_model(name: str):
    rng = np.random.default_rng(0)
    X = rng.normal(0.0, 1.0, (24, 64, 3)).astype(np.float32)
    y = np.arange(24) % 3
    return SMALL_MODELS[name]().fit(X, y, ['a', 'b', 'c'], channels=['x', 'y', 'z'])


@settings(max_examples=25)
@given(hnp.arrays(np.float32, st.tuples(st.integers(0, 3), st.just(64), st.just(3)),
                  elements=st.one_of(float32_finite, st.sampled_from(
                      [np.float32(3.4e38), np.float32(-3.4e38), np.float32(1e-45)]))),
       st.sampled_from(sorted(SMALL_MODELS)))
def test_probabilities_of_any_finite_windows_sum_to_one(X, name):
    probabilities = _small_model(name).predict_proba(X)
    assert probabilities.shape == (len(X), 3)
    assert np.all(np.isfinite(probabilities))
    np.testing.assert_allclose(probabilities.sum(axis=1), 1.0, atol=1e-6)


scaled_windows = hnp.arrays(np.float32, st.tuples(st.integers(2, 4), st.integers(2, 9),
                                                  st.integers(1, 3)),
                            elements=st.floats(-SCALED_LIMIT, SCALED_LIMIT, width=32))


@settings(max_examples=60)
@given(scaled_windows, st.sampled_from(AUGMENTATIONS), st.integers(0, 2**31 - 1))
def test_any_augmentation_of_any_scaled_batch_stays_finite_and_bounded(X, name, seed):
    """Training batches are scaled windows (within +-SCALED_LIMIT): none grows or turns NaN."""
    import torch

    from tactex_classify.training.augmentation import augment
    out = augment(torch.from_numpy(X), (name,), torch.Generator().manual_seed(seed))
    assert out.shape == X.shape and bool(torch.isfinite(out).all())
    assert float(out.abs().max()) <= 2 * SCALED_LIMIT


@settings(max_examples=200)
@given(st.lists(anything(), max_size=40), st.integers(0, 1000), st.integers(1, 100))
def test_convergence_verdicts_on_any_losses_are_plain_booleans(losses, classes, epochs):
    # A diverged (inf), broken (NaN) or absurd loss history still gets a verdict, no error.
    for verdict in (still_falling(losses), stalled_at_chance(losses, classes)):
        assert isinstance(verdict, bool)
    assert unconverged_because(losses, classes, epochs) in (
        None, 'stalled at chance', 'still falling')
    if not any(np.isfinite(losses)) and losses and classes >= 2:
        assert stalled_at_chance(losses, classes)  # no finite loss: it learned nothing
