# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Soft voting across window sizes: which short windows lie inside a long one, and the vote."""

import numpy as np
import pytest

from tactex_classify.data.dataset import Dataset
from tactex_classify.evaluation.window_voting import soft_vote, windows_inside

RATE = 100.0


def _cut(window: int, hop: int, trials=(0, 1), length=1024, classes=('a', 'b')) -> Dataset:
    """Windows of `window` samples every `hop` of recordings `length` samples long."""
    starts = np.arange(0, length - window + 1, hop)
    t0 = np.tile(starts / RATE, len(trials))
    trial = np.repeat(trials, len(starts))
    X = np.zeros((len(t0), window, 10), np.float32)
    return Dataset(X, trial % 2, trial, t0, list(classes), {'sampling_rate_hz': RATE})


def test_the_short_windows_inside_a_long_one_are_those_of_its_recording_and_span():
    long, short = _cut(512, 256), _cut(128, 64)
    inside = windows_inside(long, short)
    assert len(inside) == len(long.y)
    for index, members in enumerate(inside):
        assert members.size == 7  # (512 - 128) / 64 + 1
        assert np.all(short.trial[members] == long.trial[index])
        assert short.t0[members].min() == long.t0[index]
        assert short.t0[members].max() + 128 / RATE == pytest.approx(long.t0[index] + 512 / RATE)


def test_a_recording_missing_from_the_short_cut_leaves_its_long_windows_empty():
    inside = windows_inside(_cut(512, 256), _cut(128, 64, trials=(0,)))
    long = _cut(512, 256)
    assert all(members.size == 0 for members, trial in zip(inside, long.trial, strict=True)
               if trial == 1)


def test_the_vote_averages_each_scales_mean_probability_and_an_empty_scale_abstains():
    outer = np.array([[0.9, 0.1], [0.2, 0.8]])
    short = np.array([[0.5, 0.5], [0.1, 0.9], [0.3, 0.7]])
    inside = [np.array([0, 1]), np.array([], dtype=np.int64)]
    vote = soft_vote(outer, [(short, inside)])
    np.testing.assert_allclose(vote[0], (outer[0] + short[:2].mean(axis=0)) / 2)
    np.testing.assert_allclose(vote[1], outer[1])
    np.testing.assert_allclose(vote.sum(axis=1), 1.0)


@pytest.mark.parametrize('change, message', [
    ({'info': {'sampling_rate_hz': 50.0}}, 'sampling_rate_hz'),
    ({'info': {}}, 'sampling_rate_hz'),
    ({'classes': ['a', 'c']}, 'classes'),
])
def test_datasets_of_other_rates_or_classes_are_refused(change, message):
    short = _cut(128, 64, classes=change.get('classes', ('a', 'b')))
    if 'info' in change:
        short.info = change['info']
    with pytest.raises(ValueError, match=message):
        windows_inside(_cut(512, 256), short)
