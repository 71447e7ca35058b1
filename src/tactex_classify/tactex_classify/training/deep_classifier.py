# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Texture classifiers with one interface: the deep models (torch) and the fast baselines.

`fit(X, y, classes)` scales with state fitted on the training windows only (with early
stopping: on the recordings left after whole recordings are held out for validation),
trains, and keeps the scaler;
`predict_proba(X)` returns (n, n_classes) in `classes` order; checkpoints
(`tactex_classify.models.checkpoint`) hold the weights (`state_dict`, loaded with
`weights_only=True`) next to a JSON file with the classes, channels, window, hop, rate,
scaler state and model configuration.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass
import math
import os
from pathlib import Path
import time

import numpy as np

from tactex_classify.errors import CheckpointError, NotFittedError
from tactex_classify.models.checkpoint import Deployable, restore_fitted
from tactex_classify.models.registry import (
    AUGMENTATIONS,
    DEEP_MODELS,
    MAX_EPOCHS,
    PROFILE_NAMES,
)
from tactex_classify.models.windows import (
    channel_names,
    ChannelScaler,
    check_windows,
    SCALINGS,
    softmax,
)
from tactex_classify.training.convergence import (
    ran_out_still_falling,
    stalled_at_chance,
    unconverged_because,
)
from tactex_classify.training.training_state import KEEP_EVERY_S
from tactex_classify.training.validation import validation_split
from tactex_common.constants import MAX_SEED
from tactex_common.numbers import is_finite_number

os.environ.setdefault('OMP_WAIT_POLICY', 'PASSIVE')  # no spinning next to ROS nodes
INITS = ('keras', 'pytorch')
MAX_THREADS = 256


@dataclass
class TrainingConfig:
    """How a deep model trains; the defaults are the original's (profile `original`).

    The original trains with Adamax at lr 1e-3, clipping, batch 32, 250 epochs and Keras's
    BatchNorm momentum. `TrainingConfig.for_profile('modern', ...)` starts from current
    time-series practice instead (`MODERN`, each element cited there); any setting may
    still be given.
    """

    model: str = 'cnn_1'
    epochs: int = 250
    batch_size: int = 32
    learning_rate: float = 1e-3
    clip_norm: float = 1.0
    scaling: str = 'minmax'
    early_stopping: int = 0  # patience (epochs on a validation split) once off chance; 0: off
    validation_fraction: float = 0.1
    seed: int = 0
    threads: int = 1
    init: str = 'keras'  # initial weights: 'keras' (as the original) or 'pytorch' defaults
    profile: str = 'original'  # the preset the other settings started from
    optimizer: str = 'adamax'
    weight_decay: float = 0.0  # decoupled (AdamW) weight decay
    schedule: str = 'constant'  # or 'warmup_cosine': linear warm-up, then cosine to 0
    warmup_epochs: int = 0
    label_smoothing: float = 0.0
    ema_decay: float = 0.0  # exponential moving average of the weights per step; 0: off
    batchnorm_momentum: float = 0.01  # PyTorch's convention: 0.01 is Keras's 0.99
    augmentations: tuple[str, ...] = ()  # names of training.augmentation.AUGMENTATIONS
    mixup_alpha: float = 0.0  # Beta(alpha, alpha) mixing weight; 0: off
    pretrained: str = ''  # a deep checkpoint folder to start from (fine-tuning); '': none

    @classmethod
    def for_profile(cls, profile: str, **settings) -> TrainingConfig:
        """The settings of `profile` ('original' or 'modern'), updated by `settings`.

        Raises:
            ValueError: an unknown profile.
        """
        if profile not in PROFILES:
            raise ValueError(f'unknown profile {profile!r}; known: {", ".join(PROFILES)}')
        return cls(**{**PROFILES[profile], 'profile': profile, **settings})

    def check(self) -> TrainingConfig:
        """Return self if every setting is usable.

        Raises:
            ValueError: a setting out of its range (named, with the value).
        """
        if self.model not in DEEP_MODELS:
            raise ValueError(f'unknown model {self.model!r}; known: {", ".join(DEEP_MODELS)}')
        for name, low, high in (('epochs', 1, MAX_EPOCHS), ('batch_size', 2, 65536),
                                ('early_stopping', 0, MAX_EPOCHS), ('seed', 0, MAX_SEED),
                                ('threads', 1, MAX_THREADS), ('warmup_epochs', 0, MAX_EPOCHS)):
            value = getattr(self, name)
            if not isinstance(value, int) or isinstance(value, bool) or not low <= value <= high:
                raise ValueError(f'{name} must be an integer in {low}..{high}, got {value!r}')
        for name in ('learning_rate', 'clip_norm'):
            value = getattr(self, name)
            if not (is_finite_number(value) and 0 < value <= 1e6):
                raise ValueError(f'{name} must be finite, > 0 and <= 1e6, got {value!r}')
        for name, high in (('weight_decay', 1.0), ('label_smoothing', 0.5),
                           ('ema_decay', 1.0 - 1e-9), ('batchnorm_momentum', 1.0),
                           ('mixup_alpha', 100.0)):
            value = getattr(self, name)
            if not isinstance(value, (int, float)) or isinstance(value, bool) or not (
                    0.0 <= value <= high):
                raise ValueError(f'{name} must be a number in 0..{high:g}, got {value!r}')
        for name, allowed in (('init', INITS), ('scaling', SCALINGS), ('profile', PROFILES),
                              ('optimizer', OPTIMIZERS), ('schedule', SCHEDULES)):
            if getattr(self, name) not in allowed:
                raise ValueError(f'{name} must be one of {allowed}, got {getattr(self, name)!r}')
        if not isinstance(self.augmentations, (list, tuple)) or not set(
                self.augmentations) <= set(AUGMENTATIONS):
            raise ValueError(f'augmentations must name some of {AUGMENTATIONS}, got '
                             f'{self.augmentations!r}')
        self.augmentations = tuple(self.augmentations)
        if not isinstance(self.pretrained, str):
            raise ValueError(f'pretrained must be a checkpoint folder or empty, got '
                             f'{self.pretrained!r}')
        fraction = self.validation_fraction
        if not isinstance(fraction, (int, float)) or not 0.0 < fraction < 1.0:
            raise ValueError(f'validation_fraction must be in (0, 1), got {fraction!r}')
        return self


