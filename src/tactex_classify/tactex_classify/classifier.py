# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Texture classifiers with one interface: the deep models (torch) and the fast baselines.

`fit(X, y, classes)` scales with state fitted on X only, trains, and keeps the scaler;
`predict_proba(X)` returns (n, n_classes) in `classes` order; checkpoints hold the
weights (`state_dict`, loaded with `weights_only=True`) next to a JSON file with the
classes, channels, window, scaler state and model configuration.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import asdict, dataclass
import json
import math
import os
from pathlib import Path

import numpy as np

from tactex_classify.errors import CheckpointError, NotFittedError
from tactex_common.channels import CHANNELS

os.environ.setdefault('OMP_WAIT_POLICY', 'PASSIVE')  # no spinning next to ROS nodes
CHECKPOINT_VERSION = 1


@dataclass
class ChannelScaler:
    """Per-channel scaling fitted on training windows: Min-Max (the original) or z-score."""

    kind: str = 'minmax'
    offset: list[float] | None = None
    scale: list[float] | None = None

    def fit(self, X: np.ndarray) -> ChannelScaler:
        """Fit on (n, window, channels); a constant channel gets scale 1."""
        flat = X.reshape(-1, X.shape[-1]).astype(np.float64)
        if self.kind == 'minmax':
            offset, span = flat.min(axis=0), flat.max(axis=0) - flat.min(axis=0)
        elif self.kind == 'standard':
            offset, span = flat.mean(axis=0), flat.std(axis=0)
        else:
            raise ValueError(f'scaling must be minmax or standard, got {self.kind!r}')
        span[~(span > 1e-12)] = 1.0
        self.offset, self.scale = offset.tolist(), span.tolist()
        return self

    def transform(self, X: np.ndarray) -> np.ndarray:
        """Scaled copy of X (float32)."""
        if self.offset is None:
            raise NotFittedError('ChannelScaler is not fitted')
        if X.shape[-1] != len(self.offset):
            raise ValueError(f'X has {X.shape[-1]} channels, the scaler was fitted on '
                             f'{len(self.offset)}')
        return ((X - np.array(self.offset)) / np.array(self.scale)).astype(np.float32)


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
    """Row-wise softmax, finite for any finite logits (even +-1e4)."""
    shifted = logits - logits.max(axis=1, keepdims=True)
    exp = np.exp(shifted)
    return exp / exp.sum(axis=1, keepdims=True)


@dataclass
class TrainingConfig:
    """The original's training: Adamax, lr 1e-3, clipping, batch 32, 250 epochs."""

    model: str = 'cnn_1'
    epochs: int = 250
    batch_size: int = 32
    learning_rate: float = 1e-3
    clip_norm: float = 1.0
    scaling: str = 'minmax'
    early_stopping: int = 0  # patience in epochs on a validation split; 0: off
    validation_fraction: float = 0.1
    seed: int = 0
    threads: int = 1


