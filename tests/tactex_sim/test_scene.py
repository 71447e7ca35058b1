# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Scene files: every shipped scene loads; every mistake is named."""

import os
from pathlib import Path

import pytest

from tactex_sim.errors import SceneError, UnknownNameError
from tactex_sim.scene import load_scene, parse_scene, resolve_scene
from tactex_sim.world import World

SCENES = sorted((Path(__file__).resolve().parents[2] / 'config' / 'scenes').glob('*.toml'))
MINIMAL = {'name': 't', 'seed': 1, 'effects': ['contact'], 'surface': {'kind': 'flat'}}


@pytest.mark.parametrize('path', SCENES, ids=lambda p: p.stem)
def test_shipped_scenes_load_and_build(path):
    scene = load_scene(path)
    assert World(scene).model.nq > 0


def test_unknown_top_level_key_is_named():
    with pytest.raises(SceneError, match="unknown key\\(s\\) 'gravity' in \\[top level\\]"):
        parse_scene({**MINIMAL, 'gravity': 9.8})


def test_unknown_section_key_lists_the_known_ones():
    with pytest.raises(SceneError, match="'amplitud' in \\[surface\\]; known: amplitude_m"):
        parse_scene({**MINIMAL, 'surface': {'kind': 'flat', 'amplitud': 1}})


@pytest.mark.parametrize('change, match', [
    ({'seed': -1}, 'seed'),
    ({'sensor_rate_hz': 0}, 'sensor_rate_hz'),
    ({'timestep_s': 0.05}, 'timestep_s'),
    ({'surface': {'kind': 'wavy'}}, 'kind'),
    ({'surface': {'size_m': [0.3]}}, 'size_m must be a list of 2'),
    ({'surface': {'amplitude_m': 'big'}}, 'amplitude_m must be a finite number'),
    ({'effects': ['contact', 'contact']}, 'repeat'),
    ({'effect': {'texture': {}}}, 'does not list'),
    ({'patches': [{'texture': 'wood', 'x_m': [0.2, 0.1], 'y_m': [0, 1]}]}, 'empty rectangle'),
    ({'sweep': {'press': 'tip'}}, r'\[sweep\] press must be "centre" or "rim"'),
    ({'sweep': {'press': 3}}, r'\[sweep\] press must be text'),
    ({'sweep': {'ramp_acceleration_m_s2': 0}}, r'ramp_acceleration_m_s2 must be > 0 m/s\^2'),
    ({'sweep': {'ramp_acceleration_m_s2': 'slow'}}, 'ramp_acceleration_m_s2 must be a finite'),
])
def test_bad_values_fail_with_the_key(change, match):
    with pytest.raises(SceneError, match=match):
        parse_scene({**MINIMAL, **change})


@pytest.mark.parametrize('change, match', [
    ({'surface': {'kind': 'flat', 'cells': [100_000, 100_000]}},
     r'cells \[100000, 100000\] make 10000000000 heightfield cells; at most 1000000'),
    ({'sweep': {'contact_s': 1e7}}, r'contact_s must be <= 60 s, got 10000000.0'),
    ({'timestep_s': 1e-12}, r'timestep_s must be in 0.0001..0.02 s, got 1e-12'),
    ({'seed': 10**20}, r'seed must be a whole number in 0..4294967295'),
    ({'sensor_rate_hz': 'fast'}, 'sensor_rate_hz must be a finite number'),
    # TOML reads a long whole number as an int past the float range
    ({'sensor_rate_hz': 10**400}, 'sensor_rate_hz must be a finite number'),
    ({'surface': {'size_m': [10**400, 0.3]}}, 'size_m must hold finite numbers'),
    ({'patches': [{'texture': 'wood', 'x_m': [0.1, 0.2], 'y_m': [0.0, 0.1]}] * 65},
     '65 patches; at most 64'),
])
def test_numbers_that_size_memory_or_time_are_bounded(change, match):
    with pytest.raises(SceneError, match=match):
        parse_scene({**MINIMAL, **change})


@pytest.mark.parametrize('make, match', [
    (lambda path: os.mkfifo(path), r'is a FIFO \(named pipe\), not a regular file'),
    (lambda path: path.symlink_to('/dev/zero'), 'is a character device, not a regular file'),
    (lambda path: path.write_bytes(b'x = ' + b'[' * 200_000), 'nested too deep|not valid TOML'),
    (lambda path: path.write_bytes(b'#' * (1024 * 1024 + 1)), 'larger than the 1048576 bytes'),
])
def test_a_scene_file_that_is_no_scene_is_refused_without_waiting(tmp_path, make, match):
    path = tmp_path / 'scene.toml'
    make(path)
    with pytest.raises(SceneError, match=match):
        load_scene(path)


def test_missing_file_and_bad_toml(tmp_path):
    with pytest.raises(SceneError, match='no scene file'):
        load_scene(tmp_path / 'none.toml')
    broken = tmp_path / 'broken.toml'
    broken.write_text('name = "x', encoding='utf-8')
    with pytest.raises(SceneError, match='not valid TOML'):
        load_scene(broken)


def test_unknown_effect_lists_the_registered_ones():
    scene = parse_scene({**MINIMAL, 'effects': ['contact', 'wind']})
    with pytest.raises(UnknownNameError, match='unknown effect .wind.; known effects: contact'):
        World(scene)


def test_unknown_effect_option_is_refused():
    scene = parse_scene({**MINIMAL, 'effects': ['barometer'],
                         'effect': {'barometer': {'altitude': 3}}})
    with pytest.raises(SceneError, match="effect 'barometer': unknown option"):
        World(scene)


def test_unknown_texture_is_named():
    scene = parse_scene({**MINIMAL, 'patches': [{'texture': 'velvet', 'x_m': [0, 1],
                                                  'y_m': [0, 1]}]})
    with pytest.raises(UnknownNameError, match="unknown texture 'velvet'; known: brocade"):
        World(scene)


def test_the_shifted_scene_is_the_uneven_one_recorded_by_another_arm():
    uneven, shifted = (load_scene(resolve_scene(name)) for name in ('uneven_texture',
                                                                    'shifted_texture'))
    for same in ('sensor_rate_hz', 'timestep_s', 'effects', 'surface', 'patches'):
        assert getattr(shifted, same) == getattr(uneven, same), same
    assert shifted.sweep.speed_m_s * shifted.sweep.contact_s == pytest.approx(
        uneven.sweep.speed_m_s * uneven.sweep.contact_s, rel=0.01)  # the same path length
    assert shifted.sweep.speed_m_s > uneven.sweep.speed_m_s
    assert shifted.variability.press_depth_m[0] < uneven.variability.press_depth_m[0]
    body = shifted.effect_options['texture']
    assert body['resonance_hz'] < 85 and body['damping_ratio'] > 0.12  # softer than the default
    assert shifted.effect_options['sensor'] == {'accel_range_g': 8.0, 'gyro_range_dps': 500.0}
    assert shifted.effect_options['imu_noise']['accel_sd'] == \
        2 * uneven.effect_options['imu_noise']['accel_sd']
