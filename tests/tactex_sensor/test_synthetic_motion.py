# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Synthetic motions and readings with exact truth, and the attitude errors."""

import math

import numpy as np
import pytest

from tactex_common.chips import gyro_range
from tactex_sensor.madgwick import filter_batch, MadgwickConfig
from tactex_sensor.synthetic_motion import errors, G, motion, MOTIONS, readings


def test_a_resting_sensor_reads_gravity_and_no_rotation():
    t = np.arange(0.0, 1.0, 0.01)
    q_true, linear = motion('static tilt 30 deg', t, np.random.default_rng(0))
    gyro, accel, mag = readings(q_true, linear, 100.0, np.random.default_rng(0), np.zeros(3))
    assert np.abs(gyro).max() < 0.02  # noise only (sd 0.003 rad/s)
    assert np.linalg.norm(accel, axis=1).mean() == pytest.approx(G, rel=0.01)
    tilt = math.degrees(math.acos(accel[:, 2].mean() / G))
    assert tilt == pytest.approx(30.0, abs=0.5)


def test_errors_are_zero_for_the_truth_and_ignore_a_constant_yaw():
    t = np.arange(0.0, 5.0, 0.01)
    q_true, _ = motion('slow sweep 0.2 Hz', t, np.random.default_rng(0))
    yaw = np.array([math.cos(0.2), 0.0, 0.0, math.sin(0.2)])
    turned = np.array([[yaw[0] * w - yaw[3] * z, yaw[0] * x - yaw[3] * y,
                        yaw[0] * y + yaw[3] * x, yaw[0] * z + yaw[3] * w]
                       for w, x, y, z in q_true])  # yaw * q
    for estimate in (q_true, turned):
        tilt, full = errors(estimate, q_true)
        assert tilt.max() < 1e-5 and full.max() < 1e-3


@pytest.mark.parametrize('name', MOTIONS)
def test_madgwick_follows_every_motion_within_a_few_degrees(name):
    t = np.arange(0.0, 15.0, 1 / 120)
    rng = np.random.default_rng(1)
    q_true, linear = motion(name, t, rng)
    gyro, accel, mag = readings(q_true, linear, 120.0, rng, np.zeros(3))
    # The widest gyro range: a flip in a second turns faster than +-245 dps.
    config = MadgwickConfig(use_mag=True, max_rate_rad_s=gyro_range(2000).full_scale_si)
    tilt, _ = errors(filter_batch(gyro, accel, 1 / 120, mag, config), q_true)
    assert np.sqrt(np.mean(tilt[t > 5.0] ** 2)) < 5.0


def test_an_unknown_motion_is_refused():
    with pytest.raises(ValueError, match='nope'):
        motion('nope', np.zeros(3), np.random.default_rng(0))
