# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""MultiRocket's four poolings and HYDRA's competing counts, on outputs worked out by hand."""

import numpy as np
import pytest
from support.toy_windows import CLASSES, toy

from tactex_classify.models.hydra import (
    channels_per_group,
    competing_counts,
    hydra_dilations,
    HydraRidge,
)
from tactex_classify.models.multirocket import MultiRocketRidge, pooled


def test_the_four_poolings_of_a_known_output():
    # One kernel, one window of 8 steps, bias 0: positive at 1, 2, 3 and 6.
    outputs = np.array([[[-1.0, 2.0, 4.0, 1.0, -3.0, 0.0, 6.0, -2.0]]])
    ppv, mpv, mipv, lspv = pooled(outputs, np.zeros((1, 1)))[0]
    assert ppv == pytest.approx(4 / 8)
    assert mpv == pytest.approx((2 + 4 + 1 + 6) / 4)
    assert mipv == pytest.approx((1 + 2 + 3 + 6) / 4 / 8)
    assert lspv == pytest.approx(3 / 8)


def test_a_window_with_no_positive_value_pools_to_the_papers_defaults():
    ppv, mpv, mipv, lspv = pooled(-np.ones((1, 1, 5)), np.zeros((1, 1)))[0]
    assert (ppv, mpv, mipv, lspv) == (0.0, 0.0, -1.0, 0.0)


def test_a_bias_shifts_what_counts_as_positive():
    outputs = np.array([[[1.0, 2.0, 3.0, 4.0]]])
    features = pooled(outputs, np.array([[2.5, 0.0]])).reshape(2, 4)
    assert features[0, 0] == pytest.approx(0.5) and features[0, 1] == pytest.approx(1.0)
    assert features[1, 0] == pytest.approx(1.0) and features[1, 3] == pytest.approx(1.0)


def test_hydra_counts_the_winner_of_each_step_softly_and_the_loser_hard():
    # One group of two kernels reading one channel: +x (centre tap) and -x.
    weights = np.zeros((1, 2, 1, 9))
    weights[0, 0, 0, 4], weights[0, 1, 0, 4] = 1.0, -1.0
    series = np.array([[[2.0], [-1.0], [3.0], [-4.0]]])
    soft_plus, hard_plus, soft_minus, hard_minus = competing_counts(
        series, 1, weights, np.array([[0]]))[0]
    assert soft_plus == pytest.approx(2 + 3) and soft_minus == pytest.approx(1 + 4)
    assert hard_plus == 2 and hard_minus == 2  # the loser of each step, counted once
    assert hard_plus + hard_minus == series.shape[1]


def test_hydra_dilations_and_channel_reads_follow_the_window_and_the_channels():
    assert hydra_dilations(128).tolist() == [1, 2, 4, 8]
    assert hydra_dilations(9).tolist() == [1] and hydra_dilations(2).tolist() == [1]
    assert [channels_per_group(c) for c in (1, 2, 3, 10, 40)] == [1, 1, 2, 5, 8]


def test_each_channel_of_a_hydra_kernel_sums_to_zero_so_its_level_is_ignored():
    data = toy()
    weights = HydraRidge(seed=1).fit(data.X, data.y, CLASSES).hydra_weights_
    np.testing.assert_allclose(weights.sum(axis=-1), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.abs(weights).sum(axis=-1), 1.0)


@pytest.mark.parametrize('make', [MultiRocketRidge, HydraRidge])
def test_the_random_kernel_baselines_reproduce_from_a_seed_and_refuse_one_sample(make):
    data = toy()
    first = make(seed=4).fit(data.X, data.y, CLASSES).predict_proba(data.X[:5])
    second = make(seed=4).fit(data.X, data.y, CLASSES).predict_proba(data.X[:5])
    np.testing.assert_array_equal(first, second)
    np.testing.assert_allclose(first.sum(axis=1), 1.0)
    with pytest.raises(ValueError, match='at least 2 samples'):
        make().fit(data.X[:, :1], data.y, CLASSES)
