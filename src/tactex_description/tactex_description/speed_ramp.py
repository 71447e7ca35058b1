# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The cosine speed ramps a sweep slides with: the planner's, the movements' and the simulator's.

A sweep accelerates from rest to its sliding speed v along a cosine ramp (speed
v (1 - cos(pi t / T)) / 2, peak acceleration a = pi v / (2 T)), holds v over its contact,
and slows down the same way. A ramp lasts T = pi v / (2 a) and covers pi v^2 / (4 a).
The Sweep action plans its slide so (tactex_trajectory), a movement's part of a pathway
adds both ramps to its contact (tactex_classify), and the simulator's scripted sweep
slides so when its scene asks for ramps (tactex_sim), so that all three agree.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
import math

import numpy as np

# The sweep's ramp acceleration as shipped (config/sweep.yaml's ramp_acceleration, m/s^2).
RAMP_ACCELERATION_M_S2 = 0.05


@dataclass(frozen=True)
class TimeLaw:
    """s(t), s'(t), s''(t) of a path of length `length` over `duration_s`."""

    duration_s: float
    length: float
    position: Callable[[np.ndarray], np.ndarray]
    speed: Callable[[np.ndarray], np.ndarray]
    acceleration: Callable[[np.ndarray], np.ndarray]


def ramp_duration_s(speed_m_s: float, acceleration_m_s2: float) -> float:
    """Seconds of a cosine ramp from rest to `speed_m_s` at this peak acceleration."""
    return math.pi * speed_m_s / (2.0 * acceleration_m_s2)


def ramp_length_m(speed_m_s: float, acceleration_m_s2: float) -> float:
    """Path covered by a cosine speed ramp from rest to `speed_m_s` at this peak acceleration."""
    return math.pi * speed_m_s ** 2 / (4.0 * acceleration_m_s2)


def ramped_law(length: float, speed_m_s: float, ramp_s: float) -> TimeLaw:
    """Cosine ramp to `speed_m_s` over `ramp_s`, constant speed, cosine ramp down."""
    ramp_length = speed_m_s * ramp_s / 2.0
    cruise_s = (length - 2.0 * ramp_length) / speed_m_s
    duration = 2.0 * ramp_s + cruise_s
    w = math.pi / ramp_s

    def position(t):
        t = np.clip(np.asarray(t, dtype=float), 0.0, duration)
        up = speed_m_s / 2.0 * (t - np.sin(w * t) / w)
        down_t = duration - t
        down = length - speed_m_s / 2.0 * (down_t - np.sin(w * down_t) / w)
        cruise = ramp_length + speed_m_s * (t - ramp_s)
        travel = np.where(t < ramp_s, up, np.where(t > duration - ramp_s, down, cruise))
        return np.clip(travel, 0.0, length)  # t - sin(wt)/w rounds below 0 near t = 0

    def speed(t):
        t = np.clip(np.asarray(t, dtype=float), 0.0, duration)
        edge = np.minimum(t, duration - t)
        return np.where(edge < ramp_s, speed_m_s / 2.0 * (1.0 - np.cos(w * edge)), speed_m_s)

    def acceleration(t):
        t = np.clip(np.asarray(t, dtype=float), 0.0, duration)
        value = speed_m_s / 2.0 * w * np.sin(w * np.minimum(t, duration - t))
        return np.where(t < ramp_s, value, np.where(t > duration - ramp_s, -value, 0.0))

    return TimeLaw(duration, length, position, speed, acceleration)