class DeepClassifier:
    """One of the eight models, trained as the original trained them."""

    def __init__(self, config: TrainingConfig | None = None, *,
                 progress: Callable[[dict], None] | None = None) -> None:
        self.config = config or TrainingConfig()
        self.progress = progress
        self.model_ = None

    def fit(self, X, y, classes: list[str], groups=None, channels=None) -> DeepClassifier:
        """Train on windows X with class indices y (into `classes`).

        Args:
            X: (n, window, channels) windows, unscaled.
            y: (n,) class indices.
            classes: all class names (the output columns), even ones absent from y.
            groups: recording of each window; the early-stopping split keeps them whole.
            channels: names of X's channels (the dataset's); default this system's ten.
        """
        import torch

        from tactex_classify.models import build_model
        config = self.config
        X = check_windows(X)
        y = np.asarray(y, dtype=np.int64)
        torch.manual_seed(config.seed)
        torch.set_num_threads(config.threads)
        rng = np.random.default_rng(config.seed)
        self.classes_ = list(classes)
        self.window_, self.n_channels_ = X.shape[1], X.shape[2]
        self.channels_ = channel_names(channels, self.n_channels_)
        self.scaler_ = ChannelScaler(config.scaling).fit(X)
        train, validation = _validation_split(y, groups, config, rng)
        self.model_ = build_model(config.model, self.window_, self.n_channels_,
                                  len(self.classes_))
        optimizer = torch.optim.Adamax(self.model_.parameters(), lr=config.learning_rate)
        loss_fn = torch.nn.CrossEntropyLoss()
        data = torch.from_numpy(self.scaler_.transform(X))
        target = torch.from_numpy(y)
        best_loss, best_state, waited = math.inf, None, 0
        self.history_ = []
        for epoch in range(1, config.epochs + 1):
            self.model_.train()
            order = train[rng.permutation(train.size)]
            total, correct = 0.0, 0
            for start in range(0, order.size, config.batch_size):
                batch = order[start:start + config.batch_size]
                if batch.size < 2:
                    continue  # BatchNorm needs two samples to train
                optimizer.zero_grad()
                logits = self.model_(data[batch])
                loss = loss_fn(logits, target[batch])
                loss.backward()
                torch.nn.utils.clip_grad_norm_(self.model_.parameters(), config.clip_norm)
                optimizer.step()
                total += float(loss.detach()) * batch.size
                correct += int((logits.argmax(1) == target[batch]).sum())
            record = {'epoch': epoch, 'train_loss': total / max(train.size, 1),
                      'train_accuracy': correct / max(train.size, 1)}
            if validation.size:
                logits = self._logits(data[validation])
                record['val_loss'] = float(loss_fn(torch.from_numpy(logits),
                                                   target[validation]))
                record['val_accuracy'] = float(np.mean(logits.argmax(1) ==
                                                       y[validation]))
            self.history_.append(record)
            if self.progress:
                self.progress(record)
            if config.early_stopping and validation.size:
                if record['val_loss'] < best_loss - 1e-6:
                    best_loss, waited = record['val_loss'], 0
                    best_state = {k: v.clone() for k, v in self.model_.state_dict().items()}
                else:
                    waited += 1
                    if waited >= config.early_stopping:
                        break
        if best_state is not None:
            self.model_.load_state_dict(best_state)
        return self

    def _logits(self, data) -> np.ndarray:
        import torch
        self.model_.eval()
        with torch.no_grad():
            return np.concatenate([self.model_(data[i:i + 256]).numpy()
                                   for i in range(0, len(data), 256)])

    def predict_proba(self, X) -> np.ndarray:
        """(n, n_classes) probabilities in `classes_` order."""
        import torch
        if self.model_ is None:
            raise NotFittedError('DeepClassifier is not fitted; call fit first')
        X = check_windows(X, window=self.window_, channels=self.n_channels_)
        return softmax(self._logits(torch.from_numpy(self.scaler_.transform(X))))

    def predict(self, X) -> np.ndarray:
        """Class indices."""
        return self.predict_proba(X).argmax(axis=1)

    def save(self, folder: Path) -> Path:
        """Write weights.pt (state_dict) and checkpoint.json into `folder`."""
        import torch
        if self.model_ is None:
            raise NotFittedError('DeepClassifier is not fitted; nothing to save')
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        torch.save(self.model_.state_dict(), folder / 'weights.pt')
        meta = {'format_version': CHECKPOINT_VERSION, 'kind': 'deep', 'classes': self.classes_,
                'channels': self.channels_, 'window': self.window_,
                'scaler': asdict(self.scaler_), 'config': asdict(self.config)}
        (folder / 'checkpoint.json').write_text(json.dumps(meta, indent=2), encoding='utf-8')
        return folder

    @classmethod
    def load(cls, folder: Path) -> DeepClassifier:
        """A saved classifier; refuses anything but plain tensors in the weights file.

        Raises:
            CheckpointError: missing files, a foreign payload, or mismatching weights.
        """
        import pickle

        import torch

        from tactex_classify.models import build_model
        folder = Path(folder)
        try:
            meta = json.loads((folder / 'checkpoint.json').read_text(encoding='utf-8'))
            state = torch.load(folder / 'weights.pt', weights_only=True, map_location='cpu')
        except FileNotFoundError as err:
            raise CheckpointError(f'{folder}: missing {Path(err.filename).name}') from None
        except (pickle.UnpicklingError, RuntimeError, json.JSONDecodeError) as err:
            raise CheckpointError(f'{folder}: refused: {str(err).splitlines()[0]}') from None
        if meta.get('format_version') != CHECKPOINT_VERSION or meta.get('kind') != 'deep':
            raise CheckpointError(f'{folder}: not a tactex deep-model checkpoint')
        self = cls(TrainingConfig(**meta['config']))
        self.classes_, self.window_ = meta['classes'], meta['window']
        self.channels_ = list(meta['channels'])
        self.n_channels_ = len(self.channels_)
        self.scaler_ = ChannelScaler(**meta['scaler'])
        self.model_ = build_model(self.config.model, self.window_, self.n_channels_,
                                  len(self.classes_))
        try:
            self.model_.load_state_dict(state)
        except (RuntimeError, TypeError) as err:
            raise CheckpointError(f'{folder}: weights do not fit {self.config.model}: '
                                  f'{str(err).splitlines()[0]}') from None
        return self


def _validation_split(y: np.ndarray, groups, config: TrainingConfig,
                      rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Training and early-stopping indices; whole recordings go to one side."""
    indices = np.arange(y.size)
    if not config.early_stopping or config.validation_fraction <= 0:
        return indices, np.zeros(0, dtype=np.int64)
    keys = np.asarray(groups) if groups is not None else indices
    unique = rng.permutation(np.unique(keys))
    held = set(unique[:max(1, int(round(config.validation_fraction * unique.size)))].tolist())
    mask = np.array([k in held for k in keys])
    return indices[~mask], indices[mask]
