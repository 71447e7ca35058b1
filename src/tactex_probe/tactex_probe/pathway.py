# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The pathway record: the probing parameters, every probe's outcome, and its JSON file.

This is the stable interface between probing and sweeping: the probe node writes a
`Pathway` as JSON, the sweep reads it back with `Pathway.load`. Positions and normals are
in `base_link` (REP-105), in metres (REP-103); stamps are int nanoseconds.

File format (version 1), one JSON object::

    {"format": "tactex-pathway", "version": 1, "frame_id": "base_link",
     "stamp_ns": 12000000000,                # when probing finished
     "parameters": {"start": [x, y, z], "direction": [dx, dy, dz], "span": 0.12,
                    "step": 0.01, "approach_height": 0.02, "descent_speed": 0.005,
                    "max_descent_depth": 0.02, "force_limit": 3.0},
     "probes": [{"index": 0, "status": "ok", "stamp_ns": 3100000000,
                 "position": [x, y, z], "normal": [nx, ny, nz],
                 "force_proxy": 1.5, "confidence": 0.93, "detail": ""}, ...]}

`probes` holds one entry per probe point, in probing order, failures included (their
`status` says why; `normal` is zero and `confidence` 0); a goal that was canceled or
aborted leaves out the points it never finished. `status` is the lower-case name of
a `ContactStatus`, whose values are the tactex_msgs/Contact STATUS_* codes. Readers should
use `Pathway.contacts` (the successful probes) for a sweep.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import asdict, dataclass, fields
import enum
import json
import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from tactex_common import frames
from tactex_common.files import load_json
from tactex_common.numbers import is_finite_number
from tactex_probe.errors import ParameterError, PathwayError

FORMAT = 'tactex-pathway'
VERSION = 1
FRAME_ID = frames.BASE
# A unit vector may be off by this much in length (JSON round trips keep 17 digits).
UNIT_TOLERANCE = 1e-6
MAX_PATHWAY_BYTES = 16 * 1024**2
MAX_PATHWAY_DEPTH = 16

Vector3 = tuple[float, float, float]


class ContactStatus(enum.IntEnum):
    """Outcome of one probe; the values are tactex_msgs/Contact's STATUS_* codes."""

    OK = 0  # contact found; position, normal and force proxy are valid
    NO_CONTACT = 1  # descended max_descent_depth below the probe point without contact
    OVER_FORCE = 2  # the force limit was reached before a clean measurement
    UNREACHABLE = 3  # the approach or descent pose cannot be reached (IK, limits, blocked)
    ESTIMATION_FAILED = 4  # contact found, but the normal could not be estimated


@dataclass(frozen=True)
class ParameterRange:
    """Allowed values of one probing parameter: low < value <= high (or low <= value)."""

    low: float
    high: float
    unit: str
    description: str
    low_inclusive: bool = False

    def contains(self, value: float) -> bool:
        """True when `value` is finite and within the range."""
        above = value >= self.low if self.low_inclusive else value > self.low
        return math.isfinite(value) and above and value <= self.high


# The one table of the scalar probing parameters, used by the pathway, the explorer
# and the node's parameter descriptors.
PARAMETER_RANGES: dict[str, ParameterRange] = {
    'span': ParameterRange(0.0, 0.5, 'm', 'distance from the first to the last probe point',
                           low_inclusive=True),
    'step': ParameterRange(0.001, 0.1, 'm', 'spacing of the probe points'),
    'approach_height': ParameterRange(0.003, 0.1, 'm',
                                      'height above a probe point where its descent starts'),
    'descent_speed': ParameterRange(0.0, 0.05, 'm/s', 'speed of the descent'),
    'max_descent_depth': ParameterRange(0.0, 0.1, 'm',
                                        'deepest descent below a probe point before giving up'),
    'force_limit': ParameterRange(0.0, 20.0, 'N', 'force proxy at which a descent stops'),
}


def _vector(value: Any, name: str) -> Vector3:
    try:
        vector = tuple(float(v) for v in value)
    except (TypeError, ValueError):
        raise ParameterError(f'{name} must be 3 numbers, got {value!r}') from None
    except OverflowError:  # a whole number past the float range
        raise ParameterError(f'{name} must be 3 finite numbers, got {value!r}') from None
    if len(vector) != 3 or not all(math.isfinite(v) for v in vector):
        raise ParameterError(f'{name} must be 3 finite numbers, got {value!r}')
    return vector


def _unit_length(vector: Vector3) -> float:
    return math.sqrt(sum(v * v for v in vector))


# The probe node's own goal (probe_on_start): the uneven plate in front of the arm.
DEFAULT_GOAL = dict(start=[0.10, 0.0, 0.018], direction=[1.0, 0.0, 0.0], span=0.10, step=0.01,
                    approach_height=0.02, descent_speed=0.005, max_descent_depth=0.025,
                    force_limit=3.0)