OPTIMIZERS = ('adamax', 'adamw')
SCHEDULES = ('constant', 'warmup_cosine')
# Current time-series practice, each element ablated by bench/bench_profiles.py:
# AdamW (Loshchilov and Hutter, ICLR 2019) with linear warm-up (Goyal et al. 2017) and
# cosine decay (Loshchilov and Hutter, SGDR, ICLR 2017); label smoothing (Szegedy et al.,
# CVPR 2016); an exponential moving average of the weights (Polyak and Juditsky 1992;
# Tarvainen and Valpola 2017); PyTorch's BatchNorm momentum 0.1 (the running statistics
# follow the weights; Ioffe and Szegedy 2015); the augmentations of
# training.augmentation with mixup (Zhang et al., ICLR 2018); early stopping on
# recordings held out of training (Prechelt 1998), never on windows of trained ones.
MODERN = {'optimizer': 'adamw', 'weight_decay': 0.05, 'schedule': 'warmup_cosine',
          'warmup_epochs': 5, 'label_smoothing': 0.1, 'ema_decay': 0.99,
          'batchnorm_momentum': 0.1, 'augmentations': AUGMENTATIONS, 'mixup_alpha': 0.2,
          'early_stopping': 30}
PROFILES = dict(zip(PROFILE_NAMES, ({}, MODERN), strict=True))


