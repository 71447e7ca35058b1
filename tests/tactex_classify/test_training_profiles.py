# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The deep models' two training profiles, the augmentations and per-window scaling."""

import dataclasses

import numpy as np
import pytest
from support.toy_windows import CLASSES, STREAM, toy
import torch

from tactex_classify.models.registry import AUGMENTATIONS
from tactex_classify.models.windows import ChannelScaler
from tactex_classify.training import augmentation
from tactex_classify.training.deep_classifier import (
    DeepClassifier,
    MODERN,
    TrainingConfig,
)


def test_the_original_profile_is_the_default_and_the_originals_training():
    assert TrainingConfig() == TrainingConfig.for_profile('original')
    original = TrainingConfig()
    assert (original.optimizer, original.schedule, original.learning_rate) == (
        'adamax', 'constant', 1e-3)
    assert original.augmentations == () and original.mixup_alpha == 0
    assert original.label_smoothing == original.ema_decay == original.weight_decay == 0
    assert original.batchnorm_momentum == 0.01  # Keras's 0.99


def test_the_modern_profile_sets_each_element_and_a_given_setting_wins():
    modern = TrainingConfig.for_profile('modern', model='cnn_3', label_smoothing=0.0)
    assert modern.profile == 'modern' and modern.model == 'cnn_3'
    assert modern.label_smoothing == 0.0
    assert (modern.optimizer, modern.schedule) == ('adamw', 'warmup_cosine')
    assert modern.augmentations == AUGMENTATIONS and modern.mixup_alpha > 0
    assert modern.ema_decay > 0 and modern.batchnorm_momentum == 0.1
    assert modern.early_stopping > 0
    assert set(MODERN) <= {field.name for field in dataclasses.fields(TrainingConfig)}


@pytest.mark.parametrize('change, named', [
    ({'augmentations': ('shift', 'twist')}, 'augmentations'),
    ({'label_smoothing': 0.9}, 'label_smoothing'),
    ({'ema_decay': 1.0}, 'ema_decay'),
    ({'optimizer': 'sgd'}, 'optimizer'),
    ({'schedule': 'cyclic'}, 'schedule'),
    ({'mixup_alpha': -1}, 'mixup_alpha'),
    ({'warmup_epochs': -1}, 'warmup_epochs'),
    ({'scaling': 'robust'}, 'scaling'),
])
def test_a_bad_setting_is_refused_by_name(change, named):
    with pytest.raises(ValueError, match=named):
        TrainingConfig.for_profile('modern', **change).check()
    with pytest.raises(ValueError, match='unknown profile'):
        TrainingConfig.for_profile('fancy')


def _batch(seed=0):
    generator = torch.Generator().manual_seed(seed)
    return torch.randn(64, 96, 10, generator=generator)


@pytest.mark.parametrize('name', AUGMENTATIONS)
def test_each_augmentation_keeps_the_shape_and_changes_about_half_the_windows(name):
    batch = _batch()
    out = augmentation.augment(batch, (name,), torch.Generator().manual_seed(1))
    assert out.shape == batch.shape and torch.isfinite(out).all()
    changed = (out != batch).flatten(1).any(dim=1).float().mean().item()
    assert 0.25 < changed < 0.75
    again = augmentation.augment(batch, (name,), torch.Generator().manual_seed(1))
    torch.testing.assert_close(out, again)  # a seed reproduces it


def test_shift_and_warp_read_the_window_along_a_monotone_time_axis():
    ramp = torch.arange(96, dtype=torch.float32).reshape(1, 96, 1).repeat(32, 1, 3)
    generator = torch.Generator().manual_seed(2)
    shifted = augmentation.shift(ramp, generator)
    steps = torch.diff(shifted, dim=1)
    assert torch.all((steps == 0) | (steps == 1))  # whole samples, edges repeated
    warped = augmentation.warp(ramp, generator)
    assert torch.all(torch.diff(warped, dim=1) >= 0)
    torch.testing.assert_close(warped[:, 0], ramp[:, 0])
    torch.testing.assert_close(warped[:, -1], ramp[:, -1])


def test_channel_dropout_zeroes_whole_channels_and_scale_keeps_zero_crossings():
    batch = _batch() + 5.0
    dropped = augmentation.channel_dropout(batch, torch.Generator().manual_seed(3))
    per_channel = (dropped == 0).all(dim=1)
    assert per_channel.any() and torch.equal((dropped == 0).any(dim=1), per_channel)
    scaled = augmentation.scale(_batch(), torch.Generator().manual_seed(3))
    assert torch.equal(torch.sign(scaled), torch.sign(_batch()))


def test_mixup_mixes_each_window_with_a_partner_by_the_given_weight():
    batch = _batch()
    mixed, partners = augmentation.mixup(batch, 0.7, torch.Generator().manual_seed(4))
    torch.testing.assert_close(mixed, 0.7 * batch + 0.3 * batch[partners])
    assert sorted(partners.tolist()) == list(range(len(batch)))


def test_window_scaling_removes_each_windows_offset_but_keeps_amplitude():
    wave = np.sin(np.linspace(0, 12, 96))[None, :, None]
    windows = np.concatenate([wave + 3.0, wave - 40.0, 2 * wave + 7.0]).astype(np.float32)
    scaler = ChannelScaler('window').fit(windows)
    scaled = scaler.transform(windows)
    np.testing.assert_allclose(scaled[0], scaled[1], atol=1e-5)
    np.testing.assert_allclose(scaled[2], 2 * scaled[0], atol=1e-5)
    restored = ChannelScaler.from_state(dataclasses.asdict(scaler), 1)
    np.testing.assert_array_equal(restored.transform(windows), scaled)


def test_a_modern_training_learns_and_its_checkpoint_keeps_the_profile(tmp_path):
    data = toy(recordings_per_class=20, windows=8)
    train = data.trial % 100 < 14
    config = TrainingConfig.for_profile('modern', model='cnn_1', epochs=25, batch_size=16,
                                        early_stopping=0, seed=3)
    model = DeepClassifier(config).fit(data.X[train], data.y[train], CLASSES)
    held_out = np.mean(model.predict(data.X[~train]) == data.y[~train])
    assert held_out > 0.5  # well above the 1/3 of chance on unseen recordings
    rates = [record['learning_rate'] for record in model.history_]
    assert rates[0] < rates[4] and rates[-1] < 0.05 * max(rates)  # warm-up, then cosine
    loaded = DeepClassifier.load(model.save(tmp_path / 'ckpt', **STREAM))
    assert loaded.config == model.config and loaded.config.augmentations == AUGMENTATIONS
    np.testing.assert_array_equal(loaded.predict_proba(data.X[:5]),
                                  model.predict_proba(data.X[:5]))


def test_a_modern_model_keeps_the_averaged_weights():
    data = toy()
    config = TrainingConfig.for_profile('modern', model='cnn_3', epochs=3, early_stopping=0)
    averaged = DeepClassifier(config).fit(data.X, data.y, CLASSES)
    raw = DeepClassifier(dataclasses.replace(config, ema_decay=0.0)).fit(
        data.X, data.y, CLASSES)
    differs = [not torch.equal(a, b) for a, b in zip(
        averaged.model_.state_dict().values(), raw.model_.state_dict().values(), strict=True)]
    assert any(differs)