@dataclass(frozen=True)
class ProbeParameters:
    """Where and how to probe (tactex_msgs/action/Probe's goal; SI units, base_link).

    Probe point i is `start + i * step * direction` for i = 0 .. floor(span / step). Above
    each point the sensor stops `approach_height` higher, then descends along -z at
    `descent_speed` until contact, until it is `max_descent_depth` below the point, or until
    the force proxy reaches `force_limit`.

    Raises:
        ParameterError: a value is not finite, out of its range (`PARAMETER_RANGES`), or
            `direction` is not a unit vector.
    """

    start: Vector3
    direction: Vector3
    span: float
    step: float
    approach_height: float
    descent_speed: float
    max_descent_depth: float
    force_limit: float

    def __post_init__(self) -> None:
        """Check every value (and store vectors as float tuples)."""
        object.__setattr__(self, 'start', _vector(self.start, 'start'))
        object.__setattr__(self, 'direction', _vector(self.direction, 'direction'))
        length = _unit_length(self.direction)
        if abs(length - 1.0) > UNIT_TOLERANCE:
            raise ParameterError(f'direction must be a unit vector, got {self.direction!r} '
                                 f'(length {length:.6g})')
        for name, allowed in PARAMETER_RANGES.items():
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ParameterError(f'{name} must be a number, got {value!r}')
            if not (is_finite_number(value) and allowed.contains(float(value))):
                bracket = '[' if allowed.low_inclusive else '('
                raise ParameterError(
                    f'{name} must be in {bracket}{allowed.low:g}, {allowed.high:g}] '
                    f'{allowed.unit} ({allowed.description}), got {value!r}')
            object.__setattr__(self, name, float(value))

    @property
    def probe_count(self) -> int:
        """Number of probe points (the first and every `step` up to `span`)."""
        return int(math.floor(self.span / self.step + 1e-9)) + 1

    def probe_point(self, index: int) -> np.ndarray:
        """Probe point `index` (m, base_link)."""
        if not 0 <= index < self.probe_count:
            raise IndexError(f'probe index {index} outside 0..{self.probe_count - 1}')
        return np.asarray(self.start) + index * self.step * np.asarray(self.direction)

    def to_dict(self) -> dict[str, Any]:
        """Plain values (lists for vectors), as the file stores them."""
        values = asdict(self)
        values['start'], values['direction'] = list(self.start), list(self.direction)
        return values


@dataclass(frozen=True)
class ProbeRecord:
    """Outcome of one probe (tactex_msgs/Contact plus the probe index and a reason).

    Attributes:
        index: probe point index, 0-based.
        status: the outcome.
        stamp_ns: instant of first contact; for a failed probe, when it ended (ns).
        position: contact point on the surface (m, base_link); for NO_CONTACT and
            OVER_FORCE the deepest point the sensor reached, for UNREACHABLE the probe point.
        normal: outward unit surface normal at `position` (base_link); zero unless OK.
        force_proxy: contact force proxy (N): body compression times its stiffness.
        confidence: 0 (none) to 1 (certain); 0 unless OK.
        detail: why the probe failed or how it was measured (human-readable).
    """

    index: int
    status: ContactStatus
    stamp_ns: int
    position: Vector3
    normal: Vector3
    force_proxy: float
    confidence: float
    detail: str = ''

    def __post_init__(self) -> None:
        """Check the record's invariants (see the class docstring)."""
        object.__setattr__(self, 'status', ContactStatus(self.status))
        object.__setattr__(self, 'position', _vector(self.position, 'position'))
        object.__setattr__(self, 'normal', _vector(self.normal, 'normal'))
        if isinstance(self.index, bool) or not isinstance(self.index, int) or self.index < 0:
            raise ParameterError(f'index must be an integer >= 0, got {self.index!r}')
        if isinstance(self.stamp_ns, bool) or not isinstance(self.stamp_ns, int):
            raise ParameterError(f'stamp_ns must be an integer, got {self.stamp_ns!r}')
        for name in ('force_proxy', 'confidence'):
            value = getattr(self, name)
            if not is_finite_number(value):
                raise ParameterError(f'{name} must be a finite number, got {value!r}')
        if self.status is ContactStatus.OK:
            if abs(_unit_length(self.normal) - 1.0) > UNIT_TOLERANCE:
                raise ParameterError(f'an OK contact needs a unit normal, got {self.normal!r}')
            if not 0.0 <= self.confidence <= 1.0:
                raise ParameterError(f'confidence must be in [0, 1], got {self.confidence!r}')
        elif any(self.normal) or self.confidence != 0.0:
            raise ParameterError(f'a {self.status.name} probe has a zero normal and confidence '
                                 f'0, got {self.normal!r} and {self.confidence!r}')

    @property
    def ok(self) -> bool:
        """True for a successful contact."""
        return self.status is ContactStatus.OK

    def to_dict(self) -> dict[str, Any]:
        """Plain values, as the file stores them."""
        return {'index': self.index, 'status': self.status.name.lower(),
                'stamp_ns': self.stamp_ns, 'position': list(self.position),
                'normal': list(self.normal), 'force_proxy': self.force_proxy,
                'confidence': self.confidence, 'detail': self.detail}


