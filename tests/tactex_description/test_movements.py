# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Movement files: the shipped candidates fit the arm, and every malformed file is refused.

A movement names a speed, a press depth, an edge tilt, a direction and a contact length;
the loader holds each to the arm's and the sensor's limits and, given the sensor's rate,
refuses a contact too short for one window, each with the file, the movement and the key.
"""

import math
from pathlib import Path

import pytest

from tactex_description.geometry import PRESS_TRAVEL_M
from tactex_description.movements import (
    load_movements,
    MIN_PRESS_DEPTH_M,
    MovementError,
    SPEED_RANGE_M_S,
)

SHIPPED = Path(__file__).resolve().parents[2] / 'config' / 'movements.yaml'
GOOD = {'name': 'probe_me', 'speed': 0.02, 'press_depth': 0.002, 'edge_tilt': 0.5,
        'direction': 'forward', 'contact_length': 0.05}


def written(tmp_path, text: str) -> Path:
    path = tmp_path / 'movements.yaml'
    path.write_text(text)
    return path


def one(tmp_path, window: int | None = None, **changes) -> Path:
    fields = ', '.join(f'{key}: {value}' for key, value in {**GOOD, **changes}.items())
    return written(tmp_path, (f'window: {window}\n' if window else '')
                   + f'movements:\n  - {{{fields}}}\n')


def test_the_shipped_movements_span_the_arm_and_each_holds_three_windows_at_120_hz():
    movements = load_movements(SHIPPED, sample_rate_hz=120.0)
    assert 6 <= len(movements.movements) <= 12 and movements.window == 128
    speeds = sorted({m.speed_m_s for m in movements.movements})
    assert speeds[0] <= 0.010 and speeds[-1] >= 0.040
    assert {m.direction for m in movements.movements} == {'forward', 'backward'}
    assert len({m.press_depth_m for m in movements.movements}) >= 3
    assert len({m.edge_tilt_rad for m in movements.movements}) >= 3
    for movement in movements.movements:
        samples = movement.contact_s * 120.0
        assert 1 + (samples - 128) // 64 >= 3, movement.name
        assert movement.press_depth_m >= MIN_PRESS_DEPTH_M
    assert movements.by_name('default').speed_m_s == 0.015


def test_a_movement_is_looked_up_by_name_and_an_unknown_name_lists_the_known():
    movements = load_movements(SHIPPED)
    with pytest.raises(MovementError, match="unknown movement 'sprint'; known: slow_light, "):
        movements.by_name('sprint')


@pytest.mark.parametrize('key, value, match', [
    ('speed', 0.2, r'speed must be a number in \[0.005, 0.05\] m/s'),
    ('speed', 0.0, 'speed must be'),
    ('speed', '.nan', 'speed must be'),
    ('speed', 'true', 'speed must be'),
    ('press_depth', 0.001, r'press_depth must be a number in \[0.0015, '),
    ('press_depth', PRESS_TRAVEL_M, 'press_depth must be'),
    ('edge_tilt', math.pi / 2, 'edge_tilt must be'),
    ('edge_tilt', -0.1, 'edge_tilt must be'),
    ('contact_length', 0.0, 'contact_length must be'),
    ('direction', 'sideways', 'direction must be one of forward, backward'),
    ('name', '1st', 'name must start with a letter'),
    ('name', "'a b'", 'name must start with a letter'),
])
def test_a_movement_outside_the_arms_limits_is_refused_naming_it_and_the_key(
        tmp_path, key, value, match):
    with pytest.raises(MovementError, match=f'movement 1.*: {match}'):
        load_movements(one(tmp_path, **{key: value}))


def test_the_limits_are_the_arms():
    assert SPEED_RANGE_M_S == (0.005, 0.05)
    assert MIN_PRESS_DEPTH_M == 0.0015 and PRESS_TRAVEL_M == pytest.approx(0.006)


@pytest.mark.parametrize('text, match', [
    ('', 'no movements'),
    ('movements: []\n', 'no movements'),
    ('movements: 3\n', 'no movements'),
    ('- a\n- b\n', 'no movements'),
    ('movements:\n  - [1, 2]\n', 'a movement is a mapping'),
    ('movements:\n  - {name: a, sped: 0.02}\n', 'unknown keys sped; missing speed'),
    ('windows: 64\nmovements:\n  - {name: a}\n', 'unknown top-level keys windows'),
    ('movements: [\n', 'not a YAML movement file'),
])
def test_empty_or_malformed_files_are_refused(tmp_path, text, match):
    with pytest.raises(MovementError, match=match):
        load_movements(written(tmp_path, text))


def test_repeated_names_and_too_many_movements_are_refused(tmp_path):
    row = '  - {' + ', '.join(f'{k}: {v}' for k, v in GOOD.items()) + '}\n'
    with pytest.raises(MovementError, match='movement names repeat: probe_me'):
        load_movements(written(tmp_path, 'movements:\n' + row * 2))
    with pytest.raises(MovementError, match='33 movements; at most 32'):
        load_movements(written(tmp_path, 'movements:\n' + row * 33))


def test_a_contact_too_short_for_one_window_is_refused_at_the_sensors_rate(tmp_path):
    # 20 mm at 40 mm/s: 0.5 s, 60 samples at 120 Hz.
    short = one(tmp_path, speed=0.04, contact_length=0.02)
    with pytest.raises(MovementError, match=r'probe_me: its contact \(0.50 s, 60 samples at '
                                            '120 Hz\\) is too short for one window of 128'):
        load_movements(short, sample_rate_hz=120.0)
    assert load_movements(short, sample_rate_hz=350.0).movements[0].contact_s == 0.5
    assert load_movements(one(tmp_path, window=32, speed=0.04, contact_length=0.02),
                          sample_rate_hz=120.0).window == 32
    with pytest.raises(MovementError, match='window must be an integer'):
        load_movements(one(tmp_path, window=4))


def test_a_movement_set_written_as_a_file_reads_back_unchanged(tmp_path):
    from tactex_description.movements import movements_yaml
    shipped = load_movements(SHIPPED)
    assert load_movements(written(tmp_path, movements_yaml(shipped))) == shipped
