# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Synthetic texture datasets: scripted sweeps over every texture, one labelled bag each.

With a movement file, every texture is swept under every movement: the movement's speed,
press depth, tilt, direction and contact length replace the scene's nominal sweep, the
scene's variability drawn around them; each recording's metadata names its movement.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import asdict, replace
import math
from pathlib import Path
import tempfile
import time
import zlib

import numpy as np

from tactex_common.cluster import ray_session, run_tasks
from tactex_description.movements import Movement, MovementSet
from tactex_description.speed_ramp import RAMP_ACCELERATION_M_S2
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
    if sweep.direction not in (1, -1):
        raise SceneError(f'{where}: [sweep] direction must be 1 (towards +x) or -1, got '
                         f'{sweep.direction!r}')
    start, end = sorted((sweep.start_x_m, sweep.start_x_m
                         + sweep.direction * sweep.speed_m_s * sweep.contact_s))
    if not any(p.y_m[0] <= 0.0 <= p.y_m[1] and p.x_m[0] < end and p.x_m[1] > start
               for p in scene.patches):
        raise SceneError(f'{where}: no patch lies on the swept path (x {start:.3f}..{end:.3f} '
                         'm at y 0): move a [[patches]] rectangle onto it or change [sweep] '
                         'start_x_m')


def movement_scene(scene: Scene, movement: Movement) -> Scene:
    """The scene with its nominal sweep replaced by `movement`, its variability kept.

    The scene's swept path ([sweep] start_x_m on, speed_m_s x contact_s long, towards +x)
    stands for a probed pathway, and the movement slides its part of it as the Sweep
    action slides a movement's part of a pathway: forward from the path's start, backward
    from its end back towards the start; the speed ramps up before the contact and down
    after it (at the action's ramp acceleration as shipped). Its press depth is the rim's
    indentation as the Sweep action presses it.

    Raises:
        SceneError: the movement's part, drawn starts included, runs off the texture patch.
    """
    ramps = RAMP_ACCELERATION_M_S2
    part_m = movement.part_length_m(ramps)
    backward = movement.direction == 'backward'
    path_start = scene.sweep.start_x_m
    start = path_start + (scene.sweep.speed_m_s * scene.sweep.contact_s if backward else 0.0)
    # Starts are drawn within two standard deviations (SweepParameters.draw).
    drawn_m = 2.0 * scene.variability.start_x_m
    low, high = _patch_span(scene, start)
    room = (start - drawn_m - low) if backward else (high - start - drawn_m)
    if part_m > room + 1e-9:
        where = "swept path's end" if backward else "swept path's start"
        raise SceneError(f'{scene.path or scene.name}: movement {movement.name} slides '
                         f'{1e3 * movement.contact_length_m:.0f} mm and ramps its speed over '
                         f'{1e3 * (part_m - movement.contact_length_m):.0f} mm more; the '
                         f'texture patch holds {1e3 * max(0.0, room):.0f} mm from the {where} '
                         f'(x = {start:.3f} m, less two [variability] start_x_m): shorten its '
                         'contact_length or lower its speed')
    sweep = replace(scene.sweep, speed_m_s=movement.speed_m_s, contact_s=movement.contact_s,
                    edge_offset_rad=movement.edge_tilt_rad, direction=-1 if backward else 1,
                    press='rim', ramp_acceleration_m_s2=ramps, start_x_m=start)
    spread = replace(scene.variability, press_depth_m=(movement.press_depth_m,
                                                       scene.variability.press_depth_m[1]))
    return replace(scene, sweep=sweep, variability=spread)


def _ramps(scene: Scene) -> dict:
    """The sweep's ramp acceleration for a recording's metadata (none: full speed at once)."""
    acceleration = scene.sweep.ramp_acceleration_m_s2
    return {'ramp_acceleration_m_s2': acceleration} if math.isfinite(acceleration) else {}


def _patch_span(scene: Scene, x_m: float) -> tuple[float, float]:
    """The x extent (m) of the texture patches at y = 0 around `x_m` ((x_m, x_m): none)."""
    spans = [p.x_m for p in scene.patches if p.y_m[0] <= 0.0 <= p.y_m[1]
             and p.x_m[0] <= x_m <= p.x_m[1]]
    return (min(s[0] for s in spans), max(s[1] for s in spans)) if spans else (x_m, x_m)


