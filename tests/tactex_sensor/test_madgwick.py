# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Madgwick filter: convergence, MARG heading, and degenerate input that must not poison it."""

import math

import numpy as np
import pytest
from transforms3d.euler import euler2quat
from transforms3d.quaternions import axangle2quat

from tactex_common.chips import gyro_range
from tactex_sensor.madgwick import (
    filter_batch,
    MadgwickConfig,
    MadgwickFilter,
    REJECTED_GYRO,
    USED_ACCEL,
    USED_GYRO,
    USED_MAG,
)
from tactex_sensor.orientation import angle_between, rotate, tilt_between

G = 9.81
GYRO_FULL_SCALE_RAD_S = gyro_range().full_scale_si
EARTH_FIELD_ENU = np.array([0.0, 2.0e-5, -4.3e-5])  # north and downwards, tesla
RATE_HZ = 120.0


def static_readings(q_true, mag=True):
    """Accel and mag a motionless sensor at attitude q_true (ENU) reads."""
    conj = np.array([q_true[0], -q_true[1], -q_true[2], -q_true[3]])
    accel = rotate(conj, (0.0, 0.0, G))
    field = rotate(conj, EARTH_FIELD_ENU) if mag else None
    return accel, field


def run_static(filt, q_true, seconds, *, gyro_bias=(0.0, 0.0, 0.0), mag=False, start=None):
    accel, field = static_readings(q_true, mag)
    for i in range(int(seconds * RATE_HZ)):
        filt.update(gyro_bias, accel if start is None or i else start, 1 / RATE_HZ, field)


def test_first_sample_sets_the_attitude():
    q_true = euler2quat(0.4, -0.3, 0.0)
    filt = MadgwickFilter()
    run_static(filt, q_true, 1 / RATE_HZ)
    assert tilt_between(filt.quaternion, q_true) < 1e-9


def test_converges_within_one_second_from_a_wrong_start():
    q_true = euler2quat(2.5, 0.5, 0.0)  # ~150 degrees of tilt from the first reading
    filt = MadgwickFilter()
    run_static(filt, q_true, 1.0, start=(0.0, 0.0, G))
    assert math.degrees(tilt_between(filt.quaternion, q_true)) < 1.0


def test_marg_heading_is_east_north_up():
    q_true = euler2quat(0.2, 0.1, 1.0)  # yaw 1 rad in ENU
    filt = MadgwickFilter(MadgwickConfig(use_mag=True))
    run_static(filt, q_true, 3.0, mag=True)
    assert math.degrees(angle_between(filt.quaternion, q_true)) < 0.5


def test_gyro_bias_is_learnt_and_leaves_no_steady_tilt():
    q_true = euler2quat(0.3, 0.0, 0.0)
    accel, _ = static_readings(q_true, mag=False)
    bias = np.array([0.02, -0.015, 0.0])
    rng = np.random.default_rng(11)
    filt = MadgwickFilter()
    for _ in range(int(90 * RATE_HZ)):
        filt.update((bias + rng.normal(0, 0.003, 3)).tolist(),
                    (accel + rng.normal(0, 0.02, 3)).tolist(), 1 / RATE_HZ)
    # Without a magnetometer the bias along world up (heading) is unobservable: compare
    # only the part perpendicular to it.
    up_in_body = accel / np.linalg.norm(accel)
    error = filt.gyro_bias - bias
    error -= np.dot(error, up_in_body) * up_in_body
    assert np.linalg.norm(error) < 2e-3
    assert math.degrees(tilt_between(filt.quaternion, q_true)) < 0.3


@pytest.mark.parametrize('bad', [
    dict(gyro=(math.nan, 0.0, 0.0)), dict(gyro=(0.0, math.inf, 0.0)),
    dict(accel=(math.nan, 0.0, G)), dict(accel=(0.0, 0.0, 0.0)), dict(accel=(-math.inf, 0, 0)),
    dict(dt=0.0), dict(dt=-0.01), dict(dt=math.nan), dict(dt=1.0),
    dict(mag=(math.nan, 1e-5, 0.0)), dict(mag=(0.0, 0.0, 4e-5))])
