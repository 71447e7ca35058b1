# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""MultiRocket + ridge: MiniRocket kernels on windows and first differences, four poolings.

Written from Tan, Dempster, Bergmeir and Webb, "MultiRocket: multiple pooling operators
and transformations for fast and effective time series classification" (Data Mining
and Knowledge Discovery 36, 2022). The MiniRocket kernels (`rocket_kernels`) run on the
z-scored windows and, with kernels, masks and biases of their own, on their first
differences; each (kernel, dilation, bias) gives four features of the biased output:
- PPV, the proportion of positive values;
- MPV, the mean of the positive values (0 where there are none);
- MIPV, the mean index of the positive values (-1 where there are none);
- LSPV, the longest stretch of consecutive positive values.
MIPV and LSPV are divided by the output's length here, so one model reads windows of any
length on one scale (the standardisation before the ridge would undo a constant factor
anyway). Aeon ships the reference transform but pins numba and pandas below this
workspace's; the transform is short.
"""

from __future__ import annotations

import numpy as np

from tactex_classify.models.feature_ridge import FeatureRidge
from tactex_classify.models.rocket_kernels import (
    fit_biases,
    kernel_outputs,
    KERNELS,
    plan_kernels,
)
from tactex_common.constants import MAX_SEED

POOLINGS = ('ppv', 'mpv', 'mipv', 'lspv')
CHUNK = 256  # windows pooled at once: the biased outputs are kernels x chunk x biases x L


def pooled(outputs: np.ndarray, biases: np.ndarray) -> np.ndarray:
    """(n, kernels x biases x 4) PPV, MPV, MIPV, LSPV of (kernels, n, L) outputs."""
    length = outputs.shape[2]
    biased = outputs[:, :, None, :] - biases[:, None, :, None]  # (kernels, n, biases, L)
    positive = biased > 0
    count = positive.sum(axis=-1)
    some = count > 0
    safe = np.maximum(count, 1)
    ppv = count / length
    mpv = np.where(some, np.sum(biased * positive, axis=-1) / safe, 0.0)
    mipv = np.where(some, np.sum(np.arange(length) * positive, axis=-1) / safe / length, -1.0)
    running = np.cumsum(positive, axis=-1)
    restart = np.maximum.accumulate(np.where(positive, 0, running), axis=-1)
    lspv = (running - restart).max(axis=-1) / length
    features = np.stack([ppv, mpv, mipv, lspv], axis=-1)  # (kernels, n, biases, 4)
    return features.transpose(1, 0, 2, 3).reshape(outputs.shape[1], -1)


class MultiRocketRidge(FeatureRidge):
    """MultiRocket features + RidgeClassifierCV."""

    CHECKPOINT_KIND = 'multirocket'
    TRANSFORM_ARRAYS = ('dilations_', 'masks_', 'biases_', 'diff_dilations_', 'diff_masks_',
                        'diff_biases_')
    SETTINGS = {'dilations': (7, 64), 'biases_per_kernel': (6, 64), 'seed': (0, MAX_SEED)}

    def _fit(self, Z: np.ndarray, rng: np.random.Generator) -> None:
        """Plan both kernel banks and fit their biases on the training windows."""
        if Z.shape[1] < 2:
            raise ValueError('MultiRocket needs windows of at least 2 samples (it also reads '
                             'their first differences)')
        for prefix, series in (('', Z), ('diff_', np.diff(Z, axis=1))):
            dilations, masks = plan_kernels(series.shape[1], series.shape[2], self.dilations,
                                            rng)
            biases = np.stack([fit_biases(kernel_outputs(series, int(dilation), masks[d]),
                                          self.biases_per_kernel, rng)
                               for d, dilation in enumerate(dilations)])
            setattr(self, f'{prefix}dilations_', dilations)
            setattr(self, f'{prefix}masks_', masks)
            setattr(self, f'{prefix}biases_', biases)

    def _features(self, Z: np.ndarray) -> np.ndarray:
        chunks = []
        for start in range(0, len(Z), CHUNK):
            part = Z[start:start + CHUNK]
            columns = []
            for prefix, series in (('', part), ('diff_', np.diff(part, axis=1))):
                banks = zip(getattr(self, f'{prefix}dilations_'),
                            getattr(self, f'{prefix}masks_'),
                            getattr(self, f'{prefix}biases_'), strict=True)
                columns += [pooled(kernel_outputs(series, int(dilation), masks), biases)
                            for dilation, masks, biases in banks]
            chunks.append(np.concatenate(columns, axis=1))
        return np.concatenate(chunks, axis=0)

    def _feature_count(self) -> int:
        banks = len(self.dilations_) + len(self.diff_dilations_)
        return banks * len(KERNELS) * self.biases_per_kernel * len(POOLINGS)

    def _transform_fits(self) -> bool:
        c, b = self.n_channels_, self.biases_per_kernel
        for prefix in ('', 'diff_'):
            dilations = getattr(self, f'{prefix}dilations_')
            d = len(dilations)
            if not (dilations.shape == (d,) and 1 <= d <= self.dilations
                    and bool(np.all(dilations >= 1))
                    and getattr(self, f'{prefix}masks_').shape == (d, len(KERNELS), c)
                    and getattr(self, f'{prefix}biases_').shape == (d, len(KERNELS), b)):
                return False
            setattr(self, f'{prefix}dilations_', dilations.astype(int))
        return self.window_ >= 2
