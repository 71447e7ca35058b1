# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""How far each texture's own vibration rises above the IMU's noise, per movement and path.

For every texture of the catalogue and every movement of config/movements.yaml, one
sweep of the uneven texture scene in MuJoCo along two paths:
- `sweep action`: planned by tactex_trajectory from a pathway as the live probe reports
  it (contacts every 10 mm, 0.25 mm and 1.5 deg of noise, what the live runs measured)
  as long as identify_node's part for the movement (contact and both speed ramps)
  and played through the driver's own controller, the way identify_node's Sweep goals
  move the arm (the press depth is the rim's indentation);
- `sim collect`: the simulator's scripted sweep of `tactex sim collect --movements`, at
  the movement's nominal speed, press and tilt (the movement's scene presses the rim,
  `press = "rim"`, as the sweep action does).
Each sweep runs twice with the IMU noise off, once over the texture and once over no
texture: the difference of the accelerometer and gyro readings over the contact segment
is the texture's own signal (the texture effect changes no physics, and the sensor
chips' filtering and quantisation are deterministic). Its rms (the norm over the three
axes) is given against the rms of the scene's IMU noise over three axes, and beside it
the mean contact force and barometer reading of the sweep (ground truth) and the
high-frequency content of the sweep over no texture (the rms of sample-to-sample
differences over the square root of two: what white noise of that rms would give), the
motion each path carries whatever the texture, over the whole contact segment and
without its first START_S (where a sweep that starts sliding at full speed jolts).

Keeps bench/results/texture_signal.json and texture_signal.png (the ratio per texture and
movement, one panel per path and channel).
"""

from __future__ import annotations

from dataclasses import replace
import json
import math
from pathlib import Path
import sys
import time

import numpy as np

from tactex_description.movements import load_movements, Movement
from tactex_sim import sweep as scripted
from tactex_sim.collect import movement_scene
from tactex_sim.scene import load_scene, resolve_scene
from tactex_sim.textures import TEXTURES
from tactex_sim.world import World
from tactex_trajectory.errors import SweepRefused
from tactex_trajectory.planner import plan_sweep, SweepSettings
from tactex_trajectory.poses import PoseSettings
from tactex_trajectory.simulated_sweeps import execute, probe_like_pathway

RESULTS = Path(__file__).parent / 'results' / 'texture_signal.json'
MOVEMENTS = Path(__file__).parents[1] / 'config' / 'movements.yaml'
SCENE = load_scene(resolve_scene('uneven_texture'))
QUIET = replace(SCENE, effects=tuple(e for e in SCENE.effects if e != 'imu_noise'))
START_JOINTS = np.array([0.0, -0.3, 0.3, 1.2, 0.0])  # where the bridge starts the arm
PROBE_STEP_M, PROBE_POSITION_SD_M, PROBE_NORMAL_SD_RAD = 0.01, 0.00025, math.radians(1.5)
PATHS = ('sweep action', 'sim collect')
SEED = 0
START_S = 0.25  # the first part of the contact segment, left out of the motion 'after start'


def through_sweep_action(movement: Movement, texture: str | None) -> dict:
    """One sweep as the Sweep action moves the arm: readings over its contact segment."""
    start, settings = SCENE.sweep.start_x_m, SweepSettings(
        sliding_speed_m_s=movement.speed_m_s, pose=PoseSettings(
            edge_offset_rad=movement.edge_tilt_rad, press_depth_m=movement.press_depth_m))
    length = movement.part_length_m(settings.ramp_acceleration_m_s2) + PROBE_STEP_M
    points, normals = probe_like_pathway(
        SCENE.surface, start, start + length, PROBE_STEP_M,
        np.random.default_rng(SEED), position_sd_m=PROBE_POSITION_SD_M,
        normal_sd_rad=PROBE_NORMAL_SD_RAD)
    if movement.direction == 'backward':
        points, normals = points[::-1], normals[::-1]
    plan = plan_sweep(points, normals, None, START_JOINTS, settings)
    played = execute(_world(QUIET, texture), plan, start_joints=START_JOINTS, tail_s=0.0)
    kept = (plan.contact_start_s <= played.times_s) & (played.times_s <= plan.contact_end_s)
    return _readings(np.column_stack([played.accel, played.gyro, played.force_n,
                                      played.pressure_pa, played.times_s])[kept])


def through_sim_collect(movement: Movement, texture: str | None) -> dict:
    """One sweep as `tactex sim collect --movements` scripts it, at the nominal draw."""
    scene = movement_scene(QUIET, movement)
    plan = scripted.plan_sweep(scene, scripted.SweepParameters.nominal(scene))
    world = _world(scene, texture)
    rows = []

    def keep(sample) -> None:
        if plan.slide_start_s <= sample.time_s <= plan.slide_end_s:
            rows.append(_row(sample))

    scripted.play(world, plan, keep)
    return _readings(rows)


def _world(scene, texture: str | None) -> World:
    """The scene's world over `texture`, or over no texture at all (None: no patch)."""
    return World(scene if texture else replace(scene, patches=()), seed=SEED,
                 patch_texture=texture)


