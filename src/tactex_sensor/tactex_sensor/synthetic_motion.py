# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Synthetic motions with exact ground truth, the readings a sensor would give, and errors.

Used to score attitude filters: a named motion gives true attitudes (ENU) and linear
acceleration; `readings` turns them into gyro (the mean body rate between consecutive
true attitudes), accel (gravity + linear acceleration in the body frame) and Earth
field with white noise and a gyro bias; `errors` scores estimated attitudes.
"""

from __future__ import annotations

import math

import numpy as np
from transforms3d.euler import euler2quat
from transforms3d.quaternions import qconjugate, qmult

from tactex_sensor.orientation import rotate

G = 9.80665
FIELD_ENU = np.array([0.0, 2.0e-5, -4.3e-5])
MOTIONS = ('static tilt 30 deg', 'slow sweep 0.2 Hz', 'tactile', 'shaking 2 m/s^2',
           'flip 180 deg in 1 s')


def motion(name: str, t: np.ndarray, rng) -> tuple[np.ndarray, np.ndarray]:
    """Return true attitudes (n, 4) ENU and world linear acceleration (n, 3)."""
    zeros = np.zeros_like(t)
    linear = np.zeros((t.size, 3))
    if name == 'static tilt 30 deg':
        roll, pitch, yaw = zeros + math.radians(30), zeros, zeros + 0.5
    elif name == 'slow sweep 0.2 Hz':
        roll = math.radians(40) * np.sin(2 * math.pi * 0.2 * t)
        pitch = math.radians(20) * np.sin(2 * math.pi * 0.13 * t)
        yaw = 0.3 * np.sin(2 * math.pi * 0.05 * t)
    elif name == 'tactile':
        roll = math.radians(3) * np.sin(2 * math.pi * 1.3 * t) + math.radians(10)
        pitch = math.radians(2) * np.sin(2 * math.pi * 2.7 * t)
        yaw = zeros
        for frequency in (23.0, 61.0, 137.0, 190.0):
            phase = rng.uniform(0, 2 * math.pi, 3)
            linear += 0.6 * np.sin(2 * math.pi * frequency * t[:, None] + phase)
    elif name == 'shaking 2 m/s^2':
        roll, pitch, yaw = zeros + math.radians(15), zeros - math.radians(10), zeros
        linear[:, 0] = 2.0 * np.sin(2 * math.pi * 1.5 * t)
        linear[:, 1] = 2.0 * np.sin(2 * math.pi * 2.1 * t + 1.0)
    elif name == 'flip 180 deg in 1 s':
        ramp = np.clip(t - 10.0, 0.0, 1.0)
        roll = math.pi * (ramp - np.sin(2 * math.pi * ramp) / (2 * math.pi))
        pitch, yaw = zeros + 0.2, zeros
    else:
        raise ValueError(name)
    q = np.array([euler2quat(r, p, y, 'sxyz') for r, p, y in zip(roll, pitch, yaw,
                                                                  strict=True)])
    return q, linear


def readings(q_true, linear, rate_hz, rng, bias):
    """Gyro, accel, mag a real sensor following q_true reads (with noise and `bias`)."""
    # The gyro sample i is the mean body rate from sample i-1 to i: the rotation
    # between the two true attitudes divided by dt, exactly what the filters integrate.
    dt = 1.0 / rate_hz
    gyro = np.zeros((len(q_true), 3))
    for i in range(1, len(q_true)):
        step = qmult(qconjugate(q_true[i - 1]), q_true[i])
        step *= 1.0 if step[0] >= 0 else -1.0
        vector_norm = np.linalg.norm(step[1:])
        angle = 2.0 * math.atan2(vector_norm, step[0])
        if vector_norm > 0:
            gyro[i] = step[1:] / vector_norm * angle / dt
    accel = np.array([rotate(qconjugate(q), lin + (0.0, 0.0, G))
                      for q, lin in zip(q_true, linear, strict=True)])
    mag = np.array([rotate(qconjugate(q), FIELD_ENU) for q in q_true])
    gyro += bias + rng.normal(0, 0.003, gyro.shape)
    accel += rng.normal(0, 0.02, accel.shape)
    mag += rng.normal(0, 2e-7, mag.shape)
    return gyro, accel, mag


def up_axis(q):
    """World up expressed in the body frame, for each attitude."""
    w, x, y, z = q.T
    return np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], 1)


def errors(q_est, q_true):
    """Tilt error and full attitude error (deg) after removing a constant world yaw."""
    u_est, u_true = up_axis(q_est), up_axis(q_true)
    tilt = np.degrees(np.arctan2(np.linalg.norm(np.cross(u_est, u_true), axis=1),
                                 np.sum(u_est * u_true, axis=1)))
    # q_est ~ yaw_offset * q_true: estimate the offset as the mean of the relative rotation.
    relative = np.array([qmult(e, qconjugate(t)) for e, t in zip(q_est, q_true, strict=True)])
    relative *= np.sign(relative[:, :1] + 1e-300)
    mean = relative[len(relative) // 3:].mean(axis=0)
    offset_yaw = 2 * math.atan2(mean[3], mean[0])
    offset = np.array([math.cos(offset_yaw / 2), 0, 0, math.sin(offset_yaw / 2)])
    aligned = np.array([qmult(qconjugate(offset), e) for e in q_est])
    dots = np.abs(np.sum(aligned * q_true, axis=1)).clip(0, 1)
    return tilt, np.degrees(2 * np.arccos(dots))
