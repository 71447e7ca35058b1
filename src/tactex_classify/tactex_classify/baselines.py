# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Fast baselines for the deep models: MiniRocket + ridge, and statistics + ExtraTrees.

MiniRocket (Dempster, Schmidt, Webb, KDD 2021) is implemented here from the paper in
numpy rather than taken from a toolkit: the toolkits that ship it pin numpy, numba and
scikit-learn versions of their own, and the transform is short. Its 84 kernels of
length 9 (weights -1 with three +2) run at several dilations on a random subset of
channels each; biases are quantiles of the outputs on training windows; the features
are the proportions of positive values (PPV). Channels are z-scored on the training
windows first (pressure is ~1e5 Pa, angular rates ~1e-2 rad/s). A ridge classifier
with built-in cross-validation of its regularisation reads the features.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np
from scipy import stats
from sklearn.ensemble import ExtraTreesClassifier
from sklearn.linear_model import RidgeClassifierCV
from sklearn.preprocessing import StandardScaler

from tactex_classify.classifier import channel_names, ChannelScaler, check_windows, softmax
from tactex_classify.errors import NotFittedError

KERNELS = np.array(list(combinations(range(9), 3)))  # positions of the +2 weights
GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


class MiniRocketRidge:
    """MiniRocket features + RidgeClassifierCV."""

    def __init__(self, *, dilations: int = 7, biases_per_kernel: int = 6, seed: int = 0
                 ) -> None:
        self.dilations = dilations
        self.biases_per_kernel = biases_per_kernel
        self.seed = seed
        self.ridge_ = None

    @staticmethod
    def _convolve(kernel: np.ndarray, channels: np.ndarray, shifted: list[np.ndarray],
                  total: np.ndarray) -> np.ndarray:
        """Kernel output summed over `channels`: 3 x (the +2 taps) - (all nine taps)."""
        picked = shifted[kernel[0]] + shifted[kernel[1]] + shifted[kernel[2]]
        return (3.0 * picked[..., channels] - total[..., channels]).sum(axis=-1)

    def _shifted(self, Z: np.ndarray, dilation: int) -> tuple[list[np.ndarray], np.ndarray]:
        """The 9 taps of a dilation, zero padded ('same' length), and their sum."""
        pad = 4 * dilation
        padded = np.pad(Z, ((0, 0), (pad, pad), (0, 0)))
        length = Z.shape[1]
        shifted = [padded[:, j * dilation:j * dilation + length] for j in range(9)]
        return shifted, np.sum(shifted, axis=0) * 1.0

    def _plan(self, length: int, channels: int, rng: np.random.Generator) -> None:
        largest = max(1.0, (length - 1) / 8.0)
        self.dilations_ = np.unique(np.floor(2.0 ** np.linspace(0, np.log2(largest),
                                                                self.dilations)).astype(int))
        self.channel_sets_ = {}
        for dilation in self.dilations_:
            for index in range(len(KERNELS)):
                size = int(2 ** rng.uniform(0, np.log2(min(channels, 9) + 1)))
                self.channel_sets_[(dilation, index)] = rng.choice(channels, max(1, size),
                                                                   replace=False)

    def _features(self, Z: np.ndarray, fit: bool, rng=None) -> np.ndarray:
        columns = []
        for dilation in self.dilations_:
            shifted, total = self._shifted(Z, dilation)
            for index, kernel in enumerate(KERNELS):
                out = self._convolve(kernel, self.channel_sets_[(dilation, index)], shifted,
                                     total)
                if fit:
                    example = out[rng.integers(len(out))]
                    quantiles = (np.arange(1, self.biases_per_kernel + 1) * GOLDEN) % 1.0
                    self.biases_[(dilation, index)] = np.quantile(example, quantiles)
                biases = self.biases_[(dilation, index)]
                columns.append((out[:, :, None] > biases).mean(axis=1))
        return np.concatenate(columns, axis=1)

    def fit(self, X, y, classes, groups=None, channels=None) -> MiniRocketRidge:
        """Transform the training windows and fit the ridge."""
        del groups
        X = check_windows(X)
        rng = np.random.default_rng(self.seed)
        self.classes_ = list(classes)
        self.window_, self.n_channels_ = X.shape[1], X.shape[2]
        self.channels_ = channel_names(channels, self.n_channels_)
        self.scaler_ = ChannelScaler('standard').fit(X)
        self._plan(self.window_, self.n_channels_, rng)
        self.biases_ = {}
        features = self._features(self.scaler_.transform(X), True, rng)
        self.standard_ = StandardScaler().fit(features)
        self.ridge_ = RidgeClassifierCV(alphas=np.logspace(-3, 3, 10)).fit(
            self.standard_.transform(features), np.asarray(y))
        return self

    def predict_proba(self, X) -> np.ndarray:
        """Softmax of the ridge's decision values, one column per class in `classes_`."""
        if self.ridge_ is None:
            raise NotFittedError('MiniRocketRidge is not fitted; call fit first')
        X = check_windows(X, window=self.window_, channels=self.n_channels_)
        scores = self.ridge_.decision_function(self.standard_.transform(
            self._features(self.scaler_.transform(X), False)))
        return _full_columns(softmax(np.atleast_2d(_two_class(scores))), self.ridge_.classes_,
                             len(self.classes_))


