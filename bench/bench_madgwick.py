# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Attitude accuracy and cost of our Madgwick filter beside imufusion and ahrs, in one run.

Seeded synthetic motions with exact ground truth (gyro: the mean body rate between
consecutive true attitudes, accel = gravity + linear acceleration in the body frame,
Earth field), with white noise, with no gyro bias and with a constant one, at 120 and
350 Hz, IMU and MARG. Reports RMS tilt error and (MARG) RMS full attitude error after
5 s, after removing each filter's constant world-yaw convention offset, and the time
after which the tilt error stays within 1 degree.

Fair by construction: the gain of every filter, ours included, is grid-tuned on a
tuning seed (TUNING_SEED: its own noise and vibration phases) and then scored on
another (SCORED_SEED); each filter is scored with its tuned gain and its own default.
imufusion gets the settings of its documentation's example (2000 dps range, 10 deg
acceleration and magnetic rejection, 5 s recovery) and, where a bias is injected, its
own gyro bias compensation (`imufusion.Bias`, the offset algorithm's name in 1.3.3);
ahrs's Madgwick starts from the tilt of the first sample, like ours. The comparison
libraries are bench-only extras (`pip install -r requirements-bench.txt`). Writes
bench/results/madgwick.md (tables) and bench/results/madgwick.json (what the README's
figures are rendered from, by bench/render_results.py).
"""

from __future__ import annotations

from collections.abc import Callable
import json
import math
from pathlib import Path
import time

import numpy as np

from tactex_sensor.madgwick import filter_batch, MadgwickConfig, MadgwickFilter
from tactex_sensor.orientation import orientation_from_gravity
from tactex_sensor.synthetic_motion import errors, G, motion, MOTIONS, readings

DURATION_S = 30.0
SETTLE_S = 5.0
GYRO_BIAS = np.array([0.010, -0.008, 0.005])
BIASES = {'no gyro bias': np.zeros(3), 'gyro bias 0.6 deg/s': GYRO_BIAS}
RATES_HZ = (120.0, 350.0)
TUNING_SEED = 1
SCORED_SEED = 42
GAIN_GRIDS = {'tactex': (0.01, 0.02, 0.03, 0.04, 0.06, 0.08, 0.1, 0.15, 0.2, 0.3),
              'imufusion': (0.05, 0.1, 0.2, 0.3, 0.5, 1.0, 2.0),
              'ahrs': (0.005, 0.01, 0.02, 0.033, 0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 4.0)}
MODES = {'IMU': False, 'MARG': True}
DEFAULT_GAINS = {'tactex': MadgwickConfig().gain, 'imufusion': 0.5, 'ahrs': None}
RESULTS = Path(__file__).parent / 'results'


Runner = Callable[..., np.ndarray]


def ours(gain: float, *, from_identity: bool = False) -> Runner:
    """Our filter (batch path) with beta = `gain`."""
    def run(gyro, accel, mag, rate, marg, biased):
        del biased  # it learns the bias itself, always
        return filter_batch(gyro, accel, 1.0 / rate, mag if marg else None, MadgwickConfig(
            gain=gain, use_mag=marg, start_from_first_sample=not from_identity))
    return run


def imufusion_runner(gain: float) -> Runner:
    """The AHRS of imufusion, its documented settings, its own bias estimate where biased."""
    def run(gyro, accel, mag, rate, marg, biased):
        import imufusion
        ahrs = imufusion.Ahrs()
        settings = imufusion.AhrsSettings()
        settings.convention = imufusion.CONVENTION_ENU
        settings.gain = gain
        settings.gyroscope_range = 2000.0
        settings.acceleration_rejection = 10.0
        settings.magnetic_rejection = 10.0
        settings.rejection_timeout = int(5 * rate)
        settings.sample_rate = int(rate)
        ahrs.set_settings(settings)
        ahrs.set_sample_period(1.0 / rate)
        bias = imufusion.Bias()
        bias_settings = imufusion.BiasSettings()
        bias_settings.sample_rate = rate
        bias.set_settings(bias_settings)
        out = np.empty((len(gyro), 4))
        gyro_deg, accel_g, mag_ut = np.degrees(gyro), accel / G, mag * 1e6
        for i in range(len(gyro)):
            rate_deg = bias.update(gyro_deg[i]) if biased else gyro_deg[i]
            if marg:
                ahrs.update(rate_deg, accel_g[i], mag_ut[i])
            else:
                ahrs.update_no_magnetometer(rate_deg, accel_g[i])
            out[i] = ahrs.get_quaternion()
        return out
    return run


def ahrs_runner(gain: float | None) -> Runner:
    """The Madgwick of ahrs (its default gain for None), from the first sample's tilt."""
    def run(gyro, accel, mag, rate, marg, biased):
        del biased  # no bias estimate of its own
        from ahrs.filters import Madgwick
        kwargs = {'frequency': rate}
        if gain is not None:
            kwargs['gain'] = gain
        filt = Madgwick(**kwargs)
        q = orientation_from_gravity(accel[0])
        out = np.empty((len(gyro), 4))
        for i in range(len(gyro)):
            if marg:
                q = filt.updateMARG(q, gyro[i], accel[i], mag[i] * 1e6, dt=1.0 / rate)
            else:
                q = filt.updateIMU(q, gyro[i], accel[i], dt=1.0 / rate)
            out[i] = q
        return out
    return run


MAKERS = {'tactex': ours, 'imufusion': imufusion_runner, 'ahrs': ahrs_runner}


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
    for label, runner in (('imufusion (C)', imufusion_runner(0.5)),
                          ('ahrs Madgwick', ahrs_runner(None))):
        try:
            m = 3000
            start = time.perf_counter()
            runner(gyro[:m], accel[:m], gyro[:m], 350.0, False, False)
            cost = (time.perf_counter() - start) / m * 1e6
            rows.append(f'| {label} | {cost:.2f} | {stream_us / cost:.2f}x |')
        except ImportError:
            rows.append(f'| {label} | not installed | |')
    return rows


def cases(seed: int):
    """Every (bias, rate, motion) case of a seed, with its readings and truth."""
    for bias_name, bias in BIASES.items():
        for rate in RATES_HZ:
            t = np.arange(0.0, DURATION_S, 1.0 / rate)
            for name in MOTIONS:
                rng = np.random.default_rng(seed)
                q_true, linear = motion(name, t, rng)
                yield (bias_name, rate, name, t, q_true,
                       readings(q_true, linear, rate, rng, bias))


def score(runner: Runner, case, marg: bool) -> dict:
    """RMS tilt, RMS attitude (MARG) and convergence of one filter on one case."""
    bias_name, rate, _, t, q_true, (gyro, accel, mag) = case
    tilt, full = errors(runner(gyro, accel, mag, rate, marg, bias_name != 'no gyro bias'),
                        q_true)
    settled = t >= SETTLE_S
    return {'rms_tilt_deg': math.sqrt(float(np.mean(tilt[settled] ** 2))),
            'rms_attitude_deg': math.sqrt(float(np.mean(full[settled] ** 2))) if marg
            else None, 'converge_s': convergence_s(tilt, t)}


def objective(result: dict) -> float:
    """What tuning minimises per case: the attitude error with MARG, the tilt without."""
    return result['rms_attitude_deg'] if result['rms_attitude_deg'] is not None \
        else result['rms_tilt_deg']


def tune() -> dict[str, dict]:
    """Per filter and mode, the gain of least mean error over every case of TUNING_SEED."""
    tuning_cases = list(cases(TUNING_SEED))
    tuned = {}
    for name, grid in GAIN_GRIDS.items():
        for mode, marg in MODES.items():
            means = {}
            for gain in grid:
                runner = MAKERS[name](gain)
                means[gain] = float(np.mean([objective(score(runner, case, marg))
                                             for case in tuning_cases]))
                print(f'tuning {name} {mode}: gain {gain:g} -> mean error {means[gain]:.3f} '
                      f'deg', flush=True)
            best = min(means, key=means.get)
            if best in (grid[0], grid[-1]):
                print(f'warning: {name} {mode} is best at the edge of its grid ({best:g})')
            tuned.setdefault(name, {})[mode] = {'gain': best, 'grid': means}
    return tuned


def given_table(tuned: dict) -> list[str]:
    """What each filter was given."""
    def gains(name: str) -> str:
        return ' / '.join(f'{tuned[name][mode]["gain"]:g}' for mode in MODES)
    return ['| filter | gain tuned on seed 1 (IMU / MARG) | default gain | gyro bias | start '
            '| other settings |', '|---|---|---|---|---|---|',
            f'| tactex | {gains("tactex")} | {DEFAULT_GAINS["tactex"]:g} | learnt by the '
            'filter | first sample (and identity, with its start-up ramp) | defaults |',
            f'| imufusion 1.3.3 | {gains("imufusion")} | 0.5 | imufusion.Bias where a bias is '
            'injected | its own start-up (gain ramp) | ENU, range 2000 dps, rejection 10 '
            'deg, recovery 5 s |',
            f'| ahrs 0.4.0 Madgwick | {gains("ahrs")} | 0.033 IMU, 0.041 MARG | none (it '
            'has none) | tilt of the first sample | frequency |']


def main() -> None:
    """Tune on one seed, score on another, print and write the tables."""
    tuned = tune()

    def filters(mode: str) -> dict[str, Runner]:
        gains = {name: tuned[name][mode]['gain'] for name in tuned}
        return {'tactex': ours(gains['tactex']),
                'tactex (from identity)': ours(gains['tactex'], from_identity=True),
                'tactex (default gain)': ours(DEFAULT_GAINS['tactex']),
                'imufusion': imufusion_runner(gains['imufusion']),
                'imufusion (default gain)': imufusion_runner(0.5),
                'ahrs': ahrs_runner(gains['ahrs']), 'ahrs (default gain)': ahrs_runner(None)}
    lines = ['| gyro bias | rate | mode | motion | filter | RMS tilt (deg) | RMS attitude (deg) '
             '| converge (s) |', '|---|---|---|---|---|---|---|---|']
    rows = []
    for case in cases(SCORED_SEED):
        bias_name, rate, name = case[:3]
        for mode, marg in MODES.items():
            for label, runner in filters(mode).items():
                result = score(runner, case, marg)
                rows.append({'bias': bias_name, 'rate_hz': rate, 'mode': 'MARG' if marg
                             else 'IMU', 'motion': name, 'filter': label, **result})
                attitude = result['rms_attitude_deg']
                line = (f'| {bias_name} | {rate:.0f} | {rows[-1]["mode"]} | {name} | {label} '
                        f'| {result["rms_tilt_deg"]:.2f} | '
                        f'{"-" if attitude is None else f"{attitude:.2f}"} | '
                        f'{result["converge_s"]:.2f} |')
                print(line, flush=True)
                lines.append(line)
    cost = ['| filter | us per sample | vs tactex streaming |', '|---|---|---|', *cost_table()]
    print('\n'.join(cost))
    given = given_table(tuned)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / 'madgwick.md').write_text(
        '# Madgwick filter: accuracy and cost (bench/bench_madgwick.py)\n\n'
        f'Gains tuned on seed {TUNING_SEED}, scored on seed {SCORED_SEED}.\n\n'
        + '\n'.join(given) + '\n\n' + '\n'.join(lines) + '\n\n' + '\n'.join(cost) + '\n',
        encoding='utf-8')
    (RESULTS / 'madgwick.json').write_text(json.dumps(
        {'tuning_seed': TUNING_SEED, 'scored_seed': SCORED_SEED, 'settle_s': SETTLE_S,
         'tuned': tuned, 'default_gain': DEFAULT_GAINS['tactex'], 'results': rows},
        indent=1, default=str) + '\n', encoding='utf-8')


if __name__ == '__main__':
    main()