def test_a_degenerate_sample_never_poisons_the_state(bad):
    q_true = euler2quat(0.2, -0.1, 0.0)
    filt = MadgwickFilter(MadgwickConfig(use_mag=True))
    run_static(filt, q_true, 2.0, mag=True)
    before = filt.quaternion
    accel, field = static_readings(q_true)
    if 'mag' in bad:  # mag parallel to gravity in the sensor frame, or NaN
        bad = dict(mag=accel / G * 4e-5) if bad['mag'][2] else bad
    filt.update(bad.get('gyro', (0.0, 0.0, 0.0)), bad.get('accel', accel),
                bad.get('dt', 1 / RATE_HZ), bad.get('mag', field))
    after = filt.quaternion
    assert np.all(np.isfinite(after)) and abs(np.linalg.norm(after) - 1) < 1e-12
    assert math.degrees(angle_between(before, after)) < 1.0  # no jump of several degrees
    run_static(filt, q_true, 2.0, mag=True)
    assert math.degrees(angle_between(filt.quaternion, q_true)) < 1.0


def test_flags_say_what_was_used():
    filt = MadgwickFilter(MadgwickConfig(use_mag=True))
    accel, field = static_readings(euler2quat(0.1, 0.2, 0.3))
    filt.update((0, 0, 0), accel, 0.01, field)
    filt.update((0, 0, 0), accel, 0.01, field)
    assert filt.last_flags == USED_GYRO | USED_ACCEL | USED_MAG
    filt.update((math.nan, 0, 0), accel, 0.01, (math.nan,) * 3)
    assert filt.last_flags == USED_ACCEL | REJECTED_GYRO


@pytest.mark.parametrize('rate', [1e20, 3.4e38, -3.4e38, 2.0 * GYRO_FULL_SCALE_RAD_S])
def test_a_gyro_rate_beyond_the_sensor_range_is_rejected_and_counted(rate):
    q_true = euler2quat(0.3, -0.2, 0.0)
    filt = MadgwickFilter()
    run_static(filt, q_true, 1.0)
    before = filt.quaternion
    accel, _ = static_readings(q_true, mag=False)
    filt.update((rate, 0.0, 0.0), accel, 1 / RATE_HZ)
    assert filt.last_flags & REJECTED_GYRO and filt.rejected['gyro'] == 1
    assert abs(np.linalg.norm(filt.quaternion) - 1.0) < 1e-12
    assert math.degrees(angle_between(before, filt.quaternion)) < 0.01


def test_a_rate_within_the_sensor_range_is_integrated():
    filt = MadgwickFilter(MadgwickConfig(gain=0.0, bias_gain=0.0))
    filt.update((0.0, 0.0, 0.0), (0.0, 0.0, G), 0.0)
    filt.update((0.0, 0.0, 0.9 * GYRO_FULL_SCALE_RAD_S), (0.0, 0.0, G), 1e-3)
    assert filt.rejected['gyro'] == 0
    expected = axangle2quat((0.0, 0.0, 1.0), 0.9 * GYRO_FULL_SCALE_RAD_S * 1e-3)
    assert angle_between(filt.quaternion, expected) < 1e-12