class StatsExtraTrees:
    """Per-window statistics of every channel + ExtraTrees (the active-learning family)."""

    def __init__(self, *, trees: int = 300, seed: int = 0) -> None:
        self.trees = trees
        self.seed = seed
        self.forest_ = None

    @staticmethod
    def features(X: np.ndarray) -> np.ndarray:
        """Moments, extremes, roughness and four spectral band energies per channel."""
        X = X.astype(np.float64)
        diff = np.diff(X, axis=1)
        centred = X - X.mean(axis=1, keepdims=True)
        spectrum = np.abs(np.fft.rfft(centred, axis=1)) ** 2
        bands = np.array_split(spectrum[:, 1:], 4, axis=1)
        parts = [X.mean(1), X.std(1), X.min(1), X.max(1), np.median(X, 1),
                 np.nan_to_num(stats.skew(X, axis=1)), np.nan_to_num(stats.kurtosis(X, axis=1)),
                 np.abs(diff).mean(1), diff.std(1),
                 (np.diff(np.sign(centred), axis=1) != 0).mean(1),
                 np.argmax(spectrum[:, 1:], axis=1).astype(float)]
        parts += [np.log1p(band.sum(1)) for band in bands]
        return np.concatenate(parts, axis=1)

    def fit(self, X, y, classes, groups=None, channels=None) -> StatsExtraTrees:
        """Fit the forest on the windows' statistics."""
        del groups
        X = check_windows(X)
        self.classes_ = list(classes)
        self.window_, self.n_channels_ = X.shape[1], X.shape[2]
        self.channels_ = channel_names(channels, self.n_channels_)
        self.forest_ = ExtraTreesClassifier(n_estimators=self.trees, random_state=self.seed,
                                            n_jobs=1).fit(self.features(X), np.asarray(y))
        return self

    def predict_proba(self, X) -> np.ndarray:
        """Class probabilities (the trees' votes), one column per class in `classes_`."""
        if self.forest_ is None:
            raise NotFittedError('StatsExtraTrees is not fitted; call fit first')
        X = check_windows(X, window=self.window_, channels=self.n_channels_)
        return _full_columns(self.forest_.predict_proba(self.features(X)), self.forest_.classes_,
                             len(self.classes_))


def _two_class(scores: np.ndarray) -> np.ndarray:
    """Ridge gives one column for two classes: make it two."""
    return np.stack([-scores, scores], axis=1) if scores.ndim == 1 else scores


def _full_columns(proba: np.ndarray, seen: np.ndarray, count: int) -> np.ndarray:
    """Spread columns of the classes seen in training into all `count` classes."""
    full = np.zeros((proba.shape[0], count))
    full[:, np.asarray(seen, dtype=int)] = proba
    return full