@dataclass(frozen=True)
class Pathway:
    """The result of probing: parameters and every probe's record, in probing order."""

    parameters: ProbeParameters
    probes: tuple[ProbeRecord, ...]
    stamp_ns: int
    frame_id: str = FRAME_ID

    def __post_init__(self) -> None:
        """Records are in increasing index order, one per point, within the probe count."""
        object.__setattr__(self, 'probes', tuple(self.probes))
        indices = [p.index for p in self.probes]
        if any(b <= a for a, b in zip(indices[:-1], indices[1:], strict=True)):
            raise ParameterError(f'probe indices must increase, one per point, got {indices}')
        if indices and indices[-1] >= self.parameters.probe_count:
            raise ParameterError(f'probe index {indices[-1]} but the parameters define only '
                                 f'{self.parameters.probe_count} probe points')
        if self.frame_id != FRAME_ID:
            raise ParameterError(f'frame_id must be {FRAME_ID!r}, got {self.frame_id!r}')

    @property
    def contacts(self) -> tuple[ProbeRecord, ...]:
        """The successful probes, in order: what a sweep slides along."""
        return tuple(p for p in self.probes if p.ok)

    @property
    def outcomes(self) -> tuple[ContactStatus, ...]:
        """Status of every probe, in order."""
        return tuple(p.status for p in self.probes)

    def to_dict(self) -> dict[str, Any]:
        """The file's JSON object."""
        return {'format': FORMAT, 'version': VERSION, 'frame_id': self.frame_id,
                'stamp_ns': self.stamp_ns, 'parameters': self.parameters.to_dict(),
                'probes': [p.to_dict() for p in self.probes]}

    @classmethod
    def from_dict(cls, data: Any, source: str = '<pathway>') -> Pathway:
        """Validate and build a pathway from the file's JSON object.

        Raises:
            PathwayError: wrong format or version, a missing or unknown key, a bad value
                (the message names `source` and the key).
        """
        _expect_keys(data, {'format', 'version', 'frame_id', 'stamp_ns', 'parameters',
                            'probes'}, source, 'top level')
        if data['format'] != FORMAT or data['version'] != VERSION:
            raise PathwayError(f'{source}: not a {FORMAT} file of version {VERSION} '
                               f'(format {data["format"]!r}, version {data["version"]!r})')
        names = {f.name for f in fields(ProbeParameters)}
        _expect_keys(data['parameters'], names, source, 'parameters')
        if not isinstance(data['probes'], list):
            raise PathwayError(f'{source}: probes must be a list, got {data["probes"]!r}')
        try:
            parameters = ProbeParameters(**data['parameters'])
            probes = []
            for i, entry in enumerate(data['probes']):
                _expect_keys(entry, {f.name for f in fields(ProbeRecord)}, source,
                             f'probes[{i}]')
                probes.append(ProbeRecord(**{**entry, 'status': _status(entry['status'])}))
            return cls(parameters, tuple(probes), data['stamp_ns'], data['frame_id'])
        except ParameterError as err:
            raise PathwayError(f'{source}: {err}') from None

    def save(self, path: Path | str) -> Path:
        """Write the JSON file atomically (a reader never sees half a file); return its path."""
        path = Path(path)
        temporary = path.with_name(f'.{path.name}.tmp')
        temporary.write_text(json.dumps(self.to_dict(), indent=1) + '\n', encoding='utf-8')
        os.replace(temporary, path)
        return path

    @classmethod
    def load(cls, path: Path | str) -> Pathway:
        """Read a pathway file written by `save`.

        Raises:
            PathwayError: the file is missing, not JSON, or not a valid pathway.
        """
        path = Path(path)
        try:
            data = load_json(path, max_bytes=MAX_PATHWAY_BYTES, max_depth=MAX_PATHWAY_DEPTH)
        except FileNotFoundError:
            raise PathwayError(f'no pathway file {str(path)!r}') from None
        except (OSError, UnicodeDecodeError, json.JSONDecodeError) as err:
            raise PathwayError(f'{path}: not a readable JSON file: {err}') from None
        return cls.from_dict(data, str(path))


def _status(name: Any) -> ContactStatus:
    if not isinstance(name, str) or name.upper() not in ContactStatus.__members__:
        known = ', '.join(s.name.lower() for s in ContactStatus)
        raise ParameterError(f'status must be one of {known}, got {name!r}')
    return ContactStatus[name.upper()]


def _expect_keys(table: Any, expected: set[str], source: str, where: str) -> None:
    if not isinstance(table, Mapping):
        raise PathwayError(f'{source}: {where} must be an object, got {table!r}')
    missing, unknown = sorted(expected - set(table)), sorted(set(table) - expected)
    if missing or unknown:
        found = '; '.join(part for part in (f'missing key(s) {missing}' if missing else '',
                                            f'unknown key(s) {unknown}' if unknown else '')
                          if part)
        raise PathwayError(f'{source}: {where}: {found}; expected {sorted(expected)}')
