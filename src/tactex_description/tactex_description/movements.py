# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Candidate movements of the sensor edge on a pathway, read from a file and held to the arm.

A movement is one way to sweep: the edge's sliding speed, its press depth into the
surface, its tilt from the normal (the sweep's edge offset angle), the direction along
the pathway and how much of the pathway it covers in contact. Active identification
chooses among them; `tactex sim collect --movements` records every texture under each.
The file (config/movements.yaml, SI units):

    window: 128            # samples each movement's sweeps are classified in
    movements:
      - {name: slow_light, speed: 0.010, press_depth: 0.0015, edge_tilt: 0.35,
         direction: forward, contact_length: 0.04}

Limits held here, so that no listed movement asks the arm or the sensor for what it
cannot do: a press of at least MIN_PRESS_DEPTH_M (the sweep's default; shallower presses
lose contact on the uneven plate's crests) and less than the compliant body's travel
(`geometry.PRESS_TRAVEL_M`), a tilt in [0, pi/2) as the sweep's poses accept, a speed in
SPEED_RANGE_M_S, and a contact that holds at least one window at the sensor's rate.

The file is read strictly (`MovementLoader`): no anchors or aliases (a few hundred bytes of
nested aliases expand to gigabytes), no repeated keys (PyYAML keeps the last silently),
and numbers as YAML 1.2 writes them (`1e-2` is a number, not the text PyYAML 1.1 makes
of it). Every value echoed in an error is cut to ECHO_CHARS.
"""

from __future__ import annotations

from dataclasses import dataclass
import math
from pathlib import Path
import re
import reprlib

import yaml

from tactex_common.files import read_text
from tactex_common.numbers import is_finite_number
from tactex_description.geometry import PRESS_TRAVEL_M
from tactex_description.speed_ramp import ramp_length_m

MIN_PRESS_DEPTH_M = 0.0015
# At 50 mm/s the sweep's speed ramps (0.05 m/s^2) take 39 mm at each end of a pathway
# (the demo probes 100 mm); slower than 5 mm/s, three 128-sample windows at 120 Hz cover
# under 11 mm. In simulation the edge held 0.96-1.04 of the commanded speed in
# mid-contact from 10 to 40 mm/s (6 sweeps of each movement the shipped file then had).
SPEED_RANGE_M_S = (0.005, 0.05)
DIRECTIONS = ('forward', 'backward')
MAX_MOVEMENTS = 32
MAX_FILE_BYTES = 1024 * 1024
NAME = re.compile(r'^[A-Za-z][A-Za-z0-9_-]{0,63}\Z')  # \Z: no newline after the name
KEYS = ('name', 'speed', 'press_depth', 'edge_tilt', 'direction', 'contact_length')
ECHO_CHARS = 80  # the most of a value, or a YAML problem, an error message echoes
ECHO_NAMES = 8  # the most unknown keys an error message lists
# YAML 1.2's floats (core schema): a dot or an exponent, or .inf/.nan. YAML 1.1, which
# PyYAML follows, wants both a dot and a signed exponent, so reads `1e-2` as text.
YAML12_FLOAT = re.compile(r'^(?:[-+]?(?:[0-9]+\.[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?'
                          r'|[-+]?[0-9]+[eE][-+]?[0-9]+'
                          r'|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$')
_FLOAT_TAG = 'tag:yaml.org,2002:float'
_MERGE_TAG = 'tag:yaml.org,2002:merge'
_ECHO = reprlib.Repr()
_ECHO.maxstring = _ECHO.maxother = ECHO_CHARS


class MovementError(ValueError):
    """A movement file that cannot be used, with the file, the movement, the key and the fix."""


class RefusedYamlError(yaml.MarkedYAMLError):
    """YAML that parses but that a movement file does not take (an alias, a repeated key)."""


class MovementLoader(yaml.SafeLoader):
    """PyYAML's safe loader without anchors, aliases, merge keys or repeated keys.

    Floats are read as YAML 1.2 writes them (YAML12_FLOAT). Everything else resolves as
    `yaml.SafeLoader` resolves it.
    """

    yaml_implicit_resolvers = {
        first: [(tag, regexp) for tag, regexp in resolvers
                if tag not in (_FLOAT_TAG, _MERGE_TAG)]
        for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()}

    def compose_node(self, parent, index):
        """The next node; an anchor (&name) or an alias (*name) is refused where it stands.

        Raises:
            RefusedYamlError: at the anchor or alias, before any alias is expanded.
        """
        event = self.peek_event()
        if isinstance(event, yaml.AliasEvent) or getattr(event, 'anchor', None) is not None:
            raise RefusedYamlError(
                problem='a movement file takes no anchors or aliases (&name, *name): write '
                        'each value out', problem_mark=event.start_mark)
        return super().compose_node(parent, index)

    def construct_mapping(self, node, deep=False):
        """The mapping of `node`, refusing a key it holds twice.

        Raises:
            RefusedYamlError: at the key's second occurrence, naming it and the first line.
        """
        first_lines = {}
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)
            if isinstance(key, (str, int, float, bool)) or key is None:
                if key in first_lines:
                    raise RefusedYamlError(
                        problem=f'key {shown(key)} is given twice in one mapping (first on '
                                f'line {first_lines[key]}): keep one',
                        problem_mark=key_node.start_mark)
                first_lines[key] = key_node.start_mark.line + 1
        return super().construct_mapping(node, deep=deep)


MovementLoader.add_implicit_resolver(_FLOAT_TAG, YAML12_FLOAT, list('-+0123456789.'))


def shown(value) -> str:
    """`value`'s repr for an error message, at most ECHO_CHARS long however large it is."""
    return _cut(_ECHO.repr(value))


def _cut(text: str) -> str:
    return text if len(text) <= ECHO_CHARS else text[:ECHO_CHARS - 3] + '...'


def _listed(names) -> str:
    """Up to ECHO_NAMES of `names`, each cut, joined with commas (and how many more)."""
    names = [_cut(str(name)) for name in names]
    more = f' and {len(names) - ECHO_NAMES} more' if len(names) > ECHO_NAMES else ''
    return ', '.join(names[:ECHO_NAMES]) + more


def yaml_problem(err: yaml.YAMLError) -> str:
    """One line for a YAML error: where (line, column), what, and the construct it was in.

    PyYAML's own problems (which may quote the file) are cut to ECHO_CHARS; a
    `RefusedYamlError`'s is ours and bounded already.
    """
    if not isinstance(err, yaml.MarkedYAMLError):
        return _cut(' '.join(str(err).split()))
    mark = err.problem_mark or err.context_mark
    where = f'line {mark.line + 1}, column {mark.column + 1}: ' if mark else ''
    problem = ' '.join(str(err.problem).split())
    if not isinstance(err, RefusedYamlError):
        problem = _cut(problem)
    context = f' ({_cut(" ".join(err.context.split()))})' if err.context else ''
    return f'{where}{problem}{context}'


def parse_movement_yaml(text: str, path: Path | str):
    """The document of a movement file's `text`, read with `MovementLoader`.

    Raises:
        MovementError: not YAML, or YAML a movement file does not take, naming the line.
    """
    try:
        return yaml.load(text, Loader=MovementLoader)  # a SafeLoader: builds plain data only
    except RefusedYamlError as err:
        raise MovementError(f'{path}: {yaml_problem(err)}') from None
    except yaml.YAMLError as err:
        raise MovementError(f'{path}: not a YAML movement file: {yaml_problem(err)}; see '
                            'config/movements.yaml') from None


@dataclass(frozen=True)
class Movement:
    """One candidate movement.

    Attributes:
        name: how the movement is called in recordings, models and reports.
        speed_m_s: the edge's sliding speed.
        press_depth_m: the edge's commanded indentation along the normal.
        edge_tilt_rad: the sensor's tilt from the normal (the Sweep goal's edge_offset_angle).
        direction: 'forward' (along the pathway's order) or 'backward'.
        contact_length_m: the length of pathway slid along in contact.
    """

    name: str
    speed_m_s: float
    press_depth_m: float
    edge_tilt_rad: float
    direction: str
    contact_length_m: float

    @property
    def contact_s(self) -> float:
        """Seconds in contact at the sliding speed."""
        return self.contact_length_m / self.speed_m_s

    def part_length_m(self, ramp_acceleration_m_s2: float) -> float:
        """Path the movement slides along: its contact and a speed ramp at each end."""
        return self.contact_length_m + 2.0 * ramp_length_m(self.speed_m_s,
                                                           ramp_acceleration_m_s2)


@dataclass(frozen=True)
class MovementSet:
    """The candidate movements of one file and the window they are classified in."""

    movements: tuple[Movement, ...]
    window: int

    @property
    def names(self) -> tuple[str, ...]:
        """The movements' names, in the file's order."""
        return tuple(movement.name for movement in self.movements)

    def by_name(self, name: str) -> Movement:
        """The movement called `name`.

        Raises:
            MovementError: no movement has that name (the known ones are listed).
        """
        for movement in self.movements:
            if movement.name == name:
                return movement
        raise MovementError(f'unknown movement {shown(name)}; known: {", ".join(self.names)}')


def _number(raw: dict, key: str, where: str, low: float, high: float, unit: str,
            why: str) -> float:
    value = raw.get(key)
    if not is_finite_number(value) or not low <= value <= high:
        raise MovementError(f'{where}: {key} must be a number in [{low:g}, {high:g}] {unit} '
                            f'({why}), got {shown(value)}')
    return float(value)


def movement_from(raw, where: str) -> Movement:
    """One movement from its mapping in the file.

    Raises:
        MovementError: a missing or unknown key, or a value outside the arm's limits.
    """
    if not isinstance(raw, dict):
        raise MovementError(f'{where}: a movement is a mapping of {", ".join(KEYS)}, got '
                            f'{shown(raw)}')
    unknown = sorted(str(key) for key in set(raw) - set(KEYS))
    missing = [key for key in KEYS if key not in raw]
    if unknown or missing:
        raise MovementError(f'{where}: ' + '; '.join(
            part for part in (f'unknown keys {_listed(unknown)}' if unknown else '',
                              f'missing {", ".join(missing)}' if missing else '') if part)
            + f' (a movement has exactly {", ".join(KEYS)})')
    name = raw['name']
    if not isinstance(name, str) or not NAME.fullmatch(name):
        raise MovementError(f'{where}: name must start with a letter and hold only letters, '
                            f'digits, _ and - (at most 64), got {shown(name)}')
    where = f'{where} ({name})'
    if raw['direction'] not in DIRECTIONS:
        raise MovementError(f'{where}: direction must be one of {", ".join(DIRECTIONS)}, got '
                            f'{shown(raw["direction"])}')
    low_speed, high_speed = SPEED_RANGE_M_S
    return Movement(
        name=name,
        speed_m_s=_number(raw, 'speed', where, low_speed, high_speed, 'm/s',
                          "the arm's sliding speeds"),
        press_depth_m=_number(raw, 'press_depth', where, MIN_PRESS_DEPTH_M,
                              PRESS_TRAVEL_M - 1e-4, 'm', "the sweep's least press to the "
                              "compliant body's travel"),
        edge_tilt_rad=_number(raw, 'edge_tilt', where, 0.0, math.pi / 2 - 1e-3, 'rad',
                              'from the normal to lying flat'),
        direction=raw['direction'],
        contact_length_m=_number(raw, 'contact_length', where, 1e-3, 1.0, 'm',
                                 'of pathway slid along in contact'))


def load_movements(path: Path | str, *, sample_rate_hz: float | None = None,
                   unmeasured_s: float = 0.0) -> MovementSet:
    """The movement file at `path`, every movement checked against the arm's limits.

    Args:
        path: a movements YAML file.
        sample_rate_hz: the sensor's rate; given, each movement's contact must hold at
            least one window of the file's `window` samples after its first
            `unmeasured_s`.
        unmeasured_s: seconds at the start of a contact that a converter does not keep
            (`tactex_classify.data.dataset.FilterRule.slide_span_s`: the edge starts the
            contact from rest, and its speed, measured over that span, reaches the
            sliding threshold only that much later).

    Raises:
        MovementError: an unreadable file, no movements, repeated names, a value outside
            the limits or a contact too short for one window, naming each.
        RefusedFileError: not a regular file, or larger than MAX_FILE_BYTES.
    """
    try:
        text = read_text(path, max_bytes=MAX_FILE_BYTES)
    except UnicodeDecodeError as err:
        raise MovementError(f'{path}: not a YAML movement file ({err.reason} at byte '
                            f'{err.start}): save it as UTF-8 text') from None
    document = parse_movement_yaml(text, path)
    if not isinstance(document, dict) or not isinstance(document.get('movements'), list) \
            or not document['movements']:
        raise MovementError(f'{path}: no movements: the file needs a non-empty list '
                            '`movements:` (see config/movements.yaml)')
    unknown = sorted(str(key) for key in set(document) - {'movements', 'window'})
    if unknown:
        raise MovementError(f'{path}: unknown top-level keys {_listed(unknown)} (known: '
                            'movements, window)')
    window = document.get('window', 128)
    if isinstance(window, bool) or not isinstance(window, int) or not 8 <= window <= 4096:
        raise MovementError(f'{path}: window must be an integer of samples in [8, 4096], got '
                            f'{shown(window)}')
    raws = document['movements']
    if len(raws) > MAX_MOVEMENTS:
        raise MovementError(f'{path}: {len(raws)} movements; at most {MAX_MOVEMENTS}')
    movements = tuple(movement_from(raw, f'{path}: movement {index + 1}')
                      for index, raw in enumerate(raws))
    names = [movement.name for movement in movements]
    repeated = sorted({name for name in names if names.count(name) > 1})
    if repeated:
        raise MovementError(f'{path}: movement names repeat: {", ".join(repeated)}')
    if sample_rate_hz is not None:
        for movement in movements:
            samples = (movement.contact_s - unmeasured_s) * sample_rate_hz
            if samples < window:
                raise MovementError(
                    f'{path}: movement {movement.name}: its contact ({movement.contact_s:.2f} '
                    f's, {samples:.0f} samples at {sample_rate_hz:g} Hz'
                    f'{f" kept after the first {unmeasured_s:g} s" if unmeasured_s else ""}) '
                    f'is too short for one window of {window} samples: '
                    'lengthen contact_length, slow down, or lower window')
    return MovementSet(movements, window)


def movements_yaml(movements: MovementSet) -> str:
    """`movements` as a movement file (what `load_movements` reads back unchanged)."""
    return yaml.safe_dump({'window': movements.window, 'movements': [
        {'name': m.name, 'speed': m.speed_m_s, 'press_depth': m.press_depth_m,
         'edge_tilt': m.edge_tilt_rad, 'direction': m.direction,
         'contact_length': m.contact_length_m} for m in movements.movements]}, sort_keys=False)
