# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The physics of texture vibration: the edge's footprint as a filter, the body's response.

A rigid footprint of length l (along the sliding direction) and width w (across it)
feels the mean height under it. For a plane wave of height with wavevector components
k_along, k_across that mean is the wave times sinc(k_along l / 2) sinc(k_across w / 2):
features much finer than the footprint cancel. Sliding at v, the wave reaches the body
at v |k_along| / 2 pi Hz, where the body's resonance (a base-excited damped oscillator)
shapes it. Random roughness is averaged the same way along the path (a moving mean of
length l) and across it (a Gaussian-correlated field of correlation length c averaged
over w keeps sqrt(sqrt(pi) c / w) of its rms when w > c).
"""

from __future__ import annotations

import math

import numpy as np

# Spacing of the precomputed roughness profiles along the path (m).
ROUGHNESS_STEP_M = 2e-5


def transmissibility(frequency_hz, resonance_hz: float, damping_ratio: float):
    """Displacement (and acceleration) transmissibility of a base-excited damped oscillator.

    Plain arithmetic: a float for a float frequency (the per-sample path), an array for
    an array.
    """
    r = frequency_hz / resonance_hz
    damping = (2.0 * damping_ratio * r) ** 2
    return ((1.0 + damping) / ((1.0 - r * r) ** 2 + damping)) ** 0.5


def footprint_gain(k_along: float, k_across: float, length_m: float, width_m: float) -> float:
    """The share of a height wave a rigid footprint of `length_m` x `width_m` feels (signed).

    `k_along`, `k_across`: the wavevector's components along and across the path (rad/m).
    """
    return _sinc(0.5 * k_along * length_m) * _sinc(0.5 * k_across * width_m)


def _sinc(x: float) -> float:
    """sin(x) / x, 1 at 0 (math on floats: this runs for every wave of every sample)."""
    return math.sin(x) / x if x != 0.0 else 1.0


def footprint_roughness(heights: np.ndarray, step_m: float, length_m: float, width_m: float,
                        correlation_m: float) -> tuple[np.ndarray, np.ndarray]:
    """(slope, curvature) along a random profile, as a footprint of length x width feels it.

    Args:
        heights: the profile along the path (m), `step_m` apart, periodic.
        step_m: its spacing.
        length_m: the footprint's length along the path.
        width_m: its width across the path.
        correlation_m: the roughness's correlation length.
    """
    span = max(1, int(round(length_m / step_m)))
    padded = np.concatenate([heights[-span:], heights, heights[:span]])
    window = np.ones(span) / span
    mean = np.convolve(padded, window, mode='same')[span:-span]
    across = math.sqrt(min(1.0, math.sqrt(math.pi) * correlation_m / max(width_m, 1e-12)))
    mean = mean * across
    slope = np.gradient(mean, step_m)
    return slope, np.gradient(slope, step_m)
