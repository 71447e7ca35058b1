# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Sections 3, 5 and 6: probing, simulation and attitude filtering, accuracy against time.

3. Closed-loop probing of the uneven plate (`tactex_probe.closed_loop`) at several step
   sizes and descent speeds: normal and position error against total probing time.
5. One fixed sweep of the uneven-texture scene at several physics steps and with each
   optional effect removed: real-time factor, and the spectral distance of the
   generated signals to the reference (the finest step, every effect): the RMS over
   frequency of the log ratio of their Welch power spectra (dB), averaged over the
   accelerometer, gyroscope and barometer channels. The reference run again with
   another noise seed gives the distance that is noise alone.
6. Madgwick (`tactex_sensor.madgwick`) on synthetic motions with exact ground truth
   (`tactex_sensor.synthetic_motion`) at several rates and gains: RMS tilt and attitude
   error, and the cost per sample.
"""

from __future__ import annotations

from collections.abc import Callable
import dataclasses
import math
import time

import numpy as np

from tactex.accuracy_time.sizes import Size

SIGNALS = ('accel x', 'accel y', 'accel z', 'gyro x', 'gyro y', 'gyro z', 'pressure')
# The fidelity runs' one fixed sweep: the scene's nominal sweep, pressed 1.5 mm and
# turned 0.1 rad off the path so that both tangential axes see the texture.
FIDELITY_SWEEP = dict(press_depth_m=0.0015, heading_rad=0.1)
REFERENCE_STEPS = 17  # physics steps per sample of the reference run
STEPS_PER_SAMPLE = (1, 2, 4, 8)
FILTER_MOTIONS = ('tactile', 'slow sweep 0.2 Hz')
SETTLE_S = 3.0


def probing(size: Size, log: Callable[[str], None]) -> dict:
    """Section 3: per (step, descent speed), errors and probing time of the line.

    The first setting's run is kept (under `_first_run`) for section 7.
    """
    from tactex_probe.closed_loop import PLATE_LINE, run_probe, score_run, summary
    from tactex_probe.explorer_interface import ExplorerConfig
    from tactex_probe.pathway import ProbeParameters
    from tactex_sim.scene import load_scene, resolve_scene
    scene = load_scene(resolve_scene('probe'))
    rows, first = [], None
    for step, descent in size.probe_settings:
        parameters = ProbeParameters(**{**PLATE_LINE, 'span': size.probe_span_m}, step=step,
                                     descent_speed=descent)
        began = time.perf_counter()
        run = run_probe(scene, parameters, ExplorerConfig())
        wall = time.perf_counter() - began
        result = summary(score_run(run))
        rows.append({'step_mm': 1e3 * step, 'descent_mm_s': 1e3 * descent,
                     'points': len(run.pathway.probes), **result,
                     'probing_s': run.sim_time_s, 'wall_s': wall})
        first = first or {'run': run, 'wall_s': wall}
        log(f'  step {1e3 * step:g} mm, descent {1e3 * descent:g} mm/s: normal '
            f'{result["normal_mean_deg"]:.2f} deg, position {result["position_mean_mm"]:.2f} '
            f'mm, {run.sim_time_s:.0f} s of probing')
    return {'rows': rows, 'span_mm': 1e3 * size.probe_span_m, '_first_run': first}


def _spectra(scene, seconds: float, seed: int) -> tuple[np.ndarray, float, float, float]:
    """Welch spectra (signal, frequency) of the sliding part of one fixed sweep."""
    from scipy.signal import welch

    from tactex_sim.sweep import plan_sweep, play, SweepParameters
    from tactex_sim.world import World
    parameters = dataclasses.replace(SweepParameters.nominal(scene), **FIDELITY_SWEEP)
    plan = plan_sweep(scene, parameters, duration_s=seconds)
    world = World(scene, seed=seed, patch_texture='wood')
    samples = []
    wall = play(world, plan, samples.append)
    sliding = np.array([plan.slide_start_s <= s.time_s <= plan.slide_end_s for s in samples])
    values = np.array([[*s.accel, *s.gyro, s.pressure] for s in samples])[sliding]
    _, power = welch(values, fs=scene.sensor_rate_hz, nperseg=min(256, len(values)), axis=0)
    return power.T, wall, world.time_s, 1e3 * world.model.opt.timestep


def spectral_distance_db(power: np.ndarray, reference: np.ndarray) -> float:
    """Mean over signals of the RMS over frequency of 10 log10(power / reference) (dB).

    Signals one of the two runs does not simulate (NaN, e.g. pressure without the
    barometer effect) are left out; NaN if no signal is left.
    """
    floor = 1e-30
    both = np.isfinite(power).all(axis=1) & np.isfinite(reference).all(axis=1)
    if not both.any():
        return math.nan
    ratio = 10 * np.log10((power[both] + floor) / (reference[both] + floor))
    return float(np.mean(np.sqrt(np.mean(ratio ** 2, axis=1))))


def simulation_cost(size: Size, log: Callable[[str], None], *, seed: int) -> dict:
    """Section 5: real-time factor and spectral distance per physics step and effect set."""
    from tactex_sim.scene import load_scene, resolve_scene
    base = load_scene(resolve_scene('uneven_texture'))
    period = 1.0 / base.sensor_rate_hz
    reference, wall, simulated, step_ms = _spectra(
        dataclasses.replace(base, timestep_s=period / REFERENCE_STEPS), size.sim_seconds, seed)
    rows = [{'variant': f'reference: {REFERENCE_STEPS} steps per sample, every effect',
             'step_ms': step_ms, 'effects': ', '.join(base.effects),
             'real_time_factor': simulated / wall, 'distance_db': 0.0, 'not_simulated': []}]
    variants = [(f'reference, noise seed {seed + 1}', base, seed + 1, REFERENCE_STEPS)]
    variants += [(f'{steps} step{"s" * (steps > 1)} per sample', base, seed, steps)
                 for steps in STEPS_PER_SAMPLE]
    variants += [(f'without {effect}', dataclasses.replace(
        base, effects=tuple(e for e in base.effects if e != effect),
        effect_options={k: v for k, v in base.effect_options.items() if k != effect}),
        seed, REFERENCE_STEPS) for effect in base.effects if effect not in (
        'contact', 'compliance')]
    for label, scene, run_seed, steps in variants:
        power, wall, simulated, step_ms = _spectra(
            dataclasses.replace(scene, timestep_s=period / steps), size.sim_seconds, run_seed)
        rows.append({'variant': label, 'step_ms': step_ms, 'effects': ', '.join(scene.effects),
                     'real_time_factor': simulated / wall,
                     'distance_db': spectral_distance_db(power, reference),
                     'not_simulated': [name for name, row in zip(SIGNALS, power, strict=True)
                                       if not np.isfinite(row).all()]})
        log(f'  {label}: {simulated / wall:.1f}x real time, '
            f'{rows[-1]["distance_db"]:.2f} dB from the reference')
    return {'rows': rows, 'seconds': size.sim_seconds, 'scene': base.name}


def filter_rate(size: Size, log: Callable[[str], None], *, seed: int) -> dict:
    """Section 6: RMS errors of Madgwick per rate and gain, and its cost per sample."""
    from tactex_sensor.madgwick import filter_batch, MadgwickConfig, MadgwickFilter
    from tactex_sensor.synthetic_motion import errors, motion, readings
    rows, costs = [], []
    default_gain = MadgwickConfig().gain
    gains = sorted({*size.filter_gains, default_gain})
    for rate in size.filter_rates_hz:
        t = np.arange(0.0, size.filter_seconds, 1.0 / rate)
        cases = []
        for name in FILTER_MOTIONS:
            rng = np.random.default_rng(seed)
            q_true, linear = motion(name, t, rng)
            cases.append((q_true, readings(q_true, linear, rate, rng, np.zeros(3))))
        settled = t >= SETTLE_S
        for gain in gains:
            tilt_sq, full_sq = [], []
            for q_true, (gyro, accel, mag) in cases:
                estimate = filter_batch(gyro, accel, 1.0 / rate, mag,
                                        MadgwickConfig(gain=gain, use_mag=True))
                tilt, full = errors(estimate, q_true)
                tilt_sq.append(np.mean(tilt[settled] ** 2))
                full_sq.append(np.mean(full[settled] ** 2))
            rows.append({'rate_hz': rate, 'gain': gain, 'default': gain == default_gain,
                         'rms_tilt_deg': math.sqrt(float(np.mean(tilt_sq))),
                         'rms_attitude_deg': math.sqrt(float(np.mean(full_sq)))})
        gyro, accel, mag = cases[0][1]
        filter_batch(gyro[:8], accel[:8], 1.0 / rate, mag[:8])  # compile outside the timing
        began = time.perf_counter()
        filter_batch(gyro, accel, 1.0 / rate, mag)
        batch_us = 1e6 * (time.perf_counter() - began) / len(gyro)
        streaming = MadgwickFilter()
        count = min(len(gyro), 2000)
        began = time.perf_counter()
        for i in range(count):
            streaming.update(gyro[i], accel[i], 1.0 / rate, mag[i])
        stream_us = 1e6 * (time.perf_counter() - began) / count
        costs.append({'rate_hz': rate, 'batch_us': batch_us, 'stream_us': stream_us,
                      'stream_cpu_share': stream_us * 1e-6 * rate})
        best = min((r for r in rows if r['rate_hz'] == rate), key=lambda r: r['rms_attitude_deg'])
        log(f'  {rate:g} Hz: best gain {best["gain"]:g} ({best["rms_attitude_deg"]:.2f} deg '
            f'attitude), {stream_us:.1f} us per sample streaming')
    return {'rows': rows, 'costs': costs, 'motions': FILTER_MOTIONS,
            'seconds': size.filter_seconds, 'default_gain': default_gain}
