# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Scene files (TOML under config/scenes/): surface, texture patches, rate, seed, effects.

Every key is checked: an unknown key, a missing required one or a bad value raises
`SceneError` naming the file, the section and the key, with the keys that are known.
Every number that sizes memory or time (heightfield cells, contact time, physics step,
patches) is bounded, and the file is read only if it is a regular file of at most
`MAX_SCENE_BYTES`.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields, MISSING
import math
from pathlib import Path
import tomllib
from typing import Any

import numpy as np

from tactex_common.constants import MAX_SEED, SLIDING_SPEED_M_S
from tactex_common.errors import RefusedFileError
from tactex_common.files import read_bytes
from tactex_common.numbers import is_finite_number
from tactex_description.speed_ramp import RAMP_ACCELERATION_M_S2
from tactex_sim.errors import SceneError

MAX_SCENE_BYTES = 1024 * 1024
MAX_HEIGHTFIELD_CELLS = 1_000_000  # cells[0] x cells[1]
MAX_CONTACT_S = 60.0
MAX_PATCHES = 64
TIMESTEP_RANGE_S = (1e-4, 0.02)


@dataclass(frozen=True)
class Surface:
    """The plate under the arm: flat, or the concave-convex wave of the original.

    A flat plate may be tilted: its top face rises along +x at `slope_rad`, turned about
    the y axis through the top face's centre (probing steep slopes).
    """

    kind: str = 'flat'
    size_m: tuple[float, float] = (0.30, 0.20)
    origin_m: tuple[float, float, float] = (0.20, 0.0, 0.0)
    amplitude_m: float = 0.0
    wavelength_m: float = 0.12
    thickness_m: float = 0.01
    cells: tuple[int, int] = (1201, 2)
    slope_rad: float = 0.0

    def height(self, x_world):
        """Surface height (m, world z) at world x (the top face for a flat plate)."""
        local = np.asarray(x_world, dtype=float) - self.origin_m[0]
        if self.kind == 'flat':
            return self.top_z + math.tan(self.slope_rad) * local
        wave = np.cos(2.0 * math.pi * local / self.wavelength_m)
        return self.top_z + self.amplitude_m * wave

    def slope(self, x_world):
        """Slope d(height)/dx at world x."""
        if self.kind == 'flat':
            return np.full_like(np.asarray(x_world, dtype=float), math.tan(self.slope_rad))
        local = np.asarray(x_world, dtype=float) - self.origin_m[0]
        k = 2.0 * math.pi / self.wavelength_m
        return -self.amplitude_m * k * np.sin(k * local)

    def normal(self, x_world: float) -> np.ndarray:
        """Outward unit normal (x, z) of the surface at world x (it has no y slope)."""
        slope = float(self.slope(x_world))
        return np.array([-slope, 1.0]) / math.hypot(slope, 1.0)

    @property
    def top_z(self) -> float:
        """World z of the mean top face (the wave oscillates around it)."""
        wave = self.amplitude_m if self.kind == 'uneven' else 0.0
        return self.origin_m[2] + self.thickness_m + wave


@dataclass(frozen=True)
class Patch:
    """A texture on a rectangle of the surface (world x and y ranges, m)."""

    texture: str
    x_m: tuple[float, float]
    y_m: tuple[float, float]

    def contains(self, x: float, y: float) -> bool:
        """True when (x, y) lies on the patch."""
        return self.x_m[0] <= x <= self.x_m[1] and self.y_m[0] <= y <= self.y_m[1]


PRESS_REFERENCES = ('centre', 'rim')  # what a sweep's press depth indents


@dataclass(frozen=True)
class Sweep:
    """The scripted sweep: sliding speed, contact duration, edge offset, start, direction.

    `press` says what [variability] press_depth_m indents into the surface: 'centre', the
    edge's centre (the scenes' own sweeps, as laid out), or 'rim', its rim, as a Sweep
    goal and a movement file mean it (`tactex sim collect --movements` sweeps so, to
    press as the arm does under the same movement). `ramp_acceleration_m_s2` is the
    peak acceleration of cosine speed ramps before and after the contact, as the Sweep
    action slides (`tactex_description.speed_ramp`); infinite (the default, the scenes'
    own sweeps) starts and stops at full speed.
    """

    speed_m_s: float = SLIDING_SPEED_M_S
    contact_s: float = 7.6
    edge_offset_rad: float = 0.35
    start_x_m: float = 0.13
    direction: int = 1  # +1 slides towards +x from start_x_m, -1 towards -x
    press: str = 'centre'
    ramp_acceleration_m_s2: float = math.inf

    def __post_init__(self) -> None:
        """Refuse a press that is neither 'centre' nor 'rim', or a ramp acceleration <= 0.

        Raises:
            ValueError: naming the value.
        """
        if self.press not in PRESS_REFERENCES:
            raise ValueError(f'press must be "centre" or "rim" (what press_depth_m indents), '
                             f'got {self.press!r}')
        if not self.ramp_acceleration_m_s2 > 0:
            raise ValueError(f'ramp_acceleration_m_s2 must be > 0 m/s^2 (the Sweep action '
                             f'ramps at {RAMP_ACCELERATION_M_S2:g}), got '
                             f'{self.ramp_acceleration_m_s2!r}')