def record_sweep(scene: Scene, texture_name: str, trial: int, out: Path,
                 seed_sequence: np.random.SeedSequence, movement: str = '') -> Path:
    """Simulate one sweep over `texture_name` and write it to out/<texture>[_<movement>]_<trial>.

    `movement` names the movement `scene` was made for (`movement_scene`), if any.
    """
    rng = np.random.default_rng(seed_sequence)
    parameters = SweepParameters.draw(scene, rng)
    plan = plan_sweep(scene, parameters)
    world = World(scene, seed=int(rng.integers(2**32)), patch_texture=texture_name,
                  texture_heading_rad=parameters.heading_rad,
                  noise_scale=parameters.noise_scale,
                  drift_pa_per_s=parameters.drift_pa_per_s)
    metadata = {'label': texture_name, 'trial': trial, 'surface': scene.surface.kind,
                'scene': scene.name, 'source': 'tactex_sim', 'sensor_rate_hz':
                scene.sensor_rate_hz, 'sweep': {**asdict(parameters), 'press': scene.sweep.press,
                                                 **_ramps(scene)},
                **({'movement': movement} if movement else {})}
    path = out / f'{slug(texture_name)}{"_" + movement if movement else ""}_{trial:04d}'
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


def recorded_sweep(scenes: dict[str, Scene], movement: str, texture_name: str, trial: int,
                   seed_sequence: np.random.SeedSequence) -> tuple[str, dict[str, bytes]]:
    """One sweep recorded where this runs: its bag's folder name and files (path -> bytes).

    A Ray task on any node: the bag is written to a scratch folder there and comes back
    as bytes, so the caller writes every bag into its own output folder. `scenes` maps
    each movement's name ('' without movements) to its scene.
    """
    with tempfile.TemporaryDirectory(prefix='tactex-sweep-') as scratch:
        path = record_sweep(scenes[movement], texture_name, trial, Path(scratch),
                            seed_sequence, movement)
        return path.name, {str(item.relative_to(path)): item.read_bytes()
                           for item in sorted(path.rglob('*')) if item.is_file()}


def collect(scene: Scene, sweeps: int, out: Path, *, textures: Sequence[str] = tuple(TEXTURES),
            progress: Callable[[str], None] = print, workers: int | None = None,
            address: str | None = None, movements: MovementSet | None = None) -> list[Path]:
    """Record `sweeps` sweeps of every texture (under every movement); deterministic.

    Each sweep draws from its own seed (scene seed, texture, sweep number, and the
    movement's name), so the bags are the same whatever the number of workers, the order
    sweeps finish in, and the order of the movement file. Trial numbers run over
    movements, then textures, then sweeps, so they stay unique across movements.

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
        movements: sweep every texture under each of these (None: the scene's sweep).

    Raises:
        SceneError: the scene, or a movement in it, cannot slide in contact over a patch
            (`check_collectable`, `movement_scene`).
        SimError: a sweep is unreachable or never touched the patch.
        ClusterError: Ray cannot be started or reached.
    """
    scenes = collectable_scenes(scene, movements)
    out.mkdir(parents=True, exist_ok=True)
    per_movement = len(textures) * sweeps
    jobs = [(movement, name, movement_index * per_movement + texture_index * sweeps + sweep,
             np.random.SeedSequence([scene.seed, TEXTURES_INDEX[name], sweep,
                                     *([zlib.crc32(movement.encode())] if movement else [])]))
            for movement_index, movement in enumerate(scenes)
            for texture_index, name in enumerate(textures) for sweep in range(sweeps)]
    paths: dict[int, Path] = {}
    start = time.monotonic()

    def finished(index: int, path: Path) -> None:
        paths[index] = path
        eta = (time.monotonic() - start) / len(paths) * (len(jobs) - len(paths))
        progress(f'[{len(paths)}/{len(jobs)}] {path.name}  (about {eta:.0f} s left)')

    if (workers or 1) == 1 and address is None:
        for index, (movement, name, trial, sequence) in enumerate(jobs):
            finished(index, record_sweep(scenes[movement], name, trial, out, sequence,
                                         movement))
    else:
        def write(index: int, result: tuple[str, dict[str, bytes]]) -> None:
            folder = out / result[0]
            for relative, content in result[1].items():
                (folder / relative).parent.mkdir(parents=True, exist_ok=True)
                (folder / relative).write_bytes(content)
            finished(index, folder)

        with ray_session(address=address, cpus=None if address else workers):
            run_tasks(recorded_sweep, jobs, shared=(scenes,), on_result=write,
                      max_in_flight=workers if address else None)
    return [paths[index] for index in range(len(jobs))]


def collectable_scenes(scene: Scene, movements: MovementSet | None = None) -> dict[str, Scene]:
    """Each movement's name and scene ('' and the scene itself without movements), checked.

    Raises:
        SceneError: as `check_collectable` and `movement_scene`, naming the movement.
    """
    check_collectable(scene)
    if movements is None:
        return {'': scene}
    scenes = {movement.name: movement_scene(scene, movement) for movement in movements.movements}
    for name, each in scenes.items():
        try:
            check_collectable(each)
            for parameters in (SweepParameters.nominal(each), *SweepParameters.extremes(each)):
                plan_sweep(each, parameters)
        except SimError as err:
            raise SceneError(f'movement {name}: {err}; lower its edge_tilt or press_depth, or '
                             'shorten its contact_length') from None
    return scenes


TEXTURES_INDEX = {name: index for index, name in enumerate(TEXTURES)}
