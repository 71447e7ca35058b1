# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Movement files: the shipped candidates fit the arm, and every malformed file is refused.

A movement names a speed, a press depth, an edge tilt, a direction and a contact length;
the loader holds each to the arm's and the sensor's limits and, given the sensor's rate,
refuses a contact too short for one window, each with the file, the movement and the key.
"""

import math
from pathlib import Path
import re

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
    # 30 mm/s: faster, a drawn sweep's part with both speed ramps runs out of the arm's
    # reach on the uneven scene (test_every_shipped_movement_is_collectable_...).
    assert speeds[0] <= 0.010 and speeds[-1] >= 0.030
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
    pytest.param('speed', '1' + '0' * 400, 'speed must be', id='speed-10**400'),  # past floats
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


def test_a_name_ending_in_a_newline_is_refused(tmp_path):
    with pytest.raises(MovementError, match=r"name must start with a letter.*got 'a\\n'"):
        load_movements(written(tmp_path, 'movements:\n  - ' + ', '.join(
            ['{name: "a\\n"'] + [f'{k}: {v}' for k, v in GOOD.items() if k != 'name']) + '}\n'))


def test_a_contact_must_hold_one_window_after_the_converters_unmeasured_start(tmp_path):
    from tactex.errors import CommandError
    from tactex.options import movement_file
    from tactex_classify.data.dataset import FilterRule
    # 5.4 mm at 5 mm/s: 1.08 s, 130 samples at 120 Hz, but the converter does not count
    # the first slide_span_s (0.1 s, 12 samples) as sliding: 118 are left, under 128.
    slowest = one(tmp_path, window=128, speed=0.005, contact_length=0.0054)
    assert load_movements(slowest, sample_rate_hz=120.0).window == 128
    with pytest.raises(MovementError, match=r'probe_me: its contact \(1.08 s, 118 samples at '
                                            r'120 Hz kept after the first 0.1 s\) is too short'):
        load_movements(slowest, sample_rate_hz=120.0, unmeasured_s=0.1)
    assert FilterRule().slide_span_s == 0.1
    with pytest.raises(CommandError, match='--movements .*118 samples at 120 Hz kept after '
                                           'the first 0.1 s'):
        movement_file(slowest, 120.0)
    assert movement_file(one(tmp_path, window=128, speed=0.005, contact_length=0.006),
                         120.0).window == 128  # 1.2 s: 132 samples after the start


def test_a_movement_set_written_as_a_file_reads_back_unchanged(tmp_path):
    from tactex_description.movements import movements_yaml
    shipped = load_movements(SHIPPED)
    assert load_movements(written(tmp_path, movements_yaml(shipped))) == shipped


@pytest.mark.parametrize('text', [
    'window: 128\nmovements: [&a0 ["x", "x"], &a1 [*a0, *a0], &a2 [*a1, *a1]]\n',
    'window: &w 128\nmovements:\n  - {name: a}\n',
    'defaults: &d {speed: 0.02}\nmovements:\n  - {<<: *d, name: a}\n',
])
def test_anchors_and_aliases_are_refused_before_any_alias_is_expanded(tmp_path, text):
    with pytest.raises(MovementError, match=r'movements.yaml: line \d+, column \d+: a movement '
                                            'file takes no anchors or aliases'):
        load_movements(written(tmp_path, text))


def test_a_billion_laughs_file_is_refused_in_one_short_line(tmp_path):
    levels = ['&a0 ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    levels += [f'&a{n} [' + ', '.join([f'*a{n - 1}'] * 10) + ']' for n in range(1, 9)]
    with pytest.raises(MovementError) as refused:
        load_movements(written(tmp_path, f'window: 128\nmovements: [{", ".join(levels)}]\n'))
    assert len(str(refused.value)) < 200 and '\n' not in str(refused.value)


@pytest.mark.parametrize('text, match', [
    ('window: 128\nwindow: 64\nmovements:\n  - {name: a}\n',
     "line 2, column 1: key 'window' is given twice in one mapping \\(first on line 1\\)"),
    ('movements:\n  - {name: a, name: b}\n',
     "line 2, column 15: key 'name' is given twice .*first on line 2.*: keep one"),
    ('movements:\n  - name: a\n    speed: 0.02\n    speed: 0.03\n',
     "line 4, column 5: key 'speed' is given twice .*first on line 3"),
])
def test_a_key_given_twice_is_refused_naming_the_key_and_the_line(tmp_path, text, match):
    with pytest.raises(MovementError, match=match):
        load_movements(written(tmp_path, text))


@pytest.mark.parametrize('written_as, value', [
    ('1e-2', 0.01), ('10e-3', 0.01), ('1.5E-2', 0.015), ('+2e-2', 0.02), ('.015', 0.015),
    ('1.5e-2', 0.015), ('0.02', 0.02)])
def test_numbers_are_read_as_yaml_1_2_writes_them(tmp_path, written_as, value):
    movement, = load_movements(one(tmp_path, speed=written_as)).movements
    assert movement.speed_m_s == value


def test_integers_stay_integers_and_merge_keys_are_plain_unknown_keys(tmp_path):
    assert load_movements(one(tmp_path, window=64)).window == 64
    with pytest.raises(MovementError, match='window must be an integer .*got 64.0'):
        load_movements(one(tmp_path, window='6.4e1'))
    with pytest.raises(MovementError, match='unknown keys <<'):
        load_movements(one(tmp_path, **{'<<': '{x: 1}'}))


@pytest.mark.parametrize('key, value, match', [
    ('name', 'n' * 5000, "name must start with a letter.*got 'nnn"),
    ('speed', 's' * 5000, "speed must be a number.*got 'sss"),
    ('direction', 'd' * 5000, "direction must be one of forward, backward, got 'ddd"),
    ('k' * 1000, 1, 'unknown keys kkk'),  # YAML's longest implicit key is 1024
])
def test_an_error_echoes_at_most_a_short_cut_of_a_long_value(tmp_path, key, value, match):
    with pytest.raises(MovementError, match=match) as refused:
        load_movements(one(tmp_path, **{key: value}))
    assert len(str(refused.value)) < 400


def test_many_unknown_keys_are_listed_in_part(tmp_path):
    extra = {f'extra{n:03}': 1 for n in range(300)}
    with pytest.raises(MovementError, match='unknown keys extra000, .*extra007 and 292 more'):
        load_movements(one(tmp_path, **extra))


def test_a_movement_that_is_no_mapping_is_echoed_cut(tmp_path):
    row = '[' + ', '.join(['0.02'] * 5000) + ']'
    with pytest.raises(MovementError, match=r'a movement is a mapping .*got \[0.02, ') as refused:
        load_movements(written(tmp_path, f'movements:\n  - {row}\n'))
    assert len(str(refused.value)) < 300


def test_malformed_yaml_is_refused_in_one_line_with_its_line_and_column(tmp_path):
    text = 'window: 128\nmovements:\n  - {name: a, speed: 0.01, press_depth: 0.0015\n'
    with pytest.raises(MovementError) as refused:
        load_movements(written(tmp_path, text))
    assert '\n' not in str(refused.value)
    assert re.search(r"not a YAML movement file: line 4, column 1: expected ',' or '}'.*"
                     r'\(while parsing a flow mapping\); see config/movements.yaml',
                     str(refused.value))


def test_a_file_not_in_utf8_is_refused_with_the_fix(tmp_path):
    path = tmp_path / 'movements.yaml'
    path.write_bytes(b'\xff\xfe\x00movements')
    with pytest.raises(MovementError, match='not a YAML movement file .*save it as UTF-8'):
        load_movements(path)
