# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Current time-series architectures beside the original eight, each written from its paper.

Input (batch, window, channels), output logits over the classes, as the original models.
- `inception_time`: InceptionTime (Ismail Fawaz et al., "InceptionTime: finding AlexNet
  for time series classification", Data Min. Knowl. Disc. 34, 2020): six Inception
  modules (a 1x1 bottleneck of 32, three convolutions of 32 filters with kernels 10, 20
  and 40, here 9, 19 and 39 so that 'same' padding is symmetric, and a max-pool of 3
  followed by a 1x1 convolution of 32), BatchNorm and ReLU after the concatenation, a
  residual shortcut every three modules, global average pooling.
- `inception_time_ensemble`: the paper's ensemble of five InceptionTime networks that
  differ only in their initial weights; each member is trained on its own loss
  (`member_logits`) and the prediction averages their softmax outputs.
- `resnet`: the fully convolutional residual network of Wang, Yan and Oates ("Time series
  classification from scratch with deep neural networks: a strong baseline", IJCNN
  2017): three blocks of three convolutions (kernels 8, 5, 3; 64, 128, 128 filters), each
  followed by BatchNorm and ReLU, a shortcut per block (1x1 convolution and BatchNorm
  where the width changes), global average pooling.
- `self_attention`: a small Transformer encoder (Vaswani et al., "Attention is all you
  need", NeurIPS 2017) as Zerveas et al. apply it to multivariate series ("A
  transformer-based framework for multivariate time series representation learning",
  KDD 2021), reading the window as patches (Nie et al., "A time series is worth 64
  words", ICLR 2023): overlapping patches of 8 samples every 4, each projected to 64
  features, learned positional embeddings, two pre-norm encoder layers of four heads,
  mean pooling over the patches.
- `cnn_attention`: two convolution blocks (64 filters, kernel 5, BatchNorm, ReLU,
  max-pool 2) read local texture; one multi-head self-attention layer relates the
  pooled steps across the window; attention pooling (Raffel and Ellis, "Feed-forward
  networks with attention can solve some long-term memory problems", ICLR workshop
  2016) weighs them into one vector.

These use PyTorch's initialisation and BatchNorm defaults unless the training config
says otherwise; `architectures.build_model` builds them by name.
"""

from __future__ import annotations

import torch
from torch import nn

ENSEMBLE_MEMBERS = 5


def _channels_first(x: torch.Tensor) -> torch.Tensor:
    """(batch, time, channels) to (batch, channels, time)."""
    return x.transpose(1, 2)


class _InceptionModule(nn.Module):
    """Bottleneck, three kernel sizes and a pooled branch, concatenated; BN and ReLU."""

    def __init__(self, inputs: int, filters: int = 32, kernels=(9, 19, 39)) -> None:
        super().__init__()
        self.bottleneck = nn.Conv1d(inputs, filters, 1, bias=False) if inputs > 1 else None
        width = filters if inputs > 1 else inputs
        self.branches = nn.ModuleList(nn.Conv1d(width, filters, k, padding=k // 2, bias=False)
                                      for k in kernels)
        self.pooled = nn.Sequential(nn.MaxPool1d(3, stride=1, padding=1),
                                    nn.Conv1d(inputs, filters, 1, bias=False))
        self.norm = nn.BatchNorm1d(filters * (len(kernels) + 1))

    def forward(self, x: torch.Tensor) -> torch.Tensor:  # noqa: D102 (nn.Module's)
        narrow = self.bottleneck(x) if self.bottleneck is not None else x
        out = torch.cat([branch(narrow) for branch in self.branches] + [self.pooled(x)], 1)
        return torch.relu(self.norm(out))


class _Shortcut(nn.Module):
    """A residual shortcut: a 1x1 convolution and BatchNorm (or BatchNorm alone)."""

    def __init__(self, inputs: int, outputs: int) -> None:
        super().__init__()
        self.project = nn.Conv1d(inputs, outputs, 1, bias=False) if inputs != outputs \
            else nn.Identity()
        self.norm = nn.BatchNorm1d(outputs)

    def forward(self, x: torch.Tensor) -> torch.Tensor:  # noqa: D102 (nn.Module's)
        return self.norm(self.project(x))


class InceptionTime(nn.Module):
    """One InceptionTime network (depth 6, residual every 3 modules)."""

    def __init__(self, window: int, channels: int, classes: int, depth: int = 6) -> None:
        super().__init__()
        del window  # global pooling: any length
        width = 128
        self.inception = nn.ModuleList(
            _InceptionModule(channels if index == 0 else width) for index in range(depth))
        self.shortcuts = nn.ModuleList(
            _Shortcut(channels if index == 0 else width, width)
            for index in range(depth // 3))
        self.head = nn.Linear(width, classes)

    def forward(self, x: torch.Tensor) -> torch.Tensor:  # noqa: D102 (nn.Module's)
        x = _channels_first(x)
        residual = x
        for index, module in enumerate(self.inception):
            x = module(x)
            if index % 3 == 2:
                x = torch.relu(x + self.shortcuts[index // 3](residual))
                residual = x
        return self.head(x.mean(dim=2))


class Ensemble(nn.Module):
    """Members trained on their own losses; the output averages their probabilities.

    `forward` returns the log of the mean softmax (logits of the averaged distribution);
    `member_logits` returns each member's logits for training.
    """

    def __init__(self, members: list[nn.Module]) -> None:
        super().__init__()
        self.members = nn.ModuleList(members)

    def member_logits(self, x: torch.Tensor) -> list[torch.Tensor]:
        """Each member's logits."""
        return [member(x) for member in self.members]

    def forward(self, x: torch.Tensor) -> torch.Tensor:  # noqa: D102 (nn.Module's)
        probabilities = torch.stack([torch.softmax(logits, 1)
                                     for logits in self.member_logits(x)]).mean(0)
        return torch.log(probabilities.clamp_min(1e-12))


class _ResidualBlock(nn.Module):
    """Three convolutions (kernels 8, 5, 3) with BN and ReLU, plus a shortcut."""

    def __init__(self, inputs: int, filters: int) -> None:
        super().__init__()
        layers = []
        for index, kernel in enumerate((8, 5, 3)):
            layers += [nn.ConstantPad1d(((kernel - 1) // 2, kernel // 2), 0.0),  # 'same'
                       nn.Conv1d(inputs if index == 0 else filters, filters, kernel),
                       nn.BatchNorm1d(filters)]
            if index < 2:
                layers.append(nn.ReLU())
        self.body = nn.Sequential(*layers)
        self.shortcut = _Shortcut(inputs, filters)

    def forward(self, x: torch.Tensor) -> torch.Tensor:  # noqa: D102 (nn.Module's)
        return torch.relu(self.body(x) + self.shortcut(x))


class ResNet(nn.Module):
    """Wang et al.'s ResNet: blocks of 64, 128, 128 filters and global average pooling."""

    def __init__(self, window: int, channels: int, classes: int) -> None:
        super().__init__()
        del window
        self.blocks = nn.Sequential(_ResidualBlock(channels, 64), _ResidualBlock(64, 128),
                                    _ResidualBlock(128, 128))
        self.head = nn.Linear(128, classes)

    def forward(self, x: torch.Tensor) -> torch.Tensor:  # noqa: D102 (nn.Module's)
        return self.head(self.blocks(_channels_first(x)).mean(dim=2))


class SelfAttention(nn.Module):
    """A two-layer Transformer encoder over overlapping patches of the window, mean-pooled."""

    def __init__(self, window: int, channels: int, classes: int, width: int = 64,
                 heads: int = 4, layers: int = 2, patch: int = 8, stride: int = 4) -> None:
        super().__init__()
        if window < patch:
            raise ValueError('the window is too short for this model')
        self.embed = nn.Conv1d(channels, width, patch, stride=stride)
        self.position = nn.Parameter(torch.zeros(1, (window - patch) // stride + 1, width))
        nn.init.normal_(self.position, std=0.02)
        layer = nn.TransformerEncoderLayer(width, heads, dim_feedforward=2 * width,
                                           dropout=0.1, batch_first=True, norm_first=True)
        self.encoder = nn.TransformerEncoder(layer, layers, enable_nested_tensor=False)
        self.norm = nn.LayerNorm(width)
        self.head = nn.Linear(width, classes)

    def forward(self, x: torch.Tensor) -> torch.Tensor:  # noqa: D102 (nn.Module's)
        tokens = self.embed(_channels_first(x)).transpose(1, 2)
        encoded = self.encoder(tokens + self.position[:, :tokens.shape[1]])
        return self.head(self.norm(encoded).mean(dim=1))


class CnnAttention(nn.Module):
    """Two convolution blocks, one self-attention layer and attention pooling."""

    def __init__(self, window: int, channels: int, classes: int, width: int = 64,
                 heads: int = 4) -> None:
        super().__init__()
        if window // 4 < 1:
            raise ValueError('the window is too short for this model')
        blocks = []
        for index in range(2):
            blocks += [nn.Conv1d(channels if index == 0 else width, width, 5, padding=2),
                       nn.BatchNorm1d(width), nn.ReLU(), nn.MaxPool1d(2)]
        self.convolutions = nn.Sequential(*blocks)
        self.attention = nn.MultiheadAttention(width, heads, dropout=0.1, batch_first=True)
        self.norm = nn.LayerNorm(width)
        self.score = nn.Linear(width, 1)
        self.head = nn.Linear(width, classes)

    def forward(self, x: torch.Tensor) -> torch.Tensor:  # noqa: D102 (nn.Module's)
        steps = self.convolutions(_channels_first(x)).transpose(1, 2)
        attended, _ = self.attention(steps, steps, steps, need_weights=False)
        steps = self.norm(steps + attended)
        weights = torch.softmax(self.score(steps), dim=1)
        return self.head((weights * steps).sum(dim=1))


def inception_time(window: int, channels: int, classes: int) -> nn.Module:
    """One InceptionTime network."""
    return InceptionTime(window, channels, classes)


def inception_time_ensemble(window: int, channels: int, classes: int) -> nn.Module:
    """Five InceptionTime networks, each from its own initial weights, averaged."""
    return Ensemble([InceptionTime(window, channels, classes)
                     for _ in range(ENSEMBLE_MEMBERS)])


def resnet(window: int, channels: int, classes: int) -> nn.Module:
    """Wang et al.'s fully convolutional ResNet."""
    return ResNet(window, channels, classes)


def self_attention(window: int, channels: int, classes: int) -> nn.Module:
    """A small Transformer encoder."""
    return SelfAttention(window, channels, classes)


def cnn_attention(window: int, channels: int, classes: int) -> nn.Module:
    """Convolutions, self-attention and attention pooling."""
    return CnnAttention(window, channels, classes)
