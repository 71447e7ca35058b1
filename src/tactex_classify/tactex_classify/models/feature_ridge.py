# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Random-kernel features + a ridge classifier: what MiniRocket, MultiRocket and HYDRA share.

Each is a transform fitted on z-scored training windows (channels differ by ten orders
of magnitude: pressure ~1e5 Pa, magnetic field ~1e-5 T), its features standardised,
and scikit-learn's RidgeClassifierCV choosing its regularisation by leave-one-out. A
subclass says how the transform fits (`_fit`, or `_fit_transform` where fitting
and transforming share a pass), transforms (`_features`), how
many features it gives and whether saved arrays fit each other; this base class fits
the head, predicts, and saves and loads everything as plain arrays (no pickle).
"""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

import numpy as np
from sklearn.linear_model import RidgeClassifierCV
from sklearn.preprocessing import StandardScaler

from tactex_classify.errors import CheckpointError, NotFittedError
from tactex_classify.models.checkpoint import Deployable, MAX_MODEL_BYTES, restore_fitted
from tactex_classify.models.windows import channel_names, ChannelScaler, check_windows, softmax
from tactex_common.files import check_npz_sizes, npz_refusal, open_regular

HEAD_ARRAYS = ('feature_mean_', 'feature_scale_', 'coef_', 'intercept_', 'seen_classes_')
RIDGE_ALPHAS = np.logspace(-3, 3, 10)


class FeatureRidge(Deployable):
    """A fitted transform of the windows, read by a ridge classifier."""

    MODEL_FILE = 'weights.npz'
    TRANSFORM_ARRAYS: tuple[str, ...] = ()
    # Config field -> (default, largest value a checkpoint may give).
    SETTINGS: dict[str, tuple[int, int]] = {}

    def __init__(self, **settings: int) -> None:
        unknown = set(settings) - set(self.SETTINGS)
        if unknown:
            raise TypeError(f'unknown settings {sorted(unknown)}; known: {sorted(self.SETTINGS)}')
        for name, (default, _) in self.SETTINGS.items():
            setattr(self, name, settings.get(name, default))
        self.coef_ = None

    @property
    def model_name(self) -> str:
        """The baseline's name (its checkpoint kind)."""
        return self.CHECKPOINT_KIND

    def _fit(self, Z: np.ndarray, rng: np.random.Generator) -> None:
        """Fit the transform on scaled training windows."""
        raise NotImplementedError

    def _fit_transform(self, Z: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """Fit the transform on scaled training windows; return their features."""
        self._fit(Z, rng)
        return self._features(Z)

    def _features(self, Z: np.ndarray) -> np.ndarray:
        """Features (n, count) of scaled windows."""
        raise NotImplementedError

    def _feature_count(self) -> int:
        """How many features the fitted transform gives."""
        raise NotImplementedError

    def _transform_fits(self) -> bool:
        """Whether the transform's saved arrays fit each other, the window and channels."""
        raise NotImplementedError

    def fit(self, X, y, classes, groups=None, channels=None) -> FeatureRidge:
        """Fit the transform and the ridge on the training windows."""
        del groups
        X = check_windows(X)
        rng = np.random.default_rng(self.seed)
        self.classes_ = list(classes)
        self.window_, self.n_channels_ = X.shape[1], X.shape[2]
        self.channels_ = channel_names(channels, self.n_channels_)
        self.scaler_ = ChannelScaler('standard').fit(X)
        features = self._fit_transform(self.scaler_.transform(X), rng)
        standard = StandardScaler().fit(features)
        ridge = RidgeClassifierCV(alphas=RIDGE_ALPHAS).fit(standard.transform(features),
                                                           np.asarray(y))
        # Inference needs only these arrays (no scikit-learn object is kept or saved).
        self.feature_mean_, self.feature_scale_ = standard.mean_, standard.scale_
        self.coef_, self.intercept_ = np.atleast_2d(ridge.coef_), np.atleast_1d(ridge.intercept_)
        self.seen_classes_ = np.asarray(ridge.classes_, dtype=np.int64)
        return self

    def predict_proba(self, X) -> np.ndarray:
        """Softmax of the ridge's decision values, one column per class in `classes_`."""
        if self.coef_ is None:
            raise NotFittedError(f'{type(self).__name__} is not fitted; call fit first')
        X = check_windows(X, window=self.window_, channels=self.n_channels_)
        if not len(X):
            return np.zeros((0, len(self.classes_)))
        features = self._features(self.scaler_.transform(X))
        scores = ((features - self.feature_mean_) / self.feature_scale_) @ self.coef_.T \
            + self.intercept_
        return full_columns(softmax(two_class(scores)), self.seen_classes_,
                            len(self.classes_))

    def checkpoint_fields(self) -> dict:
        """The channel scaler and the settings (the arrays go to weights.npz)."""
        if self.coef_ is None:
            raise NotFittedError(f'{type(self).__name__} is not fitted; nothing to save')
        return {'scaler': asdict(self.scaler_),
                'config': {name: getattr(self, name) for name in self.SETTINGS}}

    def write_model(self, path: Path) -> None:
        """Write the fitted arrays as an uncompressed .npz (no pickled objects)."""
        with open(path, 'wb') as handle:
            np.savez(handle, **{name: getattr(self, name)
                                for name in self.TRANSFORM_ARRAYS + HEAD_ARRAYS})

    @classmethod
    def from_checkpoint(cls, info) -> FeatureRidge:
        """A saved model: plain, finite arrays whose shapes are checked against each other.

        Raises:
            KeyError, TypeError, ValueError: a malformed field.
            CheckpointError: the arrays are refused (objects, NaN, shapes that disagree).
        """
        self = cls(**read_config(info, {name: high for name, (_, high)
                                        in cls.SETTINGS.items()}))
        restore_fitted(self, info)
        self.scaler_ = ChannelScaler.from_state(info.fields['scaler'], self.n_channels_)
        for name, value in read_arrays(info, cls.TRANSFORM_ARRAYS + HEAD_ARRAYS).items():
            setattr(self, name, value)
        seen, features = self.seen_classes_, None
        try:
            transform_fits = self._transform_fits()
            features = self._feature_count() if transform_fits else None
        except (IndexError, ValueError, TypeError):
            transform_fits = False
        head_fits = (transform_fits
                     and self.feature_mean_.shape == self.feature_scale_.shape == (features,)
                     and self.coef_.shape[1:] == (features,)
                     and self.intercept_.shape == self.coef_.shape[:1]
                     and seen.ndim == 1 and seen.size >= 2
                     and self.coef_.shape[0] == (1 if seen.size == 2 else seen.size)
                     and np.all((seen >= 0) & (seen < len(self.classes_)))
                     and np.all(self.feature_scale_ > 0))
        if not head_fits:
            raise CheckpointError(f'{info.folder}: {cls.MODEL_FILE} arrays do not fit each '
                                  f'other, {self.n_channels_} channels and '
                                  f'{len(self.classes_)} classes')
        return self


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
        raise CheckpointError(f'{info.folder}: refused {info.model_file.name}: '
                              f'{npz_refusal(err)}'
                              ) from None
    for name, value in arrays.items():
        if value.dtype.kind not in 'iuf' or not np.all(np.isfinite(value)):
            raise CheckpointError(f'{info.folder}: {info.model_file.name}: {name} must hold '
                                  f'finite numbers')
    return arrays


def two_class(scores: np.ndarray) -> np.ndarray:
    """Ridge gives one column of scores for two classes: make it two."""
    return np.concatenate([-scores, scores], axis=1) if scores.shape[1] == 1 else scores


def full_columns(proba: np.ndarray, seen: np.ndarray, count: int) -> np.ndarray:
    """Spread columns of the classes seen in training into all `count` classes."""
    full = np.zeros((proba.shape[0], count))
    full[:, np.asarray(seen, dtype=int)] = proba
    return full
