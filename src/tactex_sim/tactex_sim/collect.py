# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Synthetic texture datasets: scripted sweeps over every texture, one labelled bag each."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import asdict
from pathlib import Path
import tempfile
import time

import numpy as np

from tactex_common.cluster import ray_session, run_tasks
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


def recorded_sweep(scene: Scene, texture_name: str, trial: int,
                   seed_sequence: np.random.SeedSequence) -> tuple[str, dict[str, bytes]]:
    """One sweep recorded where this runs: its bag's folder name and files (path -> bytes).

    A Ray task on any node: the bag is written to a scratch folder there and comes back
    as bytes, so the caller writes every bag into its own output folder.
    """
    with tempfile.TemporaryDirectory(prefix='tactex-sweep-') as scratch:
        path = record_sweep(scene, texture_name, trial, Path(scratch), seed_sequence)
        return path.name, {str(item.relative_to(path)): item.read_bytes()
                           for item in sorted(path.rglob('*')) if item.is_file()}


def collect(scene: Scene, sweeps: int, out: Path, *, textures: Sequence[str] = tuple(TEXTURES),
            progress: Callable[[str], None] = print, workers: int | None = None,
            address: str | None = None) -> list[Path]:
    """Record `sweeps` sweeps of every texture; deterministic for the scene's seed.

    Each sweep draws from its own seed (scene seed, texture, sweep number), so the bags
    are the same whatever the number of workers and the order sweeps finish in.

    Args:
        scene: a collectable scene.
        sweeps: sweeps per texture.
        out: folder for the bags (`<texture>_<trial>`, one per sweep).
        textures: the textures to sweep, in order (trial numbers follow it).
        progress: receives a line per finished sweep.
        workers: sweeps recorded at once. None or 1 without `address` records here, one
            after another; more start a local Ray instance with that many cores.
        address: a Ray cluster to run the sweeps on (every node needs tactex installed);
            `workers` then caps the sweeps in flight (None: as many as it takes).

    Raises:
        SceneError: the scene cannot slide in contact over a patch (`check_collectable`).
        SimError: a sweep is unreachable or never touched the patch.
        ClusterError: Ray cannot be started or reached.
    """
    check_collectable(scene)
    out.mkdir(parents=True, exist_ok=True)
    jobs = [(name, texture_index * sweeps + sweep,
             np.random.SeedSequence([scene.seed, TEXTURES_INDEX[name], sweep]))
            for texture_index, name in enumerate(textures) for sweep in range(sweeps)]
    paths: dict[int, Path] = {}
    start = time.monotonic()

    def finished(index: int, path: Path) -> None:
        paths[index] = path
        eta = (time.monotonic() - start) / len(paths) * (len(jobs) - len(paths))
        progress(f'[{len(paths)}/{len(jobs)}] {path.name}  (about {eta:.0f} s left)')

    if (workers or 1) == 1 and address is None:
        for index, (name, trial, sequence) in enumerate(jobs):
            finished(index, record_sweep(scene, name, trial, out, sequence))
    else:
        def write(index: int, result: tuple[str, dict[str, bytes]]) -> None:
            folder = out / result[0]
            for relative, content in result[1].items():
                (folder / relative).parent.mkdir(parents=True, exist_ok=True)
                (folder / relative).write_bytes(content)
            finished(index, folder)

        with ray_session(address=address, cpus=None if address else workers):
            run_tasks(recorded_sweep, jobs, shared=(scene,), on_result=write,
                      max_in_flight=workers if address else None)
    return [paths[index] for index in range(len(jobs))]


TEXTURES_INDEX = {name: index for index, name in enumerate(TEXTURES)}