@pytest.mark.parametrize('angle', [3.0, 1.0, 0.2, 1e-9])
def test_the_prediction_is_an_exact_rotation_at_any_step_angle(angle):
    # One step of `angle` rad about a tilted axis, no correction: the series of the
    # old kernel turned a 3 rad step into 2.97 rad.
    config = MadgwickConfig(gain=0.0, initial_gain=0.0, bias_gain=0.0, max_dt_s=2.0)
    axis = np.array([1.0, -2.0, 0.5]) / np.linalg.norm([1.0, -2.0, 0.5])
    gyro = np.array([[0.0, 0.0, 0.0], axis * angle])
    accel = np.array([[0.0, 0.0, G], [math.nan, 0.0, 0.0]])  # no accel in the second
    q = filter_batch(gyro, accel, np.array([0.0, 1.0]), config=config)
    assert angle_between(q[1], axangle2quat(axis, angle)) < 1e-12
    filt = MadgwickFilter(config)
    for i in range(2):
        filt.update(gyro[i].tolist(), accel[i].tolist(), float(i))
    np.testing.assert_allclose(filt.quaternion, q[1], atol=1e-15)



def test_quaternion_stays_unit_norm_over_ten_million_updates():
    rng = np.random.default_rng(5)
    n = 10_000_000
    gyro = rng.normal(0.0, 2.0, (n, 3))
    accel = rng.normal(0.0, 5.0, (n, 3)) + [0, 0, G]
    q = filter_batch(gyro, accel, 1 / 350)
    norms = np.linalg.norm(q[:: 1000], axis=1)
    assert np.all(np.abs(norms - 1.0) < 1e-12)
    assert abs(np.linalg.norm(q[-1]) - 1.0) < 1e-12


def test_batch_equals_streaming_including_faults():
    rng = np.random.default_rng(9)
    n = 3000
    gyro = rng.normal(0.0, 0.5, (n, 3))
    accel = rng.normal(0.0, 1.0, (n, 3)) + [0.0, 3.0, G]
    mag = rng.normal(0.0, 1e-6, (n, 3)) + [1e-5, 2e-5, -4e-5]
    dt = np.full(n, 1 / 120)
    gyro[100] = np.nan
    accel[200] = 0.0
    mag[300] = np.inf
    dt[400] = 1.5
    dt[500] = -1.0
    for config in (MadgwickConfig(), MadgwickConfig(use_mag=True)):
        filt = MadgwickFilter(config)
        streamed = []
        for i in range(n):
            filt.update(gyro[i].tolist(), accel[i].tolist(), float(dt[i]), mag[i].tolist())
            streamed.append(filt.quaternion)
        np.testing.assert_allclose(filter_batch(gyro, accel, dt, mag, config), streamed,
                                   atol=1e-12, rtol=0)


def test_invalid_configuration_is_rejected():
    with pytest.raises(ValueError, match='gain'):
        MadgwickConfig(gain=-1.0)
    with pytest.raises(ValueError, match='max_dt_s'):
        MadgwickConfig(max_dt_s=0.0)


def test_start_from_identity_converges_within_one_second():
    q_true = euler2quat(math.radians(30), 0.0, 0.0)
    config = MadgwickConfig(start_from_first_sample=False)
    filt = MadgwickFilter(config)
    run_static(filt, q_true, 1.0)
    assert math.degrees(tilt_between(filt.quaternion, q_true)) < 1.0
    accel, _ = static_readings(q_true, mag=False)
    batch = filter_batch(np.zeros((120, 3)), np.tile(accel, (120, 1)), 1 / RATE_HZ,
                         config=config)
    np.testing.assert_allclose(batch[-1], filt.quaternion, atol=1e-12)


def test_a_lasting_disagreement_with_the_accel_restarts_the_gain_ramp():
    q_true = euler2quat(0.2, 0.1, 0.0)
    filt = MadgwickFilter(MadgwickConfig(max_rate_rad_s=gyro_range(2000).full_scale_si))
    run_static(filt, q_true, 1.0)
    accel, _ = static_readings(q_true, mag=False)
    filt.update((30.0, 0.0, 0.0), accel, 0.087)  # in range, yet turns it 150 degrees
    assert math.degrees(tilt_between(filt.quaternion, q_true)) > 100
    run_static(filt, q_true, 2.5)  # the gain of 0.04 alone would take 30 s
    assert filt.restarts >= 1
    assert math.degrees(tilt_between(filt.quaternion, q_true)) < 1.0
