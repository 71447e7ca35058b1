# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Soft voting across window sizes: models of several windows decide one span together.

The same recordings cut at several window lengths (`tactex convert --window`) give one
dataset per length. A vote is cast for each window of the longest length: each length's
model contributes the mean of its class probabilities over its own windows that lie
inside that span (same recording, start and end within it), and the vote is the mean of
those contributions. A decision then waits as long as the longest window, as the largest
model's would, and reads the span at several time scales.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def windows_inside(outer, inner, tolerance_s: float = 1e-6) -> list[np.ndarray]:
    """For each window of `outer`, the indices of `inner`'s windows lying inside it.

    Both datasets must come from the same recordings at one sampling rate (their sidecars'
    `sampling_rate_hz`); `trial` names the recording and `t0` the start in seconds.

    Raises:
        ValueError: other channels or classes, no sampling rate, or a sampling rate that
            differs between the two.
    """
    rates = [dataset.info.get('sampling_rate_hz') for dataset in (outer, inner)]
    if not all(isinstance(rate, (int, float)) and rate > 0 for rate in rates) or \
            not np.isclose(rates[0], rates[1]):
        raise ValueError(f'both datasets need one sampling_rate_hz, got {rates}')
    for what in ('channels', 'classes'):
        if list(getattr(outer, what)) != list(getattr(inner, what)):
            raise ValueError(f'the datasets differ in {what}: {getattr(outer, what)} and '
                             f'{getattr(inner, what)}')
    rate = float(rates[0])
    outer_end = outer.t0 + outer.X.shape[1] / rate
    inner_end = inner.t0 + inner.X.shape[1] / rate
    by_trial: dict[int, np.ndarray] = {}
    for trial in np.unique(inner.trial):
        by_trial[int(trial)] = np.flatnonzero(inner.trial == trial)
    inside = []
    for start, end, trial in zip(outer.t0, outer_end, outer.trial, strict=True):
        candidates = by_trial.get(int(trial), np.zeros(0, dtype=np.int64))
        keep = (inner.t0[candidates] >= start - tolerance_s) & \
            (inner_end[candidates] <= end + tolerance_s)
        inside.append(candidates[keep])
    return inside


def soft_vote(outer_probabilities: np.ndarray, inner: Sequence[tuple[np.ndarray,
                                                                     list[np.ndarray]]]
              ) -> np.ndarray:
    """The vote for each outer window: the mean over scales of each scale's mean probability.

    Args:
        outer_probabilities: (n, classes) of the longest windows' model.
        inner: for each shorter length, its (m, classes) probabilities and, per outer
            window, the indices of its windows inside (`windows_inside`). A scale with no
            window inside an outer one abstains for it.
    """
    total = np.array(outer_probabilities, dtype=np.float64)
    voters = np.ones(len(total))
    for probabilities, inside in inner:
        for index, members in enumerate(inside):
            if members.size:
                total[index] += probabilities[members].mean(axis=0)
                voters[index] += 1
    return total / voters[:, None]
