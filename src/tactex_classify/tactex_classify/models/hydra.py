# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""HYDRA + ridge: groups of random kernels that compete at every time step, counted.

Written from Dempster, Schmidt and Webb, "HYDRA: competing convolutional kernels for
fast and accurate time series classification" (Data Mining and Knowledge Discovery 37,
2023), not from its reference code (GPL-3.0). `groups` groups of `kernels_per_group`
random kernels of length 9 (weights N(0, 1); the paper's normalisation, less the mean
and over the absolute sum, applied to each channel's taps, so that a kernel ignores
every channel's level as a univariate one ignores the series') run at dilations 1, 2,
4, ... up to a ninth of the window, half of the groups on the z-scored windows and half
on their first differences, 'same' padding.
At every time step the kernels of a group compete: the one with the largest response
adds that response to its count ("soft" counting of the maxima), the one with the
smallest adds 1 ("hard" counting of the minima). The counts of every kernel are the
features, square-rooted as the paper's sparse scaling does before the standardisation
(its zero-masking is left to the ridge's standardisation). Multivariate windows: each
group reads its own random subset of the channels (half of them, at most 8), one weight
set per channel, summed as a grouped convolution sums them.
"""

from __future__ import annotations

import numpy as np

from tactex_classify.models.feature_ridge import FeatureRidge
from tactex_classify.models.multirocket import MultiRocketRidge
from tactex_common.constants import MAX_SEED

LENGTH = 9
CHUNK = 128  # windows convolved at once


def channels_per_group(channels: int) -> int:
    """How many channels each group reads: half of them, at least 1, at most 8."""
    return max(1, min(8, (channels + 1) // 2))


def hydra_dilations(length: int) -> np.ndarray:
    """1, 2, 4, ... while a kernel's span stays within the window."""
    largest = max(0, int(np.floor(np.log2(max(1.0, (length - 1) / (LENGTH - 1))))))
    return 2 ** np.arange(largest + 1)


def competing_counts(series: np.ndarray, dilation: int, weights: np.ndarray,
                     channels: np.ndarray) -> np.ndarray:
    """(n, groups x kernels x 2) soft max counts and hard min counts of one kernel bank.

    Args:
        series: (n, L, c) windows.
        dilation: spacing of the taps.
        weights: (groups, kernels, m, 9), per channel read.
        channels: (groups, m) indices of the channels each group reads.
    """
    n, length, _ = series.shape
    groups, kernels, reads, _ = weights.shape
    pad = (LENGTH - 1) * dilation // 2
    picked = np.pad(series, ((0, 0), (pad, pad), (0, 0)))[:, :, channels]  # (n, L', g, m)
    picked = np.ascontiguousarray(picked.transpose(2, 0, 1, 3))  # (g, n, L', m)
    per_tap = weights.transpose(3, 0, 2, 1)  # (9, g, m, k)
    responses = np.zeros((groups, n, length, kernels), np.result_type(series, weights))
    for j in range(LENGTH):
        taps = picked[:, :, j * dilation:j * dilation + length].reshape(groups, n * length,
                                                                        reads)
        responses += (taps @ per_tap[j]).reshape(groups, n, length, kernels)
    # Each step's winner adds its response to its count, its loser adds 1.
    first = (np.arange(groups)[:, None, None] * n + np.arange(n)[None, :, None]) * kernels
    size = groups * n * kernels
    soft = np.bincount((first + responses.argmax(axis=-1)).ravel(),
                       weights=responses.max(axis=-1).ravel(), minlength=size)
    hard = np.bincount((first + responses.argmin(axis=-1)).ravel(), minlength=size)
    counts = np.stack([soft.reshape(groups, n, kernels), hard.reshape(groups, n, kernels)],
                      axis=-1)
    return counts.transpose(1, 0, 2, 3).reshape(n, -1)


class HydraRidge(FeatureRidge):
    """HYDRA features + RidgeClassifierCV."""

    CHECKPOINT_KIND = 'hydra'
    TRANSFORM_ARRAYS = ('hydra_dilations_', 'hydra_weights_', 'hydra_reads_')
    # The weight axes each normalisation spans: a channel's taps (bench_hydra_levels.py
    # measures the alternative, (-2, -1): all of a kernel's channels at once).
    NORMALISED_AXES: tuple[int, ...] = (-1,)
    SETTINGS = {'groups': (64, 1024), 'kernels_per_group': (8, 64), 'seed': (0, MAX_SEED)}

    def _fit(self, Z: np.ndarray, rng: np.random.Generator) -> None:
        """Draw the kernels and the channels each group reads."""
        if Z.shape[1] < 2:
            raise ValueError('HYDRA needs windows of at least 2 samples (it also reads '
                             'their first differences)')
        self.hydra_dilations_ = hydra_dilations(Z.shape[1])
        half, reads = max(1, self.groups // 2), channels_per_group(Z.shape[2])
        weights = rng.standard_normal((len(self.hydra_dilations_), 2, half, self.kernels_per_group,
                                       reads, LENGTH))
        # Each channel's taps less their mean, over their absolute sum: a kernel then
        # ignores every channel's level (its offset in the window), as in the paper.
        weights -= weights.mean(axis=self.NORMALISED_AXES, keepdims=True)
        self.hydra_weights_ = weights / np.abs(weights).sum(axis=self.NORMALISED_AXES,
                                                            keepdims=True)
        self.hydra_reads_ = np.stack([[[rng.choice(Z.shape[2], reads, replace=False)
                                  for _ in range(half)] for _ in range(2)]
                                for _ in self.hydra_dilations_])

    def _features(self, Z: np.ndarray) -> np.ndarray:
        chunks = []
        for start in range(0, len(Z), CHUNK):
            part = Z[start:start + CHUNK].astype(np.float32)
            columns = [competing_counts(series, int(dilation), self.hydra_weights_[d, r].astype(
                np.float32), self.hydra_reads_[d, r])
                for d, dilation in enumerate(self.hydra_dilations_)
                for r, series in enumerate((part, np.diff(part, axis=1)))]
            chunks.append(np.sqrt(np.clip(np.concatenate(columns, axis=1), 0.0, None)))
        return np.concatenate(chunks, axis=0)

    def _feature_count(self) -> int:
        groups = 2 * self.hydra_weights_.shape[2]
        return len(self.hydra_dilations_) * groups * self.kernels_per_group * 2

    def _transform_fits(self) -> bool:
        d, half = len(self.hydra_dilations_), max(1, self.groups // 2)
        reads = channels_per_group(self.n_channels_)
        fits = (self.hydra_dilations_.shape == (d,) and d >= 1 and self.window_ >= 2
                and np.array_equal(self.hydra_dilations_, hydra_dilations(self.window_))
                and self.hydra_weights_.shape == (d, 2, half, self.kernels_per_group, reads,
                                                  LENGTH)
                and self.hydra_reads_.shape == (d, 2, half, reads)
                and bool(np.all((self.hydra_reads_ >= 0)
                                & (self.hydra_reads_ < self.n_channels_))))
        self.hydra_dilations_ = self.hydra_dilations_.astype(int)
        self.hydra_reads_ = self.hydra_reads_.astype(int)
        return fits


class MultiRocketHydraRidge(MultiRocketRidge, HydraRidge):
    """MultiRocket and HYDRA features side by side, read by one ridge.

    The combination the HYDRA paper found the most accurate of the fast methods on the
    UCR archive; each half fits and transforms exactly as its own model does.
    """

    CHECKPOINT_KIND = 'multirocket_hydra'
    TRANSFORM_ARRAYS = MultiRocketRidge.TRANSFORM_ARRAYS + HydraRidge.TRANSFORM_ARRAYS
    SETTINGS = {**MultiRocketRidge.SETTINGS, **HydraRidge.SETTINGS}

    def _fit(self, Z: np.ndarray, rng: np.random.Generator) -> None:
        MultiRocketRidge._fit(self, Z, rng)
        HydraRidge._fit(self, Z, rng)

    def _features(self, Z: np.ndarray) -> np.ndarray:
        return np.concatenate([MultiRocketRidge._features(self, Z),
                               HydraRidge._features(self, Z)], axis=1)

    def _feature_count(self) -> int:
        return MultiRocketRidge._feature_count(self) + HydraRidge._feature_count(self)

    def _transform_fits(self) -> bool:
        return MultiRocketRidge._transform_fits(self) and HydraRidge._transform_fits(self)
