# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Simulator speed and accuracy, all in one run.

1. Real-time factor of a 10 s sliding sweep in each shipped scene: probe (contact +
   compliance, 120 Hz), uneven_texture (every effect, 120 Hz) and even_texture (350 Hz),
   at the physics step the world uses (the largest one <= the scene's 2 ms that divides
   the sensor period: 1.67 ms at 120 Hz, 1.43 ms at 350 Hz), beside the same sweep's
   physics and control alone (no sampling, no effects: the limit of this design).
2. The cost of each effect: the texture scene with all effects, and with each removed.
3. Timestep trade-off: the sensor pressed face-first at five points of the uneven
   surface, at 8, 5, 4, 2 and 1 physics steps per 120 Hz sample (1.04 to 8.33 ms;
   17 steps, 0.49 ms, as reference): error of the surface tilt estimated from the
   accelerometer, error of the contact force, wall time per simulated second. Table, and
   `bench/results/sim_timestep.png`.
Targets: probe scene >= 20x real time, full texture scene >= 5x. Writes
bench/results/sim.json (the README's figures are rendered from it).
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path
import time

import matplotlib

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
import mujoco  # noqa: E402
import numpy as np  # noqa: E402

from tactex_description.kinematics import inverse_kinematics  # noqa: E402
from tactex_sim.scene import load_scene, resolve_scene  # noqa: E402
from tactex_sim.sweep import plan_sweep, play, SweepParameters  # noqa: E402
from tactex_sim.world import World  # noqa: E402

RESULTS = Path(__file__).parent / 'results'
SWEEP = SweepParameters(0.10, 0.015, 0.0015, 0.5, 0.1, 1.0, 0.5)


def run_sweep(scene, seconds=10.0, repeats=3) -> tuple[float, World]:
    """Least wall time of `repeats` simulations of a sweep of `seconds` in all."""
    plan = plan_sweep(scene, SWEEP, duration_s=seconds - 2.8)
    best = math.inf
    for _ in range(repeats):
        world = World(scene, patch_texture='wood' if scene.patches else None)
        best = min(best, play(world, plan))
    return best, world


def physics_only(scene, seconds=10.0) -> float:
    """Wall time of the same sweep's physics and control alone: no sampling, no effects."""
    plan = plan_sweep(scene, SWEEP, duration_s=seconds - 2.8)
    world = World(scene, patch_texture='wood' if scene.patches else None)
    world.place_arm(plan.joints[0])
    model, data = world.model, world.data
    start = time.perf_counter()
    while data.time < plan.times_s[-1]:
        world.set_arm_targets(plan.targets(data.time))
        mujoco.mj_step(model, data)
    return time.perf_counter() - start


def speed_table(record: dict) -> list[str]:
    rows = ['| scene | effects | sensor Hz | physics step ms | real-time factor | physics + '
            'control alone | share of the limit |', '|---|---|---|---|---|---|---|']
    for name in ('probe', 'uneven_texture', 'even_texture'):
        scene = load_scene(resolve_scene(name))
        wall, world = run_sweep(scene)
        simulated = world.time_s
        bare = physics_only(scene)
        step_ms = 1e3 * world.model.opt.timestep
        record[name] = {'real_time_factor': simulated / wall,
                        'physics_alone_factor': simulated / bare, 'step_ms': step_ms,
                        'sensor_rate_hz': scene.sensor_rate_hz}
        rows.append(f'| {name} | {", ".join(scene.effects)} | {scene.sensor_rate_hz:g} | '
                    f'{step_ms:.3f} | {simulated / wall:.1f}x | {simulated / bare:.1f}x | '
                    f'{bare / wall:.2f} |')
    return rows


def effect_costs() -> list[str]:
    scene = load_scene(resolve_scene('uneven_texture'))
    wall_all, world = run_sweep(scene)
    simulated = world.time_s
    rows = ['| variant | ms per simulated s | vs all effects |', '|---|---|---|',
            f'| all effects | {1e3 * wall_all / simulated:.1f} | 1.00 |']
    for name in scene.effects:
        if name in ('contact', 'compliance'):
            continue  # without them the sweep is no longer a sweep
        variant = dataclasses.replace(scene, effects=tuple(e for e in scene.effects
                                                           if e != name),
                                      effect_options={k: v for k, v in
                                                      scene.effect_options.items()
                                                      if k != name})
        wall, _ = run_sweep(variant)
        rows.append(f'| without {name} | {1e3 * wall / simulated:.1f} | '
                    f'{wall / wall_all:.2f} (the effect costs {100 * (1 - wall / wall_all):.0f} '
                    '%) |')
    return rows


def pressed(scene, steps_per_sample, x):
    """Press face-first at x; return (tilt error deg, contact force N, wall s per sim s)."""
    variant = dataclasses.replace(scene, timestep_s=1.0 / scene.sensor_rate_hz
                                  / steps_per_sample, effects=('contact', 'compliance'))
    surface = variant.surface
    slope = float(surface.slope(x))
    normal = surface.normal(x)
    point = np.array([x, float(surface.height(x))]) - 0.002 * normal
    result = inverse_kinematics([point[0], 0.0, point[1]], math.pi / 2 - math.atan(slope))
    world = World(variant)
    world.place_arm(np.append(result.solutions[0], 0.0))
    start = time.perf_counter()
    samples = []
    while world.time_s < 2.0:
        samples.append(world.next_sample())
    wall = time.perf_counter() - start
    last = samples[-24:]
    accel = np.mean([s.accel for s in last], axis=0)
    tilt_estimate = math.degrees(math.acos(max(-1.0, min(1.0, -accel[2] /
                                                          np.linalg.norm(accel)))))
    tilt_true = math.degrees(math.atan(abs(slope)))
    force = float(np.mean([s.truth.contact.force for s in last]))
    return abs(tilt_estimate - tilt_true), force, wall / world.time_s


def timestep_table() -> list[str]:
    scene = load_scene(resolve_scene('probe'))
    points = np.linspace(0.10, 0.20, 5)
    reference = [pressed(scene, 17, x)[1] for x in points]
    rows = ['| steps per sample | timestep ms | tilt error deg (mean / max) | force error % '
            '(mean) | wall ms per sim s |', '|---|---|---|---|---|']
    curves = []
    for steps in (8, 5, 4, 2, 1):
        timestep = 1.0 / scene.sensor_rate_hz / steps
        results = [pressed(scene, steps, x) for x in points]
        tilt = np.array([r[0] for r in results])
        force = np.array([abs(r[1] - f) / max(f, 1e-9) for r, f in zip(results, reference,
                                                                        strict=True)])
        wall = 1e3 * float(np.mean([r[2] for r in results]))
        curves.append((timestep * 1e3, tilt.mean(), 100 * force.mean(), wall))
        rows.append(f'| {steps} | {timestep * 1e3:.2f} | {tilt.mean():.2f} / {tilt.max():.2f} | '
                    f'{100 * force.mean():.1f} | {wall:.0f} |')
    RESULTS.mkdir(exist_ok=True)
    figure, axes = plt.subplots(1, 2, figsize=(9, 3.5))
    steps = [c[0] for c in curves]
    axes[0].plot(steps, [c[1] for c in curves], 'o-', label='tilt error (deg)')
    axes[0].plot(steps, [c[2] for c in curves], 's-', label='contact force error (%)')
    axes[0].set_xlabel('physics timestep (ms)')
    axes[0].legend()
    axes[1].plot(steps, [c[3] for c in curves], 'o-')
    axes[1].set_xlabel('physics timestep (ms)')
    axes[1].set_ylabel('wall ms per simulated s')
    figure.suptitle('Probe scene: accuracy against cost (0.49 ms reference)')
    figure.tight_layout()
    figure.savefig(RESULTS / 'sim_timestep.png', dpi=100)
    return rows


def main() -> None:
    """Print the three tables, keep the real-time factors."""
    record: dict = {}
    for rows in (speed_table(record), effect_costs(), timestep_table()):
        print('\n'.join(rows), end='\n\n', flush=True)
    print('targets: probe >= 20x real time, full texture scene >= 5x')
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / 'sim.json').write_text(json.dumps(record, indent=1) + '\n', encoding='utf-8')


if __name__ == '__main__':
    main()
