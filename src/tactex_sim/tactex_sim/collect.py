# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Synthetic texture datasets: scripted sweeps over every texture, one labelled bag each."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import asdict
from pathlib import Path
import time

import numpy as np

from tactex_sim.recording import SweepBag
from tactex_sim.scene import Scene
from tactex_sim.sweep import plan_sweep, SweepParameters
from tactex_sim.textures import TEXTURES
from tactex_sim.world import World

# Recordings are spaced in time as if taken one after another.
RECORDING_SPACING_NS = 60 * 1_000_000_000


def slug(name: str) -> str:
    """File-name form of a texture name."""
    return name.replace(' ', '_').replace('-', '_')


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
    world.place_arm(plan.joints[0])
    world.controller = plan.targets
    metadata = {'label': texture_name, 'trial': trial, 'surface': scene.surface.kind,
                'scene': scene.name, 'source': 'tactex_sim', 'sensor_rate_hz':
                scene.sensor_rate_hz, 'sweep': asdict(parameters)}
    path = out / f'{slug(texture_name)}_{trial:04d}'
    with SweepBag(path, metadata, time_offset_ns=trial * RECORDING_SPACING_NS) as bag:
        while world.time_s < plan.times_s[-1]:
            sample = world.next_sample()
            sliding = plan.slide_start_s <= sample.time_s <= plan.slide_end_s
            bag.add(sample, world.joint_positions(), world.joint_velocities(), sliding)
    return path


def collect(scene: Scene, sweeps: int, out: Path, *, textures: Sequence[str] = tuple(TEXTURES),
            progress: Callable[[str], None] = print) -> list[Path]:
    """Record `sweeps` sweeps of every texture; deterministic for the scene's seed."""
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