@dataclass(frozen=True)
class Variability:
    """Sweep-to-sweep variation, each a standard deviation unless the name says otherwise."""

    press_depth_m: tuple[float, float] = (0.0015, 0.0004)
    speed_fraction: float = 0.05
    start_x_m: float = 0.01
    heading_rad: float = 0.35
    mount_tilt_rad: float = 0.03
    noise_scale: float = 0.15
    drift_pa_per_s: float = 2.0


@dataclass(frozen=True)
class Scene:
    """A whole scene."""

    name: str
    seed: int
    sensor_rate_hz: float
    timestep_s: float
    effects: tuple[str, ...]
    surface: Surface
    patches: tuple[Patch, ...] = ()
    sweep: Sweep = Sweep()
    variability: Variability = Variability()
    effect_options: dict[str, dict[str, Any]] = field(default_factory=dict)
    path: str = ''


_TOP_KEYS = {'name', 'seed', 'sensor_rate_hz', 'timestep_s', 'effects', 'surface', 'patches',
             'sweep', 'variability', 'effect'}


def resolve_scene(name: str) -> Path:
    """A scene given by name (config/scenes/NAME.toml of the workspace) or by path."""
    from tactex_common.share import share_directory
    if name.endswith('.toml') or '/' in name:
        return Path(name)
    return share_directory('tactex') / 'config' / 'scenes' / f'{name}.toml'


def load_scene(path: Path | str) -> Scene:
    """Read and validate a scene file.

    Raises:
        SceneError: the file is missing, not TOML, or breaks a rule (the message says which).
    """
    path = Path(path)
    try:
        raw = tomllib.loads(read_bytes(path, max_bytes=MAX_SCENE_BYTES).decode('utf-8'))
    except FileNotFoundError:
        known = sorted(p.stem for p in path.parent.glob('*.toml')) if path.parent.is_dir() \
            else []
        raise SceneError(f'no scene file {str(path)!r}' + (
            f'; scenes there: {", ".join(known)}' if known else '')) from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise SceneError(f'{path}: not valid TOML: {err}') from None
    except RecursionError:
        raise SceneError(f'{path}: nested too deep to be a scene') from None
    except RefusedFileError as err:
        raise SceneError(f'scene {err}') from None
    except OSError as err:
        raise SceneError(f'{path}: cannot read: {err.strerror}') from None
    return parse_scene(raw, str(path))