class DeepClassifier(Deployable):
    """A deep model (the original eight or a modern one), trained as its profile says."""

    CHECKPOINT_KIND = 'deep'
    MODEL_FILE = 'weights.pt'

    def __init__(self, config: TrainingConfig | None = None, *,
                 progress: Callable[[dict], None] | None = None, device: str = 'cpu',
                 state_file: Path | None = None, state_every_s: float = KEEP_EVERY_S) -> None:
        self.config = config or TrainingConfig()
        self.progress = progress
        self.device = device  # where fit trains: 'cpu', 'cuda', 'cuda:1', ...
        # Where fit keeps its state between epochs (training_state); None: not kept.
        self.state_file, self.state_every_s = state_file, state_every_s
        self.model_ = None

    def fit(self, X, y, classes: list[str], groups=None, *,
            channels: Sequence[str] | None = None) -> DeepClassifier:
        """Train on windows X with class indices y (into `classes`).

        Args:
            X: (n, window, channels) windows, unscaled.
            y: (n,) class indices.
            classes: all class names (the output columns), even ones absent from y.
            groups: recording of each window; required with early stopping, which holds
                out whole recordings (GroupShuffleSplit) before the scaler is fitted.
            channels: names of X's channels (the dataset's); default this system's ten.
                Kept in the checkpoint and checked by `predict_proba(..., channels=...)`.

        With `state_file`, the state is kept there between epochs and a fit of the same
        data and settings resumes from it (`resumed_seconds_`: the training it had done;
        a file kept for another fit is set aside with a warning). The last epoch's state
        stays there, marked finished, until the caller has kept the result and
        `training_state.forget`s it.

        Raises:
            ValueError: bad windows, labels or settings; early stopping without groups,
                with fewer than two recordings, or with nothing left to train on.
            WindowError: windows shorter than the model takes (`check_window`).
        """
        import torch

        from tactex_classify.models.architectures import build_model, check_window
        from tactex_classify.training.augmentation import augment, mixup
        from tactex_classify.training.fine_tuning import start_from
        from tactex_classify.training.steps import (
            averaged_copy,
            batch_loss,
            optimizer_for,
            schedule_for,
            training_step,
        )
        from tactex_classify.training.training_state import (
            forget,
            kept_state,
            restore_state,
            training_key,
            TrainingState,
        )
        started = time.monotonic()
        config = self.config.check()
        X = check_windows(X)
        check_window(config.model, X.shape[1])
        y = np.asarray(y, dtype=np.int64)
        if y.shape != (len(X),) or (y.size and not 0 <= y.min() <= y.max() < len(classes)):
            raise ValueError(f'y must hold {len(X)} class indices into the {len(classes)} '
                             f'classes, got shape {y.shape!r}')
        torch.manual_seed(config.seed)
        torch.set_num_threads(config.threads)
        rng = np.random.default_rng(config.seed)
        self.classes_ = list(classes)
        self.window_, self.n_channels_ = X.shape[1], X.shape[2]
        self.channels_ = channel_names(channels, self.n_channels_)
        train, validation = validation_split(y, groups, config)
        self.scaler_ = ChannelScaler(config.scaling).fit(X[train])
        device = prepare_training_device(self.device)
        self.model_ = build_model(config.model, self.window_, self.n_channels_,
                                  len(self.classes_), keras_init=config.init == 'keras'
                                  ).to(device)
        if config.pretrained:
            start_from(self.model_, config.pretrained, config.model, self.window_,
                       self.channels_, self.classes_)
        for layer in self.model_.modules():
            if isinstance(layer, torch.nn.BatchNorm1d):
                layer.momentum = config.batchnorm_momentum
        optimizer = optimizer_for(self.model_, config)
        steps_per_epoch = max(1, math.ceil(train.size / config.batch_size))
        schedule = schedule_for(optimizer, config, steps_per_epoch)
        loss_fn = torch.nn.CrossEntropyLoss(label_smoothing=config.label_smoothing)
        averaged = averaged_copy(self.model_, config)
        evaluated = averaged.module if averaged is not None else self.model_
        generator = torch.Generator(device=device).manual_seed(config.seed)
        data = torch.from_numpy(self.scaler_.transform(X)).to(device)
        target = torch.from_numpy(y).to(device)
        train_data, train_target = data[torch.from_numpy(train)], target[torch.from_numpy(train)]
        best_loss, best_state, waited = math.inf, None, 0
        self.history_ = []
        self.best_epoch_, self.resumed_seconds_, first_epoch = 0, 0.0, 1
        keeper = TrainingState(self.state_file, training_key(
            config, X, y, groups, self.classes_, device), self.state_every_s
            ) if self.state_file else None
        parts = {'model': self.model_, 'optimizer': optimizer, 'schedule': schedule,
                 'averaged': averaged}
        kept = keeper.load() if keeper else None
        if kept:
            try:
                restore_state(kept, parts, generator, rng)
            except (KeyError, RuntimeError, TypeError, ValueError) as error:
                keeper.set_aside(f'does not fit this model ({error})')
                forget(keeper.path)
                return self.fit(X, y, classes, groups, channels=channels)
            self.history_, self.best_epoch_ = kept['history'], kept['best_epoch']
            best_loss, best_state, waited = kept['best_loss'], kept['best_state'], kept['waited']
            self.resumed_seconds_ = kept['seconds']
            first_epoch = config.epochs + 1 if kept.get('finished') else kept['epoch'] + 1
        for epoch in range(first_epoch, config.epochs + 1):
            self.model_.train()
            # One gather per epoch; each batch is then a contiguous slice of it. Loss and
            # hits add up on the device: no host round trip per batch.
            order = torch.from_numpy(rng.permutation(train.size)).to(device)
            shuffled, labels = train_data[order], train_target[order]
            loss_sum = torch.zeros((), dtype=torch.float64, device=device)
            hits = torch.zeros((), dtype=torch.int64, device=device)
            for start in range(0, train.size, config.batch_size):
                inputs = shuffled[start:start + config.batch_size]
                if len(inputs) < 2:
                    continue  # BatchNorm needs two samples to train
                expected = labels[start:start + config.batch_size]
                if config.augmentations:
                    inputs = augment(inputs, config.augmentations, generator)
                optimizer.zero_grad()
                partners, weight = None, 1.0
                if config.mixup_alpha:
                    weight = float(rng.beta(config.mixup_alpha, config.mixup_alpha))
                    inputs, partners = mixup(inputs, weight, generator)
                loss_of = batch_loss(loss_fn, expected, partners, weight)
                logits, loss = training_step(self.model_, inputs, loss_of, config.clip_norm)
                optimizer.step()
                if schedule is not None:
                    schedule.step()
                if averaged is not None:
                    averaged.update_parameters(self.model_)
                loss_sum += loss.detach() * len(inputs)
                hits += (logits.detach().argmax(1) == expected).sum()
            record = {'epoch': epoch, 'train_loss': float(loss_sum) / max(train.size, 1),
                      'train_accuracy': int(hits) / max(train.size, 1),
                      'learning_rate': optimizer.param_groups[0]['lr']}
            if validation.size:
                logits = _logits(evaluated, data[torch.from_numpy(validation)],
                                 len(self.classes_))
                record['val_loss'] = float(torch.nn.functional.cross_entropy(
                    torch.from_numpy(logits), torch.from_numpy(y[validation])))
                record['val_accuracy'] = float(np.mean(logits.argmax(1) ==
                                                       y[validation]))
            self.history_.append(record)
            stop = False
            if config.early_stopping and validation.size:
                if record['val_loss'] < best_loss - 1e-6:
                    best_loss, waited, self.best_epoch_ = record['val_loss'], 0, epoch
                    best_state = {k: v.clone() for k, v in evaluated.state_dict().items()}
                elif not stalled_at_chance([r['train_loss'] for r in self.history_],
                                           len(self.classes_)):  # at chance it cannot judge
                    waited += 1
                    stop = waited >= config.early_stopping
            last = stop or epoch == config.epochs
            if keeper and (last or keeper.due()):
                keeper.save(kept_state(
                    parts, generator, rng, epoch=epoch, best_loss=best_loss,
                    best_state=best_state, waited=waited, best_epoch=self.best_epoch_,
                    history=self.history_, finished=last,
                    seconds=self.resumed_seconds_ + time.monotonic() - started))
            if self.progress:
                self.progress(record)
            if stop:
                break
        self.still_falling_ = ran_out_still_falling(
            [record['train_loss'] for record in self.history_], config.epochs)
        if best_state is None:
            best_state = evaluated.state_dict()
            self.best_epoch_ = len(self.history_)
        self.model_.load_state_dict(best_state)
        return self

    def unconverged_reason(self) -> str | None:
        """Why the last fit did not converge (`unconverged_because`), or None if it did."""
        return unconverged_because([record['train_loss'] for record in self.history_],
                                   len(self.classes_), self.config.epochs)

    def _logits(self, data) -> np.ndarray:
        """Logits of (n, window, channels) scaled windows, on the model's device."""
        return _logits(self.model_, data, len(self.classes_))

    def predict_proba(self, X, *, channels: Sequence[str] | None = None) -> np.ndarray:
        """(n, n_classes) probabilities in `classes_` order.

        Args:
            X: (n, window, channels) windows, unscaled, as at fit.
            channels: the data's channel names; must be the model's, in its order.

        Raises:
            NotFittedError: before fit or load.
            ValueError: other windows, channel count or channel names than at fit.
        """
        import torch
        if self.model_ is None:
            raise NotFittedError('DeepClassifier is not fitted; call fit first')
        if channels is not None and list(channels) != self.channels_:
            raise ValueError(f'the data has channels {list(channels)}, the model was fitted '
                             f'on {self.channels_}')
        X = check_windows(X, window=self.window_, channels=self.n_channels_)
        return softmax(self._logits(torch.from_numpy(self.scaler_.transform(X))))

    def predict(self, X, *, channels: Sequence[str] | None = None) -> np.ndarray:
        """Class indices (see `predict_proba`)."""
        return self.predict_proba(X, channels=channels).argmax(axis=1)

    @property
    def model_name(self) -> str:
        """The model's name (one of DEEP_MODELS)."""
        return self.config.model

    def checkpoint_fields(self) -> dict:
        """The checkpoint fields of this kind: the fitted scaler and the training settings.

        Raises:
            NotFittedError: before fit or load.
        """
        if self.model_ is None:
            raise NotFittedError('DeepClassifier is not fitted; nothing to save')
        return {'scaler': asdict(self.scaler_), 'config': asdict(self.config)}

    def write_model(self, path: Path) -> None:
        """Write the weights (a state_dict of tensors) to `path`."""
        import torch
        torch.save(self.model_.state_dict(), path)

    @classmethod
    def from_checkpoint(cls, info) -> DeepClassifier:
        """A saved classifier; refuses anything but plain, finite tensors in the weights file.

        Raises:
            KeyError, TypeError, ValueError: a missing or malformed field.
            CheckpointError: the weights file is refused or does not fit the model.
        """
        import pickle

        import torch

        from tactex_classify.models.architectures import build_model
        config = info.fields['config']
        if not isinstance(config, dict):
            raise TypeError(f'config must be an object, got {config!r}')
        self = cls(TrainingConfig(**config).check())
        restore_fitted(self, info)
        self.scaler_ = ChannelScaler.from_state(info.fields['scaler'], self.n_channels_)
        try:
            state = torch.load(info.model_file, weights_only=True, map_location='cpu')
        except (pickle.UnpicklingError, RuntimeError, EOFError, OSError, ValueError) as err:
            reason = (str(err).splitlines() or [type(err).__name__])[0]
            raise CheckpointError(f'{info.folder}: refused {info.model_file.name}: {reason}'
                                  ) from None
        if not isinstance(state, dict) or not all(
                isinstance(v, torch.Tensor) and bool(torch.isfinite(v).all())
                for v in state.values()):
            raise CheckpointError(f'{info.folder}: weights.pt must hold a state_dict of finite '
                                  f'tensors')
        self.model_ = build_model(self.config.model, self.window_, self.n_channels_,
                                  len(self.classes_))
        try:
            self.model_.load_state_dict(state)
        except (RuntimeError, TypeError, KeyError) as err:
            raise CheckpointError(f'{info.folder}: weights do not fit {self.config.model}: '
                                  f'{str(err).splitlines()[0]}') from None
        self.model_.eval()
        return self


def prepare_training_device(name: str):
    """The torch device to train on; for a GPU, cuDNN is first set to autotune (process-wide).

    With `torch.backends.cudnn.benchmark` cuDNN times its algorithms for each new input
    shape once and keeps the fastest: a training's few shapes (the batch, the last batch,
    the validation chunks) each pay that once. On an H200 it cut InceptionTime's GPU time
    per step from 35.9 to 3.9 ms and made a cell 2.3 times as fast (bench/bench_gpu_pace.py,
    kept in bench/results/gpu_pace.json). cuDNN may then choose other algorithms on another
    run, so a GPU training does not repeat its seed's result bit for bit (cuDNN's default
    algorithms did not promise that either).
    """
    import torch
    device = torch.device(name)
    if device.type == 'cuda':
        torch.backends.cudnn.benchmark = True
    return device


def _logits(model, data, classes: int) -> np.ndarray:
    """Logits of (n, window, channels) scaled windows by `model`, on its device."""
    import torch
    model.eval()
    if not len(data):
        return np.zeros((0, classes), dtype=np.float32)
    device = next(model.parameters()).device
    with torch.inference_mode():
        return torch.cat([model(data[i:i + 256].to(device))
                          for i in range(0, len(data), 256)]).cpu().numpy()
