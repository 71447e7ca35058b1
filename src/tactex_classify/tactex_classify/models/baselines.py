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

from pathlib import Path
import warnings

import numpy as np
from scipy import stats
from sklearn.ensemble import ExtraTreesClassifier

from tactex_classify.errors import CheckpointError, NotFittedError
from tactex_classify.models.checkpoint import Deployable, restore_fitted
from tactex_classify.models.feature_ridge import FeatureRidge, full_columns, read_config
from tactex_classify.models.rocket_kernels import fit_biases, kernel_outputs, KERNELS, plan_kernels
from tactex_classify.models.windows import channel_names, check_windows
from tactex_common.constants import MAX_SEED


class MiniRocketRidge(FeatureRidge):
    """MiniRocket features + RidgeClassifierCV."""

    CHECKPOINT_KIND = 'minirocket'
    TRANSFORM_ARRAYS = ('dilations_', 'masks_', 'biases_')
    SETTINGS = {'dilations': (7, 64), 'biases_per_kernel': (6, 64), 'seed': (0, MAX_SEED)}

    def _fit_transform(self, Z: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """Plan dilations and channel masks, then fit the biases while transforming."""
        self.dilations_, self.masks_ = plan_kernels(Z.shape[1], Z.shape[2], self.dilations, rng)
        self.biases_ = np.zeros((len(self.dilations_), len(KERNELS), self.biases_per_kernel))
        return self._ppv(Z, rng)

    def _features(self, Z: np.ndarray) -> np.ndarray:
        return self._ppv(Z)

    def _ppv(self, Z: np.ndarray, rng=None) -> np.ndarray:
        """PPV features (n, dilations x kernels x biases); fits the biases when rng is given."""
        columns = []
        for d, dilation in enumerate(self.dilations_):
            out = kernel_outputs(Z, int(dilation), self.masks_[d])  # (kernels, n, L)
            if rng is not None:
                self.biases_[d] = fit_biases(out, self.biases_per_kernel, rng)
            biases = self.biases_[d].astype(out.dtype)[:, None, :, None]
            ppv = np.count_nonzero(out[:, :, None, :] > biases, axis=-1) / out.shape[2]
            columns.append(ppv.transpose(1, 0, 2).reshape(len(Z), -1))
        return np.concatenate(columns, axis=1)

    def _feature_count(self) -> int:
        return len(self.dilations_) * len(KERNELS) * self.biases_per_kernel

    def _transform_fits(self) -> bool:
        d, c, b = len(self.dilations_), self.n_channels_, self.biases_per_kernel
        fits = (self.masks_.shape == (d, len(KERNELS), c)
                and self.biases_.shape == (d, len(KERNELS), b)
                and self.dilations_.shape == (d,) and d <= self.dilations
                and bool(np.all(self.dilations_ >= 1)))
        self.dilations_ = self.dilations_.astype(int)
        return fits


class StatsExtraTrees(Deployable):
    """Per-window statistics of every channel + ExtraTrees (the active-learning family)."""

    CHECKPOINT_KIND = 'extratrees'
    MODEL_FILE = 'model.skops'
    model_name = 'extratrees'

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
        with warnings.catch_warnings():  # a (nearly) constant channel's moments are NaN: 0
            warnings.filterwarnings('ignore', 'Precision loss occurred', RuntimeWarning)
            shape = [np.nan_to_num(stats.skew(X, axis=1)),
                     np.nan_to_num(stats.kurtosis(X, axis=1))]
        parts = [X.mean(1), X.std(1), X.min(1), X.max(1), np.median(X, 1), *shape,
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
        return full_columns(self.forest_.predict_proba(self.features(X)), self.forest_.classes_,
                             len(self.classes_))


    def checkpoint_fields(self) -> dict:
        """The hyper-parameters (the forest goes to model.skops)."""
        if self.forest_ is None:
            raise NotFittedError('StatsExtraTrees is not fitted; nothing to save')
        return {'config': {'trees': self.trees, 'seed': self.seed}}

    def write_model(self, path: Path) -> None:
        """Write the forest with skops (no pickle)."""
        import skops.io
        skops.io.dump(self.forest_, path)

    @classmethod
    def from_checkpoint(cls, info) -> StatsExtraTrees:
        """A saved forest, read by skops trusting only the forest's own types.

        Raises:
            KeyError, TypeError, ValueError: a malformed field.
            CheckpointError: the file holds any other type (nothing of it is run), is
                unreadable, or the forest does not fit the channels and classes.
        """
        import skops.io
        self = cls(**read_config(info, {'trees': 100_000, 'seed': MAX_SEED}))
        restore_fitted(self, info)
        try:
            untrusted = set(skops.io.get_untrusted_types(file=info.model_file))
            if untrusted - set(TRUSTED_FOREST_TYPES):
                raise CheckpointError(f'{info.folder}: refused {cls.MODEL_FILE}: it holds '
                                      f"types outside the forest's own: "
                                      f'{sorted(untrusted - set(TRUSTED_FOREST_TYPES))}')
            forest = skops.io.load(info.model_file, trusted=list(TRUSTED_FOREST_TYPES))
        except CheckpointError:
            raise
        except Exception as err:  # noqa: BLE001 - skops raises many types for a bad file
            raise CheckpointError(f'{info.folder}: refused {cls.MODEL_FILE}: '
                                  f'{type(err).__name__}: {err}') from None
        features = self.features(np.zeros((1, self.window_, self.n_channels_))).shape[1]
        if not isinstance(forest, ExtraTreesClassifier) or forest.n_features_in_ != features \
                or len(forest.estimators_) != self.trees or not np.all(
                    np.isin(forest.classes_, np.arange(len(self.classes_)))):
            raise CheckpointError(f'{info.folder}: {cls.MODEL_FILE} is not a forest of '
                                  f'{self.trees} trees over {features} features of '
                                  f'{len(self.classes_)} classes')
        self.forest_ = forest
        return self


# What an ExtraTreesClassifier saved by skops is made of; anything else is refused.
TRUSTED_FOREST_TYPES = ('sklearn.ensemble._forest.ExtraTreesClassifier',
                        'sklearn.tree._classes.ExtraTreeClassifier', 'sklearn.tree._tree.Tree')
