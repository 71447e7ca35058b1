# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""MiniRocket's kernels, dilations, channel masks and biases, shared with MultiRocket.

From Dempster, Schmidt and Webb, "MiniRocket", KDD 2021: 84 kernels of length 9 with
weights -1 and three +2 (every choice of the three positions), each at several
dilations, applied to a random subset of the channels summed; biases are quantiles
(low-discrepancy: multiples of the golden ratio mod 1) of a kernel's output on one
random training window.
"""

from __future__ import annotations

from itertools import combinations

import numpy as np

KERNELS = np.array(list(combinations(range(9), 3)))  # positions of the +2 weights
GOLDEN = (np.sqrt(5.0) - 1.0) / 2.0


def plan_kernels(length: int, channels: int, dilations: int, rng: np.random.Generator
                 ) -> tuple[np.ndarray, np.ndarray]:
    """(dilations, channel masks (dilations, kernels, channels)) for windows of `length`."""
    largest = max(1.0, (length - 1) / 8.0)
    chosen = np.unique(np.floor(2.0 ** np.linspace(0, np.log2(largest), dilations)).astype(int))
    masks = np.zeros((len(chosen), len(KERNELS), channels), np.float32)
    for d in range(len(chosen)):
        for index in range(len(KERNELS)):
            size = int(2 ** rng.uniform(0, np.log2(min(channels, 9) + 1)))
            masks[d, index, rng.choice(channels, max(1, size), replace=False)] = 1.0
    return chosen, masks


def kernel_outputs(Z: np.ndarray, dilation: int, masks: np.ndarray) -> np.ndarray:
    """Every kernel's output at one dilation, summed over its channels: (kernels, n, L).

    A kernel is 3 x (its three +2 taps) - (all nine taps); with 'same' zero padding. The
    taps are projected on each kernel's channel mask first, so the 84 kernels cost one
    matrix product.
    """
    pad = 4 * dilation
    padded = np.pad(Z, ((0, 0), (pad, pad), (0, 0)))
    length = Z.shape[1]
    taps = np.stack([padded[:, j * dilation:j * dilation + length] for j in range(9)])
    projected = np.moveaxis(taps @ masks.T, -1, 1)  # (9, kernels, n, L)
    kernel = np.arange(len(KERNELS))
    picked = projected[KERNELS[:, 0], kernel] + projected[KERNELS[:, 1], kernel] \
        + projected[KERNELS[:, 2], kernel]
    return 3.0 * picked - np.moveaxis(taps.sum(axis=0) @ masks.T, -1, 0)


def fit_biases(outputs: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    """(kernels, count) biases: quantiles of each kernel's output on one random window."""
    quantiles = (np.arange(1, count + 1) * GOLDEN) % 1.0
    return np.stack([np.quantile(outputs[index, rng.integers(outputs.shape[1])], quantiles)
                     for index in range(len(outputs))])
