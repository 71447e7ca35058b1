# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Early stopping's validation split: whole recordings held out of a deep model's training."""

from __future__ import annotations

import math

import numpy as np


def validation_split(y: np.ndarray, groups, config) -> tuple[np.ndarray, np.ndarray]:
    """Training and early-stopping indices; whole recordings go to one side.

    `config` is a `deep_classifier.TrainingConfig` (its early stopping, validation
    fraction and seed).

    Without early stopping every window trains. With it, `validation_fraction` of the
    recordings (at least one) is held out by scikit-learn's GroupShuffleSplit.

    Raises:
        ValueError: early stopping without one group per window (window-level validation
            would leak), with fewer than two recordings, or no window left to train on.
    """
    from sklearn.model_selection import GroupShuffleSplit
    indices = np.arange(y.size)
    if not indices.size:
        raise ValueError('no training windows')
    if not config.early_stopping:
        return indices, np.zeros(0, dtype=np.int64)
    if groups is None:
        raise ValueError('early stopping holds out whole recordings: pass groups (the '
                         'recording of each window); validating on windows of the training '
                         'recordings would leak')
    groups = np.asarray(groups)
    if groups.shape != y.shape:
        raise ValueError(f'groups must name the recording of each of the {y.size} windows, '
                         f'got shape {groups.shape!r}')
    recordings = np.unique(groups).size
    if recordings < 2:
        raise ValueError(f'early stopping needs at least 2 recordings (one to validate on), '
                         f'got {recordings}')
    if math.ceil(config.validation_fraction * recordings) >= recordings:
        raise ValueError(f'validation_fraction {config.validation_fraction} of {recordings} '
                         f'recordings leaves none to train on')
    splitter = GroupShuffleSplit(n_splits=1, test_size=config.validation_fraction,
                                 random_state=config.seed)
    return next(splitter.split(indices, y, groups))