def parse_scene(raw: dict[str, Any], source: str = '<scene>') -> Scene:
    """Validate a scene given as a dict (the parsed TOML)."""
    _check_keys(raw, _TOP_KEYS, source, 'top level')
    for key in ('name', 'seed', 'effects', 'surface'):
        if key not in raw:
            raise SceneError(f'{source}: missing required key {key!r}')
    effects = raw['effects']
    if not isinstance(effects, list) or not all(isinstance(e, str) for e in effects):
        raise SceneError(f'{source}: effects must be a list of names, got {effects!r}')
    if len(set(effects)) != len(effects):
        raise SceneError(f'{source}: effects repeat: {effects!r}')
    seed = raw['seed']
    if not isinstance(seed, int) or isinstance(seed, bool) or not 0 <= seed <= MAX_SEED:
        raise SceneError(f'{source}: seed must be a whole number in 0..{MAX_SEED}, got '
                         f'{seed!r}')
    surface = _section(Surface, raw['surface'], source, 'surface')
    if surface.kind not in ('flat', 'uneven'):
        raise SceneError(f'{source}: [surface] kind must be "flat" or "uneven", got '
                         f'{surface.kind!r}')
    if min(surface.size_m) <= 0 or surface.wavelength_m <= 0 or surface.thickness_m <= 0 \
            or surface.amplitude_m < 0 or min(surface.cells) < 2:
        raise SceneError(f'{source}: [surface] sizes, wavelength and thickness must be > 0, '
                         f'amplitude >= 0 and cells >= 2')
    if math.prod(surface.cells) > MAX_HEIGHTFIELD_CELLS:
        raise SceneError(f'{source}: [surface] cells {list(surface.cells)} make '
                         f'{math.prod(surface.cells)} heightfield cells; at most '
                         f'{MAX_HEIGHTFIELD_CELLS} (e.g. [1201, 2], 0.25 mm along the wave)')
    if surface.slope_rad and (surface.kind != 'flat' or abs(surface.slope_rad) >= 1.4):
        raise SceneError(f'{source}: [surface] slope_rad tilts a flat plate only, by less than '
                         f'1.4 rad, got {surface.slope_rad!r} on a {surface.kind!r} surface')
    if len(raw.get('patches', [])) > MAX_PATCHES:
        raise SceneError(f'{source}: {len(raw["patches"])} patches; at most {MAX_PATCHES}')
    patches = tuple(_section(Patch, p, source, f'patches[{i}]')
                    for i, p in enumerate(raw.get('patches', [])))
    for patch in patches:
        if len(patch.x_m) != 2 or len(patch.y_m) != 2:
            raise SceneError(f'{source}: patch {patch.texture!r}: x_m and y_m need 2 numbers')
        if patch.x_m[0] >= patch.x_m[1] or patch.y_m[0] >= patch.y_m[1]:
            raise SceneError(f'{source}: patch {patch.texture!r} has an empty rectangle')
    rate = _coerce(raw.get('sensor_rate_hz', 120.0), 0.0, source, 'top level', 'sensor_rate_hz')
    timestep = _coerce(raw.get('timestep_s', 0.002), 0.0, source, 'top level', 'timestep_s')
    if not (0 < rate <= 2000 and math.isfinite(rate)):
        raise SceneError(f'{source}: sensor_rate_hz must be in (0, 2000], got {rate!r}')
    if not (TIMESTEP_RANGE_S[0] <= timestep <= TIMESTEP_RANGE_S[1]):
        raise SceneError(f'{source}: timestep_s must be in {TIMESTEP_RANGE_S[0]:g}..'
                         f'{TIMESTEP_RANGE_S[1]:g} s, got {timestep!r}')
    if timestep > 1.0 / rate:
        raise SceneError(f'{source}: timestep_s {timestep} is longer than one sensor period '
                         f'{1.0 / rate:.4f} s')
    options = raw.get('effect', {})
    if not isinstance(options, dict):
        raise SceneError(f'{source}: [effect.NAME] tables expected, got {options!r}')
    for name in options:
        if name not in effects:
            raise SceneError(f'{source}: [effect.{name}] configures an effect the scene does '
                             f'not list in effects {effects!r}')
    sweep = _section(Sweep, raw.get('sweep', {}), source, 'sweep')
    if not sweep.contact_s <= MAX_CONTACT_S:
        raise SceneError(f'{source}: [sweep] contact_s must be <= {MAX_CONTACT_S:g} s, got '
                         f'{sweep.contact_s!r}')
    return Scene(name=str(raw['name']), seed=seed, sensor_rate_hz=rate, timestep_s=timestep,
                 effects=tuple(effects), surface=surface, patches=patches, sweep=sweep,
                 variability=_section(Variability, raw.get('variability', {}), source,
                                      'variability'),
                 effect_options={k: dict(v) for k, v in options.items()}, path=source)


def _check_keys(table: dict, known: set[str], source: str, section: str) -> None:
    if not isinstance(table, dict):
        raise SceneError(f'{source}: [{section}] must be a table, got {table!r}')
    unknown = sorted(set(table) - known)
    if unknown:
        raise SceneError(f'{source}: unknown key(s) {", ".join(map(repr, unknown))} in '
                         f'[{section}]; known: {", ".join(sorted(known))}')


def _section(cls, table: dict, source: str, section: str):
    known = {f.name for f in fields(cls)}
    _check_keys(table, known, source, section)
    values = {}
    for item in fields(cls):
        if item.name in table:
            default = None if item.default is MISSING else item.default
            values[item.name] = _coerce(table[item.name], default, source, section, item.name)
    try:
        return cls(**values)
    except (TypeError, ValueError) as err:
        raise SceneError(f'{source}: [{section}] {err}') from None


def _coerce(value, default, source: str, section: str, key: str):
    where = f'{source}: [{section}] {key}'
    if isinstance(default, tuple) or isinstance(value, list):
        if not isinstance(value, list) or (isinstance(default, tuple)
                                           and len(value) != len(default)):
            size = len(default) if isinstance(default, tuple) else 'a'
            raise SceneError(f'{where} must be a list of {size} numbers, got {value!r}')
        if not all(is_finite_number(v) for v in value):
            raise SceneError(f'{where} must hold finite numbers, got {value!r}')
        cast = int if default and isinstance(default[0], int) else float
        return tuple(cast(v) for v in value)
    if isinstance(default, str) or (default is None and isinstance(value, str)):
        if not isinstance(value, str):
            raise SceneError(f'{where} must be text, got {value!r}')
        return value
    if not is_finite_number(value):
        raise SceneError(f'{where} must be a finite number, got {value!r}')
    return float(value)
