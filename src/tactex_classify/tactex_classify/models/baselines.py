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

from dataclasses import asdict
from itertools import combinations
from pathlib import Path

import numpy as np
from scipy import stats
from sklearn.ensemble import ExtraTreesClassifier
from sklearn.linear_model import RidgeClassifierCV
from sklearn.preprocessing import StandardScaler

from tactex_classify.errors import CheckpointError, NotFittedError
from tactex_classify.models.checkpoint import Deployable, MAX_MODEL_BYTES, restore_fitted
from tactex_classify.models.windows import channel_names, ChannelScaler, check_windows, softmax
from tactex_common.constants import MAX_SEED
from tactex_common.files import check_npz_sizes, open_regular

KERNELS = np.array(list(combinations(range(9), 3)))  # positions of the +2 weights
GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


class MiniRocketRidge(Deployable):
    """MiniRocket features + RidgeClassifierCV."""

    CHECKPOINT_KIND = 'minirocket'
    MODEL_FILE = 'weights.npz'
    model_name = 'minirocket'

    def __init__(self, *, dilations: int = 7, biases_per_kernel: int = 6, seed: int = 0
                 ) -> None:
        self.dilations = dilations
        self.biases_per_kernel = biases_per_kernel
        self.seed = seed
        self.coef_ = None

    @staticmethod
    def _outputs(Z: np.ndarray, dilation: int, masks: np.ndarray) -> np.ndarray:
        """Every kernel's output at one dilation, summed over its channels: (kernels, n, L).

        A kernel is 3 x (its three +2 taps) - (all nine taps); with 'same' zero padding.
        The taps are projected on each kernel's channel mask first, so the 84 kernels cost
        one matrix product.
        """
        pad = 4 * dilation
        padded = np.pad(Z, ((0, 0), (pad, pad), (0, 0)))
        length = Z.shape[1]
        taps = np.stack([padded[:, j * dilation:j * dilation + length] for j in range(9)])
        projected = np.moveaxis(taps @ masks.T, -1, 1)  # (9, kernels, n, L)
        kernel = np.arange(len(KERNELS))
        picked = projected[KERNELS[:, 0], kernel] + projected[KERNELS[:, 1], kernel] \
            + projected[KERNELS[:, 2], kernel]
        return 3.0 * picked - np.moveaxis(taps.sum(axis=0) @ masks.T, -1, 0)

    def _plan(self, length: int, channels: int, rng: np.random.Generator) -> None:
        largest = max(1.0, (length - 1) / 8.0)
        self.dilations_ = np.unique(np.floor(2.0 ** np.linspace(0, np.log2(largest),
                                                                self.dilations)).astype(int))
        self.masks_ = np.zeros((len(self.dilations_), len(KERNELS), channels), np.float32)
        for d in range(len(self.dilations_)):
            for index in range(len(KERNELS)):
                size = int(2 ** rng.uniform(0, np.log2(min(channels, 9) + 1)))
                self.masks_[d, index, rng.choice(channels, max(1, size), replace=False)] = 1.0

    def _features(self, Z: np.ndarray, rng=None) -> np.ndarray:
        """PPV features (n, dilations x kernels x biases); fits the biases when rng is given."""
        columns = []
        if rng is not None:
            self.biases_ = np.zeros((len(self.dilations_), len(KERNELS),
                                     self.biases_per_kernel))
            quantiles = (np.arange(1, self.biases_per_kernel + 1) * GOLDEN) % 1.0
        for d, dilation in enumerate(self.dilations_):
            out = self._outputs(Z, int(dilation), self.masks_[d])  # (kernels, n, L)
            if rng is not None:
                for index in range(len(KERNELS)):
                    self.biases_[d, index] = np.quantile(out[index, rng.integers(out.shape[1])],
                                                         quantiles)
            biases = self.biases_[d].astype(out.dtype)[:, None, :, None]
            ppv = np.count_nonzero(out[:, :, None, :] > biases, axis=-1) / out.shape[2]
            columns.append(ppv.transpose(1, 0, 2).reshape(len(Z), -1))
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
        features = self._features(self.scaler_.transform(X), rng)
        standard = StandardScaler().fit(features)
        ridge = RidgeClassifierCV(alphas=np.logspace(-3, 3, 10)).fit(
            standard.transform(features), np.asarray(y))
        # Inference needs only these arrays (no scikit-learn object is kept or saved).
        self.feature_mean_, self.feature_scale_ = standard.mean_, standard.scale_
        self.coef_, self.intercept_ = np.atleast_2d(ridge.coef_), np.atleast_1d(ridge.intercept_)
        self.seen_classes_ = np.asarray(ridge.classes_, dtype=np.int64)
        return self

    def predict_proba(self, X) -> np.ndarray:
        """Softmax of the ridge's decision values, one column per class in `classes_`."""
        if self.coef_ is None:
            raise NotFittedError('MiniRocketRidge is not fitted; call fit first')
        X = check_windows(X, window=self.window_, channels=self.n_channels_)
        features = self._features(self.scaler_.transform(X))
        scores = ((features - self.feature_mean_) / self.feature_scale_) @ self.coef_.T \
            + self.intercept_
        return _full_columns(softmax(_two_class(scores)), self.seen_classes_,
                             len(self.classes_))

    ARRAYS = ('dilations_', 'masks_', 'biases_', 'feature_mean_', 'feature_scale_', 'coef_',
              'intercept_', 'seen_classes_')

    def checkpoint_fields(self) -> dict:
        """The channel scaler and the hyper-parameters (the arrays go to weights.npz)."""
        if self.coef_ is None:
            raise NotFittedError('MiniRocketRidge is not fitted; nothing to save')
        return {'scaler': asdict(self.scaler_),
                'config': {'dilations': self.dilations,
                           'biases_per_kernel': self.biases_per_kernel, 'seed': self.seed}}

    def write_model(self, path: Path) -> None:
        """Write the fitted arrays as an uncompressed .npz (no pickled objects)."""
        with open(path, 'wb') as handle:
            np.savez(handle, **{name: getattr(self, name) for name in self.ARRAYS})

    @classmethod
    def from_checkpoint(cls, info) -> MiniRocketRidge:
        """A saved MiniRocket: plain arrays, shapes checked against each other.

        Raises:
            KeyError, TypeError, ValueError: a malformed field.
            CheckpointError: the arrays are refused (objects, NaN, shapes that disagree).
        """
        self = cls(**read_config(info, {'dilations': 64, 'biases_per_kernel': 64,
                                        'seed': MAX_SEED}))
        restore_fitted(self, info)
        self.scaler_ = ChannelScaler.from_state(info.fields['scaler'], self.n_channels_)
        arrays = read_arrays(info, cls.ARRAYS)
        for name, value in arrays.items():
            setattr(self, name, value)
        d, c, b = len(self.dilations_), self.n_channels_, self.biases_per_kernel
        features = d * len(KERNELS) * b
        seen = self.seen_classes_
        shapes_fit = (self.masks_.shape == (d, len(KERNELS), c)
                      and self.biases_.shape == (d, len(KERNELS), b)
                      and self.dilations_.shape == (d,) and d <= self.dilations
                      and self.feature_mean_.shape == self.feature_scale_.shape == (features,)
                      and self.coef_.shape[1:] == (features,)
                      and self.intercept_.shape == self.coef_.shape[:1]
                      and seen.ndim == 1 and seen.size >= 2
                      and self.coef_.shape[0] == (1 if seen.size == 2 else seen.size)
                      and np.all((seen >= 0) & (seen < len(self.classes_)))
                      and np.all(self.dilations_ >= 1) and np.all(self.feature_scale_ > 0))
        if not shapes_fit:
            raise CheckpointError(f'{info.folder}: {cls.MODEL_FILE} arrays do not fit each '
                                  f'other, {c} channels and {len(self.classes_)} classes')
        self.dilations_ = self.dilations_.astype(int)
        return self


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


