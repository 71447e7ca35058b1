# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Modern architectures: as their papers build them, trained and kept like the original eight."""

import numpy as np
import pytest
from support.toy_windows import CLASSES, STREAM, toy
import torch

from tactex_classify.models.architectures import build_model
from tactex_classify.models.modern_architectures import Ensemble, ENSEMBLE_MEMBERS
from tactex_classify.models.registry import DEEP_MODELS, MODERN_MODELS, ORIGINAL_MODELS
from tactex_classify.online.runtime import export_onnx
from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
from tactex_classify.training.steps import training_step

torch.set_num_threads(1)


def test_the_deep_models_are_the_original_eight_then_the_modern_ones():
    assert len(ORIGINAL_MODELS) == 8
    assert DEEP_MODELS == ORIGINAL_MODELS + MODERN_MODELS
    assert set(MODERN_MODELS) == {'inception_time', 'inception_time_ensemble', 'resnet',
                                  'self_attention', 'cnn_attention'}


@pytest.mark.parametrize('name', ['inception_time', 'resnet'])
def test_globally_pooled_networks_read_any_window_length(name):
    model = build_model(name, 128, 10, 12).eval()
    with torch.no_grad():
        assert model(torch.randn(2, 300, 10)).shape == (2, 12)


def test_inception_time_has_six_modules_of_four_branches_and_two_shortcuts():
    model = build_model('inception_time', 128, 10, 12)
    assert len(model.inception) == 6 and len(model.shortcuts) == 2
    kernels = [branch.kernel_size[0] for branch in model.inception[0].branches]
    assert kernels == [9, 19, 39]
    assert model.inception[0].norm.num_features == 128  # 3 convolutions + pooled, 32 each


def test_resnet_blocks_use_kernels_8_5_3_and_keep_the_length():
    model = build_model('resnet', 128, 10, 12)
    kernels = [layer.kernel_size[0] for layer in model.blocks[0].body
               if isinstance(layer, torch.nn.Conv1d)]
    assert kernels == [8, 5, 3]
    with torch.no_grad():
        assert model.blocks(torch.randn(2, 10, 128)).shape == (2, 128, 128)


def test_the_ensemble_averages_the_probabilities_of_differently_initialised_members():
    torch.manual_seed(0)
    model = build_model('inception_time_ensemble', 64, 10, 3).eval()
    assert isinstance(model, Ensemble) and len(model.members) == ENSEMBLE_MEMBERS
    first, second = (member.head.weight for member in model.members[:2])
    assert not torch.equal(first, second)
    x = torch.randn(4, 64, 10)
    with torch.no_grad():
        mean = torch.stack([torch.softmax(m(x), 1) for m in model.members]).mean(0)
        torch.testing.assert_close(torch.softmax(model(x), 1), mean)


def test_each_ensemble_member_trains_on_its_own_loss_as_if_alone():
    torch.manual_seed(0)
    model = build_model('inception_time_ensemble', 32, 10, 3)
    x, labels = torch.randn(6, 32, 10), torch.tensor([0, 1, 2, 0, 1, 2])

    def loss_of(logits):
        return torch.nn.functional.cross_entropy(logits, labels)
    training_step(model, x, loss_of, clip_norm=1e6)
    together = [p.grad.clone() for p in model.members[1].parameters()]
    model.zero_grad()
    loss_of(model.members[1](x)).backward()
    for joint, alone in zip(together, (p.grad for p in model.members[1].parameters()),
                            strict=True):
        torch.testing.assert_close(joint, alone)


@pytest.mark.slow
@pytest.mark.parametrize('name', ['inception_time', 'resnet', 'self_attention',
                                  'cnn_attention'])
def test_every_modern_model_learns_under_the_modern_profile(name):
    data = toy(recordings_per_class=8, windows=8, window=64)
    train = data.trial % 100 < 6
    config = TrainingConfig.for_profile('modern', model=name, epochs=25, batch_size=16,
                                        early_stopping=0, scaling='window', seed=1)
    model = DeepClassifier(config).fit(data.X[train], data.y[train], CLASSES)
    assert np.mean(model.predict(data.X[~train]) == data.y[~train]) > 0.6  # chance: 1/3


@pytest.mark.parametrize('name', MODERN_MODELS)
def test_every_modern_model_survives_a_checkpoint_and_exports_to_onnx(name, tmp_path):
    data = toy(recordings_per_class=2, windows=4, window=64)
    config = TrainingConfig.for_profile('modern', model=name, epochs=1, early_stopping=0)
    model = DeepClassifier(config).fit(data.X, data.y, CLASSES)
    loaded = DeepClassifier.load(model.save(tmp_path / 'ckpt', **STREAM))
    assert loaded.config.model == name
    np.testing.assert_allclose(loaded.predict_proba(data.X[:5]),
                               model.predict_proba(data.X[:5]), rtol=1e-5, atol=1e-6)
    assert export_onnx(tmp_path / 'ckpt', tmp_path / 'ckpt' / 'model.onnx').stat().st_size
