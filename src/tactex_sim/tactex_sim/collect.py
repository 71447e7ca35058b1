# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Synthetic texture datasets: scripted sweeps over every texture, one labelled bag each."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import asdict
from pathlib import Path
import time

import numpy as np

from tactex_sim.errors import SceneError, SimError
from tactex_sim.recording import SweepBag
from tactex_sim.scene import Scene
from tactex_sim.sweep import plan_sweep, play, SweepParameters
from tactex_sim.textures import TEXTURES
from tactex_sim.world import Sample, World

# Recordings are spaced in time as if taken one after another.
RECORDING_SPACING_NS = 60 * 1_000_000_000


def slug(name: str) -> str:
    """File-name form of a texture name."""
    return name.replace(' ', '_').replace('-', '_')


def check_collectable(scene: Scene) -> None:
    """Refuse a scene whose sweeps cannot slide in contact over a texture patch.

    Raises:
        SceneError: naming the scene file, section and key, and the fix.
    """
    where = scene.path or scene.name
    sweep, spread = scene.sweep, scene.variability
    missing = [e for e in ('contact', 'texture') if e not in scene.effects]
    if missing:
        raise SceneError(f'{where}: effects lack {", ".join(missing)}: without them the sensor '
                         'never touches or feels a texture; add them to effects')
    if not scene.patches:
        raise SceneError(f'{where}: no [[patches]]: add a texture patch on the swept path')
    if not sweep.speed_m_s > 0 or not sweep.contact_s > 0:
        raise SceneError(f'{where}: [sweep] speed_m_s and contact_s must be > 0 (got '
                         f'{sweep.speed_m_s}, {sweep.contact_s}): a sensor that does not move '
                         'does not slide')
    if not 0 <= spread.speed_fraction < 0.5:
        raise SceneError(f'{where}: [variability] speed_fraction must be in [0, 0.5), got '
                         f'{spread.speed_fraction}: a larger spread can draw a standing sweep')
    depth_mean, depth_sd = spread.press_depth_m
    if not depth_mean > 0 or depth_sd < 0:
        raise SceneError(f'{where}: [variability] press_depth_m mean must be > 0 and its sd '
                         f'>= 0 (got {list(spread.press_depth_m)}): the edge never presses '
                         'into the surface')
    start, end = sweep.start_x_m, sweep.start_x_m + sweep.speed_m_s * sweep.contact_s
    if not any(p.y_m[0] <= 0.0 <= p.y_m[1] and p.x_m[0] < end and p.x_m[1] > start
               for p in scene.patches):
        raise SceneError(f'{where}: no patch lies on the swept path (x {start:.3f}..{end:.3f} '
                         'm at y 0): move a [[patches]] rectangle onto it or change [sweep] '
                         'start_x_m')


def record_sweep(scene: Scene, texture_name: str, trial: int, out: Path,
                 seed_sequence: np.random.SeedSequence) -> Path:
    """Simulate one sweep over `texture_name` and write it to out/<texture>_<trial>."""
    rng = np.random.default_rng(seed_sequence)
    parameters = SweepParameters.draw(scene, rng)
    plan = plan_sweep(scene, parameters)
    world = World(scene, seed=int(rng.integers(2**32)), patch_texture=texture_name,
                  texture_heading_rad=parameters.heading_rad,
                  noise_scale=parameters.noise_scale,
                  drift_pa_per_s=parameters.drift_pa_per_s)
    metadata = {'label': texture_name, 'trial': trial, 'surface': scene.surface.kind,
                'scene': scene.name, 'source': 'tactex_sim', 'sensor_rate_hz':
                scene.sensor_rate_hz, 'sweep': asdict(parameters)}
    path = out / f'{slug(texture_name)}_{trial:04d}'
    over_texture = 0
    with SweepBag(path, metadata, time_offset_ns=trial * RECORDING_SPACING_NS) as bag:
        def write(sample: Sample) -> None:
            nonlocal over_texture
            sliding = plan.slide_start_s <= sample.time_s <= plan.slide_end_s
            over_texture += sliding and sample.truth.contact.touching \
                and sample.truth.texture == texture_name
            bag.add(sample, world.joint_positions(), world.joint_velocities(), sliding)
        play(world, plan, write)
    if not over_texture:
        raise SimError(f'{scene.path or scene.name}: sweep {trial} ({texture_name}) never '
                       'touched the patch while sliding; check [sweep], [variability] '
                       'press_depth_m and [[patches]]')
    return path


def collect(scene: Scene, sweeps: int, out: Path, *, textures: Sequence[str] = tuple(TEXTURES),
            progress: Callable[[str], None] = print) -> list[Path]:
    """Record `sweeps` sweeps of every texture; deterministic for the scene's seed.

    Raises:
        SceneError: the scene cannot slide in contact over a patch (`check_collectable`).
        SimError: a sweep is unreachable or never touched the patch.
    """
    check_collectable(scene)
    out.mkdir(parents=True, exist_ok=True)
    total = sweeps * len(textures)
    paths = []
    start = time.monotonic()
    for texture_index, name in enumerate(textures):
        for sweep in range(sweeps):
            trial = texture_index * sweeps + sweep
            sequence = np.random.SeedSequence([scene.seed, TEXTURES_INDEX[name], sweep])
            paths.append(record_sweep(scene, name, trial, out, sequence))
            done = len(paths)
            eta = (time.monotonic() - start) / done * (total - done)
            progress(f'[{done}/{total}] {paths[-1].name}  (about {eta:.0f} s left)')
    return paths


TEXTURES_INDEX = {name: index for index, name in enumerate(TEXTURES)}
