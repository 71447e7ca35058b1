# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The original's eight texture models in PyTorch, with Keras semantics kept.

Input (batch, window, channels), output logits over the classes; the softmax of the
original's last layer is applied by `predict_proba` (training uses log-softmax inside
the cross-entropy, the same model with a numerically safer loss). Keras defaults kept:
Conv1D 'valid' padding with ReLU, MaxPooling1D of 2, BatchNormalization over the
feature axis (momentum 0.99 in Keras is 0.01 in PyTorch, epsilon 1e-3), Dropout before
BatchNormalization where the original has it, LSTM layers returning sequences except
the last, which returns its final state (for a bidirectional layer: the forward
direction's last step and the backward direction's first, concatenated, as Keras does).

Initialisation is Keras's, not PyTorch's (whose kaiming-uniform kernels and non-zero
biases train differently): Glorot-uniform kernels in every Conv1D, Dense and LSTM input
kernel, orthogonal recurrent kernels, zero biases except the LSTM forget gate's, which
is 1 (Keras's unit_forget_bias; PyTorch adds two bias vectors, so the input one carries
it), BatchNormalization at gamma 1, beta 0. Its effect on convergence (epochs to 95 %
training accuracy, before and after) is measured by bench/bench_init.py.

Choices where the original is silent: every convolution uses ReLU; an unqualified
"Dropout" is 0.1 (0.5 in the models that say so); in cnn_bilstm_1 the BiLSTM 16
returns its final state, like cnn_bilstm_3.
"""

from __future__ import annotations

from collections.abc import Callable
import functools

import torch
from torch import nn

from tactex_classify.errors import WindowError
from tactex_classify.models import modern_architectures
from tactex_classify.models.registry import DEEP_MODELS, ORIGINAL_MODELS


class _BatchNorm(nn.Module):
    """Keras BatchNormalization on (batch, time, features) or (batch, features)."""

    def __init__(self, features: int) -> None:
        super().__init__()
        self.norm = nn.BatchNorm1d(features, eps=1e-3, momentum=0.01)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        if x.dim() == 3:
            return self.norm(x.transpose(1, 2)).transpose(1, 2)
        return self.norm(x)


class _Conv(nn.Module):
    """Keras Conv1D (valid padding, ReLU) on (batch, time, features)."""

    def __init__(self, inputs: int, filters: int, kernel: int) -> None:
        super().__init__()
        self.conv = nn.Conv1d(inputs, filters, kernel)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return torch.relu(self.conv(x.transpose(1, 2))).transpose(1, 2)


class _MaxPool(nn.Module):
    """Keras MaxPooling1D(2) on (batch, time, features)."""

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return nn.functional.max_pool1d(x.transpose(1, 2), 2).transpose(1, 2)


class _Recurrent(nn.Module):
    """Keras (Bidirectional) LSTM: the whole sequence, or the final state."""

    def __init__(self, inputs: int, units: int, *, bidirectional: bool,
                 return_sequences: bool) -> None:
        super().__init__()
        self.lstm = nn.LSTM(inputs, units, batch_first=True, bidirectional=bidirectional)
        self.units = units
        self.bidirectional = bidirectional
        self.return_sequences = return_sequences

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        output, _ = self.lstm(x)
        if self.return_sequences:
            return output
        if not self.bidirectional:
            return output[:, -1]
        return torch.cat([output[:, -1, :self.units], output[:, 0, self.units:]], dim=1)


class _Flatten(nn.Module):
    def forward(self, x: torch.Tensor) -> torch.Tensor:
        return x.reshape(x.shape[0], -1)


class _Dense(nn.Module):
    def __init__(self, inputs: int, units: int, relu: bool) -> None:
        super().__init__()
        self.linear = nn.Linear(inputs, units)
        self.relu = relu

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        y = self.linear(x)
        return torch.relu(y) if self.relu else y


class _Builder:
    """Stack layers while tracking the feature width and the time length."""

    def __init__(self, window: int, channels: int) -> None:
        self.layers: list[nn.Module] = []
        self.width = channels
        self.time = window

    def conv(self, filters: int, kernel: int) -> _Builder:
        self.layers.append(_Conv(self.width, filters, kernel))
        self.width, self.time = filters, self._left(self.time - kernel + 1)
        return self

    def pool(self) -> _Builder:
        self.layers.append(_MaxPool())
        self.time = self._left(self.time // 2)
        return self

    @staticmethod
    def _left(time: int) -> int:
        if time < 1:
            raise ValueError('the window is too short for this model')
        return time

    def dropout_norm(self, rate: float) -> _Builder:
        self.layers += [nn.Dropout(rate), _BatchNorm(self.width)]
        return self

    def lstm(self, units: int, *, bidirectional: bool = True,
             return_sequences: bool = True) -> _Builder:
        self.layers.append(_Recurrent(self.width, units, bidirectional=bidirectional,
                                      return_sequences=return_sequences))
        self.width = units * (2 if bidirectional else 1)
        return self

    def flatten(self) -> _Builder:
        self.layers.append(_Flatten())
        self.width *= self.time
        return self

    def dense(self, units: int, relu: bool = True) -> _Builder:
        self.layers.append(_Dense(self.width, units, relu))
        self.width = units
        return self

    def build(self) -> nn.Sequential:
        return nn.Sequential(*self.layers)


def _cnn_bilstm(window, channels, classes, rate: float, pool_each: bool) -> nn.Sequential:
    b = _Builder(window, channels).conv(128, 3)
    if pool_each:
        b.pool().dropout_norm(rate)
    b.conv(64, 3).pool().dropout_norm(rate)
    b.lstm(64).dropout_norm(rate).lstm(32).dropout_norm(rate)
    b.lstm(16, return_sequences=False).dropout_norm(rate)
    return b.dense(classes, relu=False).build()


def cnn_bilstm_1(window: int, channels: int, classes: int) -> nn.Sequential:
    """Conv 128 k3, Conv 64 k3, MaxPool, Dropout 0.1 + BN, BiLSTM 64 -> 32 -> 16, Dense."""
    return _cnn_bilstm(window, channels, classes, 0.1, pool_each=False)


def cnn_bilstm_2(window: int, channels: int, classes: int) -> nn.Sequential:
    """Two conv blocks (128, 64 k3 + pool + dropout + BN), BiLSTM 64, LSTM 32, Dense 16, 12."""
    b = _Builder(window, channels)
    b.conv(128, 3).pool().dropout_norm(0.1).conv(64, 3).pool().dropout_norm(0.1)
    b.lstm(64).dropout_norm(0.1)
    b.lstm(32, bidirectional=False, return_sequences=False).dropout_norm(0.1)
    return b.dense(16).dense(classes, relu=False).build()


def cnn_bilstm_3(window: int, channels: int, classes: int) -> nn.Sequential:
    """As cnn_bilstm_1 with Dropout 0.5 and a MaxPool after each conv block."""
    return _cnn_bilstm(window, channels, classes, 0.5, pool_each=True)


def cnn_1(window: int, channels: int, classes: int) -> nn.Sequential:
    """Conv 128 k5 block, Conv 64, Conv 32 block, Conv 16, Flatten, Dense."""
    b = _Builder(window, channels)
    b.conv(128, 5).pool().dropout_norm(0.1).conv(64, 5)
    b.conv(32, 5).pool().dropout_norm(0.1).conv(16, 5)
    return b.flatten().dense(classes, relu=False).build()


def cnn_2(window: int, channels: int, classes: int) -> nn.Sequential:
    """Two conv blocks (128, 64 k5), Flatten, Dense 64 + Dropout + BN, Dense."""
    b = _Builder(window, channels)
    b.conv(128, 5).pool().dropout_norm(0.1).conv(64, 5).pool().dropout_norm(0.1)
    b.flatten().dense(64).dropout_norm(0.1)
    return b.dense(classes, relu=False).build()


def cnn_3(window: int, channels: int, classes: int) -> nn.Sequential:
    """Four conv blocks (128, 64, 32, 16 k5), Flatten, Dense."""
    b = _Builder(window, channels)
    for filters in (128, 64, 32, 16):
        b.conv(filters, 5).pool().dropout_norm(0.1)
    return b.flatten().dense(classes, relu=False).build()


def _bilstm(window, channels, classes, rate: float) -> nn.Sequential:
    b = _Builder(window, channels).lstm(128).dropout_norm(rate)
    b.lstm(64, return_sequences=False).dropout_norm(rate)
    return b.dense(32).dense(classes, relu=False).build()


def bilstm_1(window: int, channels: int, classes: int) -> nn.Sequential:
    """BiLSTM 128 (sequences) + Dropout 0.1 + BN, BiLSTM 64 + same, Dense 32, Dense."""
    return _bilstm(window, channels, classes, 0.1)


def bilstm_2(window: int, channels: int, classes: int) -> nn.Sequential:
    """As bilstm_1 with Dropout 0.5."""
    return _bilstm(window, channels, classes, 0.5)


# The builders by name; the names (and their order) come from the registry alone.
MODELS: dict[str, Callable[[int, int, int], nn.Module]] = {
    name: globals()[name] if name in ORIGINAL_MODELS else getattr(modern_architectures, name)
    for name in DEEP_MODELS}


def keras_initialise(model: nn.Module) -> nn.Module:
    """Give every layer Keras's default initial weights (see the module docstring)."""
    for layer in model.modules():
        if isinstance(layer, (nn.Conv1d, nn.Linear)):
            nn.init.xavier_uniform_(layer.weight)
            if layer.bias is not None:
                nn.init.zeros_(layer.bias)
        elif isinstance(layer, nn.LSTM):
            for name, parameter in layer.named_parameters():
                if name.startswith('weight_ih'):
                    nn.init.xavier_uniform_(parameter)
                elif name.startswith('weight_hh'):
                    nn.init.orthogonal_(parameter)
                else:
                    nn.init.zeros_(parameter)
                    if name.startswith('bias_ih'):  # gates i, f, g, o: f is the second
                        parameter.data[layer.hidden_size:2 * layer.hidden_size] = 1.0
        elif isinstance(layer, nn.BatchNorm1d):
            nn.init.ones_(layer.weight)
            nn.init.zeros_(layer.bias)
    return model


