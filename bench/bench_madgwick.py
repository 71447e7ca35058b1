# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Attitude accuracy and cost of our Madgwick filter beside imufusion and ahrs, in one run.

Seeded synthetic motions with exact ground truth (gyro: the mean body rate between
consecutive true attitudes, accel = gravity + linear acceleration in the body frame, Earth field),
with white noise and a constant gyro bias, at 120 and 350 Hz, IMU and MARG. Reports
RMS tilt error and (MARG) RMS full attitude error after 5 s, after removing each
filter's constant world-yaw convention offset, and the time after which the tilt
error stays within 1 degree. The comparison libraries are bench-only extras
(`pip install -r requirements-bench.txt`); missing ones are skipped and said so.
Writes `bench/results/madgwick.md`.
"""

from __future__ import annotations

import math
from pathlib import Path
import time

import numpy as np
from transforms3d.euler import euler2quat
from transforms3d.quaternions import qconjugate, qmult

from tactex_sensor.madgwick import filter_batch, MadgwickConfig, MadgwickFilter
from tactex_sensor.orientation import rotate

G = 9.80665
FIELD_ENU = np.array([0.0, 2.0e-5, -4.3e-5])
DURATION_S = 30.0
SETTLE_S = 5.0
GYRO_BIAS = np.array([0.010, -0.008, 0.005])
RESULTS = Path(__file__).parent / 'results'


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


def readings(q_true, linear, rate_hz, rng):
    """Gyro, accel, mag a real sensor following q_true reads (with noise and bias)."""
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
    gyro += GYRO_BIAS + rng.normal(0, 0.003, gyro.shape)
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


def run_ours(gyro, accel, mag, rate, marg):
    return filter_batch(gyro, accel, 1.0 / rate, mag if marg else None,
                        MadgwickConfig(use_mag=marg))


def run_ours_from_identity(gyro, accel, mag, rate, marg):
    return filter_batch(gyro, accel, 1.0 / rate, mag if marg else None,
                        MadgwickConfig(use_mag=marg, start_from_first_sample=False))


def run_imufusion(gyro, accel, mag, rate, marg):
    import imufusion
    ahrs = imufusion.Ahrs()
    settings = imufusion.AhrsSettings()
    settings.convention = imufusion.CONVENTION_ENU
    settings.sample_rate = int(rate)
    ahrs.set_settings(settings)
    ahrs.set_sample_period(1.0 / rate)
    out = np.empty((len(gyro), 4))
    gyro_deg, accel_g, mag_ut = np.degrees(gyro), accel / G, mag * 1e6
    for i in range(len(gyro)):
        if marg:
            ahrs.update(gyro_deg[i], accel_g[i], mag_ut[i])
        else:
            ahrs.update_no_magnetometer(gyro_deg[i], accel_g[i])
        out[i] = ahrs.get_quaternion()
    return out


def ahrs_runner(gain):
    def run(gyro, accel, mag, rate, marg):
        from ahrs.filters import Madgwick
        kwargs = {'frequency': rate}
        if gain is not None:
            kwargs['gain'] = gain
        filt = Madgwick(**kwargs)
        q = np.array([1.0, 0.0, 0.0, 0.0])
        out = np.empty((len(gyro), 4))
        for i in range(len(gyro)):
            if marg:
                q = filt.updateMARG(q, gyro[i], accel[i], mag[i] * 1e6, dt=1.0 / rate)
            else:
                q = filt.updateIMU(q, gyro[i], accel[i], dt=1.0 / rate)
            out[i] = q
        return out
    return run


def convergence_s(tilt, t):
    """First time after which the tilt error stays within 1 degree (inf if never)."""
    above = np.nonzero(tilt > 1.0)[0]
    if above.size == 0:
        return 0.0
    return math.inf if above[-1] + 1 >= t.size else float(t[above[-1] + 1])


def cost_table() -> list[str]:
    """Per-sample cost of the streaming and batch paths beside the others."""
    rng = np.random.default_rng(0)
    n = 20000
    gyro = rng.normal(0, 0.1, (n, 3))
    accel = rng.normal(0, 0.1, (n, 3)) + (0, 0, G)
    rows = []
    filt = MadgwickFilter()
    g_list, a_list = gyro.tolist(), accel.tolist()
    filt.update(g_list[0], a_list[0], 1 / 350)  # first sample: attitude set, JIT loaded
    start = time.perf_counter()
    for i in range(n):
        filt.update(g_list[i], a_list[i], 1 / 350)
    stream_us = (time.perf_counter() - start) / n * 1e6
    filter_batch(gyro[:10], accel[:10], 1 / 350)  # compile outside the timing
    start = time.perf_counter()
    filter_batch(gyro, accel, 1 / 350)
    batch_us = (time.perf_counter() - start) / n * 1e6
    rows.append(f'| tactex streaming (Python) | {stream_us:.2f} | 1.0 |')
    rows.append(f'| tactex batch (numba) | {batch_us:.3f} | {stream_us / batch_us:.0f}x faster |')
    for label, runner in (('imufusion (C)', run_imufusion), ('ahrs Madgwick', ahrs_runner(None))):
        try:
            m = 3000
            start = time.perf_counter()
            runner(gyro[:m], accel[:m], gyro[:m], 350.0, False)
            cost = (time.perf_counter() - start) / m * 1e6
            rows.append(f'| {label} | {cost:.2f} | {stream_us / cost:.2f}x |')
        except ImportError:
            rows.append(f'| {label} | not installed | |')
    return rows


def main() -> None:
    """Run every motion through every filter and print/write the tables."""
    filters = {'tactex': run_ours, 'tactex (from identity)': run_ours_from_identity,
               'imufusion': run_imufusion,
               'ahrs (default gain)': ahrs_runner(None), 'ahrs (gain 0.1)': ahrs_runner(0.1)}
    motions = ('static tilt 30 deg', 'slow sweep 0.2 Hz', 'tactile', 'shaking 2 m/s^2',
               'flip 180 deg in 1 s')
    lines = ['| rate | mode | motion | filter | RMS tilt (deg) | RMS attitude (deg) | '
             'converge (s) |', '|---|---|---|---|---|---|---|']
    for rate in (120.0, 350.0):
        t = np.arange(0.0, DURATION_S, 1.0 / rate)
        for name in motions:
            rng = np.random.default_rng(42)
            q_true, linear = motion(name, t, rng)
            gyro, accel, mag = readings(q_true, linear, rate, rng)
            for marg in (False, True):
                for label, runner in filters.items():
                    try:
                        q_est = runner(gyro, accel, mag, rate, marg)
                    except ImportError:
                        continue
                    tilt, full = errors(q_est, q_true)
                    settled = t >= SETTLE_S
                    rms_tilt = math.sqrt(np.mean(tilt[settled] ** 2))
                    rms_full = math.sqrt(np.mean(full[settled] ** 2)) if marg else math.nan
                    line = (f'| {rate:.0f} | {"MARG" if marg else "IMU"} | {name} | {label} | '
                            f'{rms_tilt:.2f} | {"-" if not marg else f"{rms_full:.2f}"} | '
                            f'{convergence_s(tilt, t):.2f} |')
                    print(line, flush=True)
                    lines.append(line)
    cost = ['| filter | us per sample | vs tactex streaming |', '|---|---|---|', *cost_table()]
    print('\n'.join(cost))
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / 'madgwick.md').write_text(
        '# Madgwick filter: accuracy and cost (bench/bench_madgwick.py)\n\n'
        + '\n'.join(lines) + '\n\n' + '\n'.join(cost) + '\n', encoding='utf-8')


if __name__ == '__main__':
    main()
