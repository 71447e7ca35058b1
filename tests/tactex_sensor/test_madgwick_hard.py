# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Madgwick filter, streaming and batch, under any input.

Recovery: bad input (anything, including in-range garbage that turns the attitude
anywhere) followed by a resting sensor: the tilt is back within 1 degree at most
RECOVERY_S after the bad input stops.
"""

import math

from hypothesis import assume, given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from support.hard_values import anything, steps_s, vectors
from transforms3d.euler import euler2quat

from tactex_sensor.madgwick import (
    filter_batch,
    MadgwickConfig,
    MadgwickFilter,
    USED_ACCEL,
    USED_GYRO,
)
from tactex_sensor.orientation import rotate, tilt_between

pytestmark = pytest.mark.hard_case

RATE_HZ = 120.0
RECOVERY_S = 6.0
CONFIG = MadgwickConfig()
# In-range garbage: rates the gyro can report, steps the filter integrates over.
plausible_gyro = vectors(st.floats(-CONFIG.max_rate_rad_s, CONFIG.max_rate_rad_s))
samples = st.tuples(st.one_of(vectors(anything()), plausible_gyro), vectors(anything()),
                    st.one_of(steps_s(1 / RATE_HZ), st.floats(0.0, CONFIG.max_dt_s)),
                    st.one_of(st.none(), vectors(anything())))


def resting_readings(roll: float, pitch: float):
    q_true = euler2quat(roll, pitch, 0.3)
    accel = rotate(np.array([q_true[0], *-q_true[1:]]), (0.0, 0.0, 9.81))
    return q_true, tuple(accel)


@settings(max_examples=60)
@given(st.lists(samples, max_size=25), st.booleans())
def test_any_input_keeps_a_unit_quaternion_and_a_bounded_bias(sequence, use_mag):
    config = MadgwickConfig(use_mag=use_mag)
    filt = MadgwickFilter(config)
    for gyro, accel, dt, mag in sequence:
        filt.update(gyro, accel, dt, mag)
        q = filt.quaternion
        assert np.all(np.isfinite(q)) and abs(np.linalg.norm(q) - 1.0) < 1e-12
        assert np.linalg.norm(filt.gyro_bias) <= config.max_bias * (1 + 1e-12)


@settings(max_examples=40)
@given(st.lists(samples, max_size=25), st.booleans(), st.booleans())
def test_batch_agrees_with_streaming_on_any_input(sequence, use_mag, from_first):
    config = MadgwickConfig(use_mag=use_mag, start_from_first_sample=from_first)
    filt = MadgwickFilter(config)
    streamed, flags = [], []
    for gyro, accel, dt, mag in sequence:
        filt.update(gyro, accel, dt, mag)
        streamed.append(filt.quaternion)
        flags.append(filt.last_flags)
    n = len(sequence)
    gyro = np.array([s[0] for s in sequence], dtype=float).reshape(n, 3)
    accel = np.array([s[1] for s in sequence], dtype=float).reshape(n, 3)
    dt = np.array([s[2] for s in sequence], dtype=float)
    mag = np.array([(math.nan,) * 3 if s[3] is None else s[3] for s in sequence],
                   dtype=float).reshape(n, 3)
    batch, batch_flags = filter_batch(gyro, accel, dt, mag, config, return_flags=True)
    assert batch.shape == (n, 4)
    np.testing.assert_allclose(batch, np.array(streamed).reshape(n, 4), atol=1e-12, rtol=0)
    assert batch_flags.tolist() == flags


@settings(max_examples=60)
@given(vectors(anything()), vectors(anything()), steps_s(1 / RATE_HZ), st.booleans())
def test_a_sample_with_neither_usable_gyro_nor_accel_leaves_the_state_alone(
        gyro, accel, dt, use_mag):
    filt = MadgwickFilter(MadgwickConfig(use_mag=use_mag))
    _, resting = resting_readings(0.4, -0.2)
    for _ in range(30):
        filt.update((0.01, -0.02, 0.0), resting, 1 / RATE_HZ)
    before_q, before_bias = filt.quaternion, filt.gyro_bias
    filt.update(gyro, accel, dt)
    assume(not filt.last_flags & (USED_GYRO | USED_ACCEL))
    np.testing.assert_allclose(filt.quaternion, before_q, atol=1e-15, rtol=0)
    np.testing.assert_array_equal(filt.gyro_bias, before_bias)


@settings(max_examples=60)
@given(vectors(anything()), steps_s(1 / RATE_HZ))
def test_every_rejected_sample_is_counted(gyro, dt):
    filt = MadgwickFilter()
    _, resting = resting_readings(0.1, 0.2)
    filt.update((0.0, 0.0, 0.0), resting, 0.0)
    filt.update(gyro, resting, dt)
    dt_ok = 0.0 < dt <= CONFIG.max_dt_s
    gyro_ok = all(abs(g) <= CONFIG.max_rate_rad_s for g in gyro)
    assert filt.rejected == {'gyro': int(dt_ok and not gyro_ok), 'accel': 0,
                             'dt': int(not dt_ok)}


@settings(max_examples=25)
@given(st.floats(-2.5, 2.5), st.floats(-1.2, 1.2), st.lists(samples, min_size=1, max_size=30),
       st.booleans())
def test_tilt_recovers_within_the_stated_time_after_bad_input_stops(roll, pitch, bad,
                                                                    use_mag):
    q_true, resting = resting_readings(roll, pitch)
    filt = MadgwickFilter(MadgwickConfig(use_mag=use_mag))
    for _ in range(int(RATE_HZ)):
        filt.update((0.0, 0.0, 0.0), resting, 1 / RATE_HZ)
    for gyro, accel, dt, mag in bad:
        filt.update(gyro, accel, dt, mag)
    for _ in range(int(RECOVERY_S * RATE_HZ)):
        filt.update((0.0, 0.0, 0.0), resting, 1 / RATE_HZ)
    assert math.degrees(tilt_between(filt.quaternion, q_true)) < 1.0


@given(st.integers(0, 1), st.booleans())
def test_empty_and_single_sample_batches_work(n, use_mag):
    config = MadgwickConfig(use_mag=use_mag)
    out = filter_batch(np.zeros((n, 3)), np.tile([0.0, 0.0, 9.81], (n, 1)), np.full(n, 0.01),
                       np.zeros((n, 3)) if use_mag else None, config)
    assert out.shape == (n, 4) and np.all(np.isfinite(out))