def read_config(info, maxima: dict[str, int]) -> dict[str, int]:
    """A baseline's `config` field: exactly the named whole numbers, each in 0..its maximum.

    Raises:
        ValueError: another set of names, or a value out of its range (named).
    """
    config = info.fields['config']
    if not isinstance(config, dict) or set(config) != set(maxima):
        raise ValueError(f'config must hold {", ".join(maxima)}; got {config!r}')
    for name, maximum in maxima.items():
        value = config[name]
        low = 0 if name == 'seed' else 1
        if not isinstance(value, int) or isinstance(value, bool) or not low <= value <= maximum:
            raise ValueError(f'config {name} must be a whole number in {low}..{maximum}, got '
                             f'{value!r}')
    return config


def read_arrays(info, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """Named numeric, finite arrays of a checkpoint's .npz (no pickled objects).

    Raises:
        CheckpointError: unreadable, an object array, a missing name, or NaN/inf.
    """
    import zipfile
    try:
        with open_regular(info.model_file, max_bytes=MAX_MODEL_BYTES) as handle, \
                np.load(handle, allow_pickle=False) as npz:
            check_npz_sizes(npz, MAX_MODEL_BYTES, info.model_file)
            arrays = {name: npz[name] for name in names}
    except KeyError as err:
        raise CheckpointError(f'{info.folder}: {info.model_file.name} lacks {err}') from None
    except (ValueError, OSError, EOFError, zipfile.BadZipFile) as err:
        raise CheckpointError(f'{info.folder}: refused {info.model_file.name}: {err}'
                              ) from None
    for name, value in arrays.items():
        if value.dtype.kind not in 'iuf' or not np.all(np.isfinite(value)):
            raise CheckpointError(f'{info.folder}: {info.model_file.name}: {name} must hold '
                                  f'finite numbers')
    return arrays


def _two_class(scores: np.ndarray) -> np.ndarray:
    """Ridge gives one column of scores for two classes: make it two."""
    return np.concatenate([-scores, scores], axis=1) if scores.shape[1] == 1 else scores


def _full_columns(proba: np.ndarray, seen: np.ndarray, count: int) -> np.ndarray:
    """Spread columns of the classes seen in training into all `count` classes."""
    full = np.zeros((proba.shape[0], count))
    full[:, np.asarray(seen, dtype=int)] = proba
    return full
