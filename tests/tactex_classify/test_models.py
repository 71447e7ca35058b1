# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The deep models: shapes at every window size, Keras semantics, numerically safe heads."""

import math

import numpy as np
import pytest
import torch

from tactex_classify.errors import WindowError
from tactex_classify.models.architectures import build_model, check_window, min_window, MODELS
from tactex_classify.models.registry import DEEP_MODELS
from tactex_classify.models.windows import softmax

torch.set_num_threads(1)


@pytest.mark.parametrize('name', list(MODELS))
@pytest.mark.parametrize('window', [128, 256, 512])
def test_every_model_maps_windows_to_class_logits(name, window):
    model = build_model(name, window, 10, 12).eval()
    with torch.no_grad():
        assert model(torch.randn(3, window, 10)).shape == (3, 12)


@pytest.mark.parametrize('name', list(MODELS))
def test_a_batch_of_one_works_in_eval_mode(name):
    model = build_model(name, 128, 10, 12).eval()
    with torch.no_grad():
        assert torch.all(torch.isfinite(model(torch.randn(1, 128, 10))))


def test_bidirectional_final_state_is_forward_last_and_backward_first():
    model = build_model('bilstm_1', 16, 10, 12)
    recurrent = model[3]  # BiLSTM 64 returning its final state
    x = torch.randn(2, 16, 256)
    full, _ = recurrent.lstm(x)
    out = recurrent(x)
    torch.testing.assert_close(out[:, :64], full[:, -1, :64])
    torch.testing.assert_close(out[:, 64:], full[:, 0, 64:])


def test_dropout_comes_before_batch_normalisation():
    names = [type(layer).__name__ for layer in build_model('cnn_3', 128, 10, 12)]
    assert names[:4] == ['_Conv', '_MaxPool', 'Dropout', '_BatchNorm']


def test_unknown_model_and_too_short_window_are_refused():
    with pytest.raises(ValueError, match='unknown model .lstm_fcn.; known: cnn_bilstm_1'):
        build_model('lstm_fcn', 128, 10, 12)
    with pytest.raises(ValueError, match='too short'):
        build_model('cnn_3', 16, 10, 12)


@pytest.mark.parametrize('name', DEEP_MODELS)
def test_min_window_is_the_shortest_window_each_model_builds_at(name):
    shortest = min_window(name)
    build_model(name, shortest, 10, 3)
    if shortest > 1:
        with pytest.raises(ValueError, match='too short'):
            build_model(name, shortest - 1, 10, 3)


def test_the_window_check_names_the_model_the_lengths_and_the_ways_out():
    assert (min_window('cnn_3'), min_window('cnn_1'), min_window('resnet')) == (76, 40, 1)
    check_window('cnn_3', 76)
    with pytest.raises(WindowError, match=r"^--model cnn_3 needs windows of at least 76 "
                       r"samples, the data's are 64: convert \(or import\) with --window 76 "
                       'or more, or choose another --model$'):
        check_window('cnn_3', 64)


def test_softmax_and_log_softmax_of_huge_logits_stay_finite():
    logits = np.array([[1e4, -1e4, 0.0], [-1e4, -1e4, -1e4]])
    probabilities = softmax(logits)
    assert np.all(np.isfinite(probabilities))
    np.testing.assert_allclose(probabilities.sum(axis=1), 1.0)
    log_probabilities = torch.log_softmax(torch.tensor(logits), dim=1)
    assert torch.all(torch.isfinite(log_probabilities))
    loss = torch.nn.functional.cross_entropy(torch.tensor(logits), torch.tensor([1, 0]))
    assert torch.isfinite(loss)


def test_the_catalog_names_exactly_the_models_that_exist():
    assert tuple(MODELS) == DEEP_MODELS


def _glorot_limit(weight: torch.Tensor) -> float:
    receptive = weight[0, 0].numel() if weight.dim() > 2 else 1
    return math.sqrt(6.0 / (weight.shape[0] * receptive + weight.shape[1] * receptive))


@pytest.mark.parametrize('name', list(MODELS))
def test_every_model_starts_from_keras_initial_weights(name):
    torch.manual_seed(0)
    model = build_model(name, 128, 10, 12)
    checked = 0
    for layer in model.modules():
        if isinstance(layer, (torch.nn.Conv1d, torch.nn.Linear)):
            limit = _glorot_limit(layer.weight)
            assert layer.weight.abs().max() <= limit
            if layer.weight.numel() >= 1000:  # uniform on +-limit: sd limit / sqrt(3)
                spread = float(layer.weight.detach().std())
                assert spread == pytest.approx(limit / math.sqrt(3), rel=0.1)
            assert layer.bias is None or torch.count_nonzero(layer.bias) == 0
            checked += 1
        elif isinstance(layer, torch.nn.LSTM):
            units = layer.hidden_size
            for parameter_name, parameter in layer.named_parameters():
                if parameter_name.startswith('weight_hh'):  # orthogonal columns
                    gram = parameter.T @ parameter
                    torch.testing.assert_close(gram, torch.eye(units), atol=1e-5, rtol=0)
                elif parameter_name.startswith('weight_ih'):
                    assert parameter.abs().max() <= _glorot_limit(parameter)
                elif parameter_name.startswith('bias_ih'):
                    expected = torch.zeros(4 * units)
                    expected[units:2 * units] = 1.0  # unit forget-gate bias
                    torch.testing.assert_close(parameter.detach(), expected)
                else:
                    assert torch.count_nonzero(parameter) == 0
            checked += 1
    assert checked >= 2


def test_pytorch_initialisation_stays_available_for_comparison():
    torch.manual_seed(0)
    model = build_model('cnn_3', 128, 10, 12, keras_init=False)
    assert torch.count_nonzero(model[0].conv.bias) > 0