def output_parameters(model: nn.Module) -> set[str]:
    """Names of the parameters of the layers that output the classes.

    The original models end in their output layer; the modern ones name theirs `head`
    (an ensemble has one per member).
    """
    if isinstance(model, nn.Sequential):
        last = str(len(model) - 1)
        return {name for name, _ in model.named_parameters() if name.split('.')[0] == last}
    return {name for name, _ in model.named_parameters() if name.split('.')[-2] == 'head'}


def build_model(name: str, window: int, channels: int, classes: int, *,
                keras_init: bool = True) -> nn.Module:
    """The model called `name`, initialised as Keras would (PyTorch's defaults if not).

    Raises:
        ValueError: unknown name (the message lists them) or a window too short for it.
    """
    if name not in MODELS:
        raise ValueError(f'unknown model {name!r}; known: {", ".join(MODELS)}')
    model = MODELS[name](window, channels, classes)
    return keras_initialise(model) if keras_init else model


@functools.cache
def min_window(name: str) -> int:
    """The fewest samples per window the deep model called `name` takes.

    Each builder refuses a window too short for its convolutions, pooling or patches (a
    ValueError), and takes every longer one; so the shortest it builds, found by doubling
    then bisecting over builds on the meta device (no weights allocated), is exact.
    """
    def builds(window: int) -> bool:
        try:
            with torch.device('meta'):
                MODELS[name](window, 1, 2)
        except ValueError:
            return False
        return True

    low, high = 0, 1  # low: too short (or 0), high: builds
    while not builds(high):
        low, high = high, 2 * high
    while high - low > 1:
        middle = (low + high) // 2
        low, high = (low, middle) if builds(middle) else (middle, high)
    return high


def check_window(name: str, window: int) -> None:
    """Refuse windows of `window` samples that the deep model `name` cannot take.

    Raises:
        WindowError: naming --model, both lengths and the ways out.
    """
    needed = min_window(name)
    if window < needed:
        raise WindowError(f'--model {name} needs windows of at least {needed} samples, the '
                          f"data's are {window}: convert (or import) with --window {needed} or "
                          'more, or choose another --model')
