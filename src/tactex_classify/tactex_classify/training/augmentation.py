# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Augmentations of tactile windows for the `modern` training profile, on torch batches.

Each acts on a batch of scaled windows (batch, time, channels), on each window with
probability `APPLY_P`, with its own draw, and keeps the shape:
- `shift`: moves the window up to 1/8 of its length in time, the edge samples repeated
  (window slicing; Le Guennec, Malinowski, Tavenard 2016);
- `scale`: multiplies each channel by N(1, 0.1) (magnitude scaling; Um et al. 2017,
  "Data augmentation of wearable sensor data", ICMI);
- `jitter`: adds N(0, 0.03) noise (Um et al. 2017);
- `warp`: resamples along a smooth, monotone random time axis, speeds N(1, 0.2) at four
  knots (time warping; Um et al. 2017; Iwana and Uchida 2021, PLOS ONE);
- `channel_dropout`: zeroes each channel with probability 0.1 (whole channels, as
  spatial dropout drops feature maps; Tompson et al. 2015), so no model leans on one chip.
Mixup (Zhang et al. 2018, ICLR) mixes windows and their labels, so it lives in the
training loop (`mixup`). Every draw comes from the given torch generator: a seed
reproduces a training.
"""

from __future__ import annotations

import torch

from tactex_classify.models.registry import AUGMENTATIONS

APPLY_P = 0.5
SHIFT_FRACTION = 1 / 8
SCALE_SIGMA = 0.1
JITTER_SIGMA = 0.03
WARP_SIGMA = 0.2
WARP_KNOTS = 4
CHANNEL_DROP_P = 0.1


def _chosen(batch: torch.Tensor, generator: torch.Generator) -> torch.Tensor:
    """(batch, 1, 1) mask: 1 where a window is augmented this time."""
    return (torch.rand(len(batch), 1, 1, generator=generator, device=batch.device)
            < APPLY_P).to(batch.dtype)


def _resample(batch: torch.Tensor, positions: torch.Tensor) -> torch.Tensor:
    """Windows read at fractional time `positions` (batch, time), linearly interpolated."""
    length = batch.shape[1]
    positions = positions.clamp(0, length - 1)
    lower = positions.floor().long().clamp(max=length - 2) if length > 1 else \
        torch.zeros_like(positions, dtype=torch.long)
    upper = (lower + 1).clamp(max=length - 1)
    weight = (positions - lower).unsqueeze(-1).to(batch.dtype)
    index = lower.unsqueeze(-1).expand(-1, -1, batch.shape[2])
    upper_index = upper.unsqueeze(-1).expand(-1, -1, batch.shape[2])
    return torch.gather(batch, 1, index) * (1 - weight) + \
        torch.gather(batch, 1, upper_index) * weight


def shift(batch: torch.Tensor, generator: torch.Generator) -> torch.Tensor:
    """Each window moved by a whole number of samples, edges repeated."""
    length = batch.shape[1]
    most = int(length * SHIFT_FRACTION)
    offsets = torch.randint(-most, most + 1, (len(batch), 1), generator=generator,
                            device=batch.device)
    time = torch.arange(length, device=batch.device).unsqueeze(0)
    return _resample(batch, (time + offsets).to(batch.dtype))


def scale(batch: torch.Tensor, generator: torch.Generator) -> torch.Tensor:
    """Each channel of each window times N(1, SCALE_SIGMA)."""
    factors = 1 + SCALE_SIGMA * torch.randn(len(batch), 1, batch.shape[2], generator=generator,
                                            device=batch.device, dtype=batch.dtype)
    return batch * factors


def jitter(batch: torch.Tensor, generator: torch.Generator) -> torch.Tensor:
    """Gaussian noise of JITTER_SIGMA on every sample."""
    return batch + JITTER_SIGMA * torch.randn(batch.shape, generator=generator,
                                              device=batch.device, dtype=batch.dtype)


def warp(batch: torch.Tensor, generator: torch.Generator) -> torch.Tensor:
    """Resampled along a random, smooth, monotone time axis spanning the whole window."""
    length = batch.shape[1]
    speeds = (1 + WARP_SIGMA * torch.randn(len(batch), 1, WARP_KNOTS, generator=generator,
                                           device=batch.device)).clamp(min=0.2)
    smooth = torch.nn.functional.interpolate(speeds, size=length, mode='linear',
                                             align_corners=True).squeeze(1)
    axis = torch.cumsum(smooth, dim=1) - smooth[:, :1]
    axis = axis / axis[:, -1:].clamp(min=1e-9) * (length - 1)
    return _resample(batch, axis.to(batch.dtype))


def channel_dropout(batch: torch.Tensor, generator: torch.Generator) -> torch.Tensor:
    """Whole channels of a window set to zero with probability CHANNEL_DROP_P."""
    kept = torch.rand(len(batch), 1, batch.shape[2], generator=generator,
                      device=batch.device) >= CHANNEL_DROP_P
    return batch * kept.to(batch.dtype)


TRANSFORMS = {name: globals()[name] for name in AUGMENTATIONS}


def augment(batch: torch.Tensor, names: tuple[str, ...],
            generator: torch.Generator) -> torch.Tensor:
    """`batch` with each named augmentation applied to about APPLY_P of its windows."""
    for name in names:
        mask = _chosen(batch, generator)
        batch = mask * TRANSFORMS[name](batch, generator) + (1 - mask) * batch
    return batch


def mixup(batch: torch.Tensor, weight: float, generator: torch.Generator
          ) -> tuple[torch.Tensor, torch.Tensor]:
    """Windows mixed with a permutation of the batch: (mixed, partner order).

    `weight` is drawn from Beta(alpha, alpha) by the caller; the loss is weight x
    loss(labels) + (1 - weight) x loss(labels[partner order]).
    """
    order = torch.randperm(len(batch), generator=generator, device=generator.device)
    return weight * batch + (1 - weight) * batch[order], order
