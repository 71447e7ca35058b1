# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A small synthetic dataset whose class sets a sine's frequency, for training tests."""

import numpy as np

from tactex_classify.data.dataset import Dataset

CLASSES = ['low', 'mid', 'high']


def toy(recordings_per_class=4, windows=6, window=96, seed=0):
    """Windows whose class sets the frequency of a sine in channel 0."""
    rng = np.random.default_rng(seed)
    X, y, trial, t0 = [], [], [], []
    for label in range(3):
        for recording in range(recordings_per_class):
            phase = rng.uniform(0, 6)
            for k in range(windows):
                t = np.arange(window) + k * window // 2
                channels = rng.normal(0, 0.3, (window, 10))
                channels[:, 0] += np.sin(2 * np.pi * (label + 1) * t / window + phase)
                channels[:, 9] += 101_000.0
                X.append(channels)
                y.append(label)
                trial.append(label * 100 + recording)
                t0.append(k * 0.1)
    return Dataset(np.array(X, np.float32), np.array(y), np.array(trial), np.array(t0),
                   CLASSES, {'sampling_rate_hz': 100.0, 'hop': window // 2})


STREAM = {'hop': 48, 'sampling_rate_hz': 100.0}  # what a checkpoint keeps of the toy set
