# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Sweep accuracy and planning time against the number of path samples and the probing step.

Sweeps of the uneven texture scene (MuJoCo, every effect), planned by tactex_trajectory
from pathways as a probe reports them (contacts every STEP on the true surface, 1 mm
position and 2 deg normal noise), played through the driver's own controller. The
reference, run here too: the simulator's scripted sweep (tactex_sim.sweep), which knows
the true surface, over the same stretch at the same speed, edge offset and press.

(a) against the number of path samples (trajectory points along the slide), probing
    every 10 mm; (b) against the probing step, samples every 2 mm (the default);
(c) the default sweep along pathways probed in closed loop in MuJoCo by tactex_probe's
    explorer (every 10 mm over the same stretch), not made from the true surface.
Each point: 3 pathways (seeds). Metrics over the planned contact segment: fraction in
contact (ground truth), worst 0.25 s window of the sliding speed (in brackets: of the
edge where the arm's joints hold it, before the compliant body), press depth error
(rms; in brackets the share of the plan itself, before the arm's tracking), and the
planning time (best of 5 plans, one BLAS thread; the median over the pathways). Table
on stdout, the numbers in bench/results/sweep.json, curves in
bench/results/sweep_accuracy.png.
"""

from __future__ import annotations

import json
import os

os.environ.setdefault('OPENBLAS_NUM_THREADS', '1')  # planning time on one core

from pathlib import Path  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from tactex_description.mjcf import EDGE_TIP_RADIUS_M  # noqa: E402
from tactex_sim import sweep as scripted  # noqa: E402
from tactex_sim.scene import load_scene, resolve_scene  # noqa: E402
from tactex_sim.world import World  # noqa: E402
from tactex_trajectory.path import path_from_contacts, PathSettings  # noqa: E402
from tactex_trajectory.planner import plan_sweep, SweepSettings  # noqa: E402
from tactex_trajectory.poses import PoseSettings  # noqa: E402
from tactex_trajectory.simulated_sweeps import (  # noqa: E402
    execute,
    measure,
    measure_segment,
    probe_like_pathway,
    probed_pathway,
    record,
)

RESULTS = Path(__file__).parent / 'results'
SCENE = load_scene(resolve_scene('uneven_texture'))
START_JOINTS = np.array([0.0, -0.3, 0.3, 1.2, 0.0])
FIRST_X, LAST_X = 0.085, 0.22
SPEED, OFFSET, DEPTH = 0.015, 0.5, 0.0015
SEEDS = (0, 1, 2)
SAMPLE_COUNTS = (8, 16, 32, 66, 132, 264)
PROBE_STEPS = (0.005, 0.01, 0.015, 0.02, 0.03)
REFERENCE_TRIM_S = 0.75


def our_sweep(step: float, seed: int, samples: int | None = None, *,
              closed_loop: bool = False) -> dict:
    """Plan (timed) and simulate one sweep; its measurement and planning time."""
    if closed_loop:
        points, normals, ok = probed_pathway(SCENE, FIRST_X, LAST_X, step, seed=seed)
    else:
        points, normals = probe_like_pathway(SCENE.surface, FIRST_X, LAST_X, step,
                                             np.random.default_rng(seed))
        ok = None
    settings = SweepSettings(sliding_speed_m_s=SPEED, path=PathSettings(samples=samples),
                             pose=PoseSettings(edge_offset_rad=OFFSET, press_depth_m=DEPTH))
    times = []
    for _ in range(5):
        began = time.perf_counter()
        plan = plan_sweep(points, normals, ok, START_JOINTS, settings)
        times.append(time.perf_counter() - began)
    result = measure(execute(World(SCENE, seed=seed), plan, start_joints=START_JOINTS), plan,
                     SCENE.surface)
    return {'result': result, 'plan_ms': 1e3 * min(times),
            'samples': len(plan.path.arclength_m)}


def scripted_reference(seed: int) -> dict:
    """The simulator's scripted sweep over the same stretch (it knows the surface)."""
    # The script presses sensor_edge itself `press_depth_m` in; ours presses the rim.
    parameters = scripted.SweepParameters(start_x_m=FIRST_X, speed_m_s=SPEED,
                                 press_depth_m=DEPTH - EDGE_TIP_RADIUS_M,
                                 edge_offset_rad=OFFSET, heading_rad=0.0, noise_scale=1.0,
                                 drift_pa_per_s=0.0)
    contact_s = (LAST_X - 0.005 - FIRST_X) / SPEED
    began = time.perf_counter()
    plan = scripted.plan_sweep(SCENE, parameters, duration_s=contact_s)
    plan_ms = 1e3 * (time.perf_counter() - began)
    world = World(SCENE, seed=seed)
    world.place_arm(plan.joints[0])
    run = record(world, plan.targets, plan.times_s[-1])
    xs = np.linspace(FIRST_X, LAST_X, 200)
    truth = path_from_contacts(
        np.stack([xs, np.zeros_like(xs), SCENE.surface.height(xs)], axis=1),
        np.stack([-SCENE.surface.slope(xs), np.zeros_like(xs), np.ones_like(xs)], axis=1),
        settings=PathSettings(position_noise_m=1e-6, normal_noise_rad=1e-4))
    # It starts and stops sliding at once: its ends are left out as long as our ramps.
    segment = (plan.slide_start_s + REFERENCE_TRIM_S, plan.slide_end_s - REFERENCE_TRIM_S)
    result = measure_segment(run, segment, truth, SPEED, DEPTH, plan.targets, SCENE.surface)
    return {'result': result, 'plan_ms': plan_ms}


def summarise(runs: list[dict]) -> dict:
    results = [run['result'] for run in runs]
    return {
        'contact': 100 * min(r.contact_fraction for r in results),
        'contact_mean': 100 * statistics.mean(r.contact_fraction for r in results),
        'speed': 100 * max(r.speed_error_max for r in results),
        'arm_speed': 100 * max(r.arm_speed_error_max for r in results),
        'depth': 1e3 * statistics.mean(r.press_depth_error_rms_m for r in results),
        'planned': 1e3 * statistics.mean(r.planned_depth_error_rms_m for r in results),
        'bias': 1e3 * statistics.mean(r.press_depth_error_mean_m for r in results),
        'plan_ms': statistics.median(run['plan_ms'] for run in runs),
    }


def row(label: str, numbers: dict, reference: dict) -> str:
    return (f'| {label} | {numbers["contact"]:.1f} ({numbers["contact_mean"]:.1f}) | '
            f'{numbers["speed"]:.1f} ({numbers["arm_speed"]:.1f}) | '
            f'{numbers["depth"]:.2f} ({numbers["planned"]:.2f}) | '
            f'{numbers["bias"]:+.2f} | {numbers["depth"] / reference["depth"]:.2f} | '
            f'{numbers["plan_ms"]:.0f} |')


def main() -> None:
    started = time.monotonic()
    print('reference: the scripted sweep of the simulator on the true surface ...',
          file=sys.stderr)
    reference = summarise([scripted_reference(seed) for seed in SEEDS])
    by_samples, by_step = {}, {}
    for count in SAMPLE_COUNTS:
        print(f'(a) {count} path samples ...', file=sys.stderr)
        by_samples[count] = summarise([our_sweep(0.01, seed, count) for seed in SEEDS])
    for step in PROBE_STEPS:
        print(f'(b) probing every {step * 1e3:g} mm ...', file=sys.stderr)
        by_step[step] = summarise([our_sweep(step, seed) for seed in SEEDS])
    print('(c) probed in closed loop every 10 mm ...', file=sys.stderr)
    probed = summarise([our_sweep(0.01, seed, closed_loop=True) for seed in SEEDS])
    header = ('| setting | contact % min (mean) | worst speed window % (arm) | press depth error '
              'rms mm (planned) | mean mm | depth error vs reference | planning ms (best of 5) |\n'
              '|---|---|---|---|---|---|---|')
    print()
    print(f'Uneven texture scene, {len(SEEDS)} pathways per setting, {SPEED * 1e3:g} mm/s, '
          f'edge offset {OFFSET} rad, press {DEPTH * 1e3:g} mm.')
    print()
    print(header)
    print(row('scripted sweep, true surface (reference)', reference, reference))
    for count, numbers in by_samples.items():
        print(row(f'(a) {count} samples, probed every 10 mm', numbers, reference))
    for step, numbers in by_step.items():
        print(row(f'(b) probed every {step * 1e3:g} mm, samples every 2 mm', numbers,
                  reference))
    print(row('(c) probed in closed loop (MuJoCo) every 10 mm, samples every 2 mm', probed,
              reference))
    default = by_step[0.01]
    print()
    print(f'goals: contact >= 99 %, speed within +-5 %; thresholds: >= 95 %, +-10 %. '
          f'Default (10 mm probing, 2 mm samples): contact {default["contact"]:.1f} % (worst '
          f'pathway), worst window {default["speed"]:.1f} % (the arm\'s edge '
          f'{default["arm_speed"]:.1f} %), press depth error '
          f'{default["depth"]:.2f} mm rms ({default["depth"] / reference["depth"]:.2f}x the '
          f'scripted sweep on the true surface), planned in {default["plan_ms"]:.0f} ms.')
    plot(by_samples, by_step, reference, probed)
    (RESULTS / 'sweep.json').write_text(json.dumps(
        {'speed_m_s': SPEED, 'edge_offset_rad': OFFSET, 'press_depth_m': DEPTH,
         'pathways': len(SEEDS), 'reference': reference,
         'by_samples': {str(k): v for k, v in by_samples.items()},
         'by_step_mm': {f'{k * 1e3:g}': v for k, v in by_step.items()},
         'probed_closed_loop': probed}, indent=1) + '\n',
        encoding='utf-8')
    print(f'({time.monotonic() - started:.0f} s)', file=sys.stderr)


def plot(by_samples: dict, by_step: dict, reference: dict, probed: dict) -> None:
    metrics = (('contact', 'contact, worst pathway (%)'), ('speed', 'worst speed window (%)'),
               ('depth', 'press depth error rms (mm)'), ('plan_ms', 'planning time (ms)'))
    figure, axes = plt.subplots(2, 4, figsize=(16, 7))
    for row_axes, (series, label, scale) in zip(axes, (
            (by_samples, 'path samples (probing every 10 mm)', 'log'),
            (by_step, 'probing step (mm), samples every 2 mm', 'linear')), strict=True):
        xs = [x * 1e3 if scale == 'linear' else x for x in series]
        for axis, (key, title) in zip(row_axes, metrics, strict=True):
            axis.plot(xs, [series[x][key] for x in series], 'o-', label='tactex_trajectory')
            if series is by_step:
                axis.plot(10, probed[key], '*', markersize=12, color='tab:orange',
                          label='probed in closed loop')
            extra = {'speed': ('arm_speed', "the arm's edge"),
                     'depth': ('planned', 'the plan alone')}.get(key)
            if extra:
                axis.plot(xs, [series[x][extra[0]] for x in series], 's:', color='tab:blue',
                          alpha=0.6, label=extra[1])
                axis.legend(fontsize=7)
            if key != 'plan_ms':
                axis.axhline(reference[key], color='grey', linestyle='--',
                             label='scripted, true surface')
            if key == 'contact':
                axis.axhline(95, color='red', linewidth=0.8, label='threshold')
                axis.axhline(99, color='green', linewidth=0.8, label='goal')
            if key == 'speed':
                axis.axhline(10, color='red', linewidth=0.8)
                axis.axhline(5, color='green', linewidth=0.8)
            axis.set_xscale(scale)
            axis.set_xlabel(label)
            axis.set_title(title)
            axis.grid(True, alpha=0.3)
    axes[0][0].legend(fontsize=8)
    figure.tight_layout()
    RESULTS.mkdir(exist_ok=True)
    figure.savefig(RESULTS / 'sweep_accuracy.png', dpi=100)


if __name__ == '__main__':
    main()