def _row(sample) -> tuple:
    return (*sample.accel, *sample.gyro, sample.truth.contact.force, sample.pressure,
            sample.time_s)


def _readings(rows) -> dict:
    """Accel, gyro, force, pressure and time (from the first row) of rows as `_row` gives."""
    table = np.array(rows, dtype=float)
    return {'accel': table[:, 0:3], 'gyro': table[:, 3:6], 'force_n': table[:, 6],
            'pressure_pa': table[:, 7], 'time_s': table[:, 8] - table[0, 8]}


def rms_norm(values: np.ndarray) -> float:
    """The rms over samples of the vector norm over the three axes."""
    return float(np.sqrt(np.mean(np.sum(values ** 2, axis=1))))


def measured(sweep, movement: Movement) -> dict:
    """Every texture's own signal under `movement` along one path, and the sweep's force."""
    bare = sweep(movement, None)
    textures = {}
    for name in TEXTURES:
        felt = sweep(movement, name)
        textures[name] = {'accel_rms': rms_norm(felt['accel'] - bare['accel']),
                          'gyro_rms': rms_norm(felt['gyro'] - bare['gyro'])}
    return {'force_n': float(np.mean(bare['force_n'])),
            'pressure_pa': float(np.mean(bare['pressure_pa'])),
            'bare_accel_hf_rms': rms_norm(np.diff(bare['accel'], axis=0) / math.sqrt(2.0)),
            'bare_gyro_hf_rms': rms_norm(np.diff(bare['gyro'], axis=0) / math.sqrt(2.0)),
            'bare_gyro_hf_rms_after_start': rms_norm(np.diff(
                bare['gyro'][bare['time_s'] >= START_S], axis=0) / math.sqrt(2.0)),
            'samples': int(len(bare['force_n'])), 'textures': textures}


def plot(kept: dict, path: Path) -> None:
    """Texture signal over the noise, per texture and movement: a panel per path and channel."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    movements, textures = kept['movements'], list(TEXTURES)
    figure, panels = plt.subplots(2, 2, figsize=(12, 9), sharex=True, sharey=True)
    for row, path_name in enumerate(PATHS):
        for column, channel in enumerate(('accel', 'gyro')):
            noise = kept['noise_rms'][channel]
            rows = kept['paths'][path_name]
            ratio = np.array([[rows[m]['textures'][t][f'{channel}_rms'] / noise
                               if 'textures' in rows[m] else np.nan for m in movements]
                              for t in textures])
            axes = panels[row][column]
            image = axes.imshow(np.log10(np.maximum(ratio, 1e-3)), cmap='viridis', vmin=-2,
                                vmax=1.5, aspect='auto')
            for (i, j), value in np.ndenumerate(ratio):
                label = 'refused' if np.isnan(value) else f'{value:.2g}'
                axes.text(j, i, label, ha='center', va='center', fontsize=6,
                          color='black' if np.isnan(value) or value >= 1 else 'white')
            axes.set_title(f'{path_name}: {channel} signal / noise rms', fontsize=9)
            axes.set_xticks(range(len(movements)), movements, rotation=45, ha='right',
                            fontsize=7)
            axes.set_yticks(range(len(textures)), textures, fontsize=7)
    figure.colorbar(image, ax=panels, label='log10 (texture rms / noise rms)', shrink=0.6)
    figure.savefig(path, dpi=110, bbox_inches='tight')
    plt.close(figure)


def main() -> int:
    if '--plot' in sys.argv[1:]:
        plot(json.loads(RESULTS.read_text()), RESULTS.with_suffix('.png'))
        return 0
    began = time.monotonic()
    noise = SCENE.effect_options['imu_noise']
    movements = load_movements(MOVEMENTS).movements
    kept = {'scene': SCENE.name, 'seed': SEED, 'movements': [m.name for m in movements],
            'noise_rms': {'accel': math.sqrt(3) * noise['accel_sd'],
                          'gyro': math.sqrt(3) * noise['gyro_sd']},
            'paths': {name: {} for name in PATHS}}
    for movement in movements:
        for name, sweep in zip(PATHS, (through_sweep_action, through_sim_collect), strict=True):
            try:
                row = measured(sweep, movement)
            except SweepRefused as refused:  # the arm cannot: kept as the planner's reason
                row = {'refused': str(refused)}
            kept['paths'][name][movement.name] = row
            print(f'{movement.name} {name}: ' + (f'force {row["force_n"]:.3f} N' if 'force_n'
                                                  in row else row['refused'])
                  + f' ({time.monotonic() - began:.0f} s)', flush=True)
    kept['seconds'] = time.monotonic() - began
    RESULTS.write_text(json.dumps(kept, indent=1) + '\n', encoding='utf-8')
    plot(kept, RESULTS.with_suffix('.png'))
    return 0


if __name__ == '__main__':
    sys.exit(main())
