# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What every model shares about windows: the checks, per-channel scaling, softmax."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tactex_classify.errors import NotFittedError
from tactex_common.channels import CHANNELS
from tactex_common.numbers import is_finite_number

SCALINGS = ('minmax', 'standard', 'window')
SCALED_LIMIT = 1e4


@dataclass
class ChannelScaler:
    """Per-channel scaling fitted on training windows: Min-Max (the original), z-score, or window.

    `window` removes each window's own per-channel mean first (the offsets of a mount
    tilt, a pressure baseline or a gyro bias drop out), then divides by the training
    windows' per-channel spread of what is left, so amplitude still tells textures apart.
    """

    kind: str = 'minmax'
    offset: list[float] | None = None
    scale: list[float] | None = None

    def fit(self, X: np.ndarray) -> ChannelScaler:
        """Fit on (n, window, channels); a constant channel gets scale 1.

        Raises:
            ValueError: no windows, NaN or inf in them, or an unknown kind.
        """
        if not X.size:
            raise ValueError(f'cannot fit a scaler on no data, got shape {X.shape!r}')
        if not np.all(np.isfinite(X)):
            raise ValueError('cannot fit a scaler on data with NaN or inf; drop them first')
        flat = self._centred(X).reshape(-1, X.shape[-1]).astype(np.float64)
        if self.kind == 'minmax':
            offset, span = flat.min(axis=0), flat.max(axis=0) - flat.min(axis=0)
        elif self.kind == 'standard':
            offset, span = flat.mean(axis=0), flat.std(axis=0)
        elif self.kind == 'window':
            offset, span = np.zeros(flat.shape[1]), flat.std(axis=0)
        else:
            raise ValueError(f'scaling must be one of {SCALINGS}, got {self.kind!r}')
        span[~(span > 1e-12)] = 1.0
        self.offset, self.scale = offset.tolist(), span.tolist()
        return self

    @classmethod
    def from_state(cls, state, channels: int) -> ChannelScaler:
        """A fitted scaler from its saved fields, checked against the channel count.

        Raises:
            TypeError, ValueError: not the saved form, another length, or a value that is
                not finite (a scale must also be > 0).
        """
        if not isinstance(state, dict) or set(state) != {'kind', 'offset', 'scale'}:
            raise TypeError(f'scaler must be an object with kind, offset, scale, got {state!r}')
        if state['kind'] not in SCALINGS:
            raise ValueError(f'scaler kind must be one of {SCALINGS}, got {state["kind"]!r}')
        arrays = {}
        for name in ('offset', 'scale'):
            values = state[name]
            if not isinstance(values, list) or len(values) != channels or not all(
                    is_finite_number(v) for v in values):
                raise ValueError(f'scaler {name} must be {channels} finite numbers (one per '
                                 f'channel), got {values!r}')
            arrays[name] = [float(v) for v in values]
        if min(arrays['scale']) <= 0.0:
            raise ValueError(f'scaler scale must be > 0, got {arrays["scale"]!r}')
        return cls(state['kind'], arrays['offset'], arrays['scale'])

    def transform(self, X: np.ndarray) -> np.ndarray:
        """Scaled copy of X (float32), clipped to +-SCALED_LIMIT so no layer can overflow.

        The training windows scale into [0, 1] (Min-Max) or a few units (z-score); a value
        10^4 training ranges away is corrupt, and a float32 inf would turn every logit NaN.
        """
        if self.offset is None:
            raise NotFittedError('ChannelScaler is not fitted')
        if X.shape[-1] != len(self.offset):
            raise ValueError(f'X has {X.shape[-1]} channels, the scaler was fitted on '
                             f'{len(self.offset)}')
        scaled = (self._centred(X) - np.array(self.offset)) / np.array(self.scale)
        return np.clip(scaled, -SCALED_LIMIT, SCALED_LIMIT).astype(np.float32)

    def _centred(self, X: np.ndarray) -> np.ndarray:
        """X less each window's per-channel mean (kind `window`), else X itself."""
        if self.kind != 'window':
            return X
        X = X.astype(np.float64)
        return X - X.mean(axis=1, keepdims=True)


def check_windows(X, *, window: int | None = None, channels: int | None = None) -> np.ndarray:
    """X as float32 (n, window, channels), finite.

    Raises:
        TypeError: not an array of 3 dimensions.
        ValueError: NaN or inf inside, or a window/channel count unlike the fitted one.
    """
    X = np.asarray(X)
    if X.ndim != 3:
        raise TypeError(f'X must be (n_windows, window, channels), got shape {X.shape!r}')
    if not np.all(np.isfinite(X)):
        bad = int(np.sum(~np.all(np.isfinite(X), axis=(1, 2))))
        raise ValueError(f'X contains NaN or inf in {bad} window(s); drop them first')
    if window is not None and X.shape[1:] != (window, channels):
        raise ValueError(f'X windows are {X.shape[1:]}, the model was fitted on '
                         f'({window}, {channels})')
    return X.astype(np.float32)


def channel_names(channels, count: int) -> list[str]:
    """The fitted channels' names: given, or this system's channels when there are ten.

    Raises:
        ValueError: no names for a channel count other than ten, or a count mismatch.
    """
    if channels is None:
        if count != len(CHANNELS):
            raise ValueError(f'X has {count} channels: pass their names (channels=...)')
        return list(CHANNELS)
    names = [str(name) for name in channels]
    if len(names) != count:
        raise ValueError(f'{len(names)} channel names for {count} channels')
    return names


def softmax(logits: np.ndarray) -> np.ndarray:
    """Row-wise softmax of (n, classes) logits: a distribution for any finite logits.

    Raises:
        ValueError: not (n, classes >= 1), or a logit that is not finite.
    """
    logits = np.asarray(logits)
    if logits.ndim != 2 or logits.shape[1] < 1:
        raise ValueError(f'logits must be (n, classes >= 1), got shape {logits.shape!r}')
    if not np.all(np.isfinite(logits)):
        raise ValueError('logits must be finite; the model produced NaN or inf')
    if not len(logits):
        return np.zeros(logits.shape, dtype=logits.dtype)
    # The largest logit maps to exp(0) = 1, so no row sums below 1; a difference that
    # overflows to -inf just gives 0.
    with np.errstate(over='ignore'):
        shifted = logits - logits.max(axis=1, keepdims=True)
    exp = np.exp(shifted)
    return exp / exp.sum(axis=1, keepdims=True)
