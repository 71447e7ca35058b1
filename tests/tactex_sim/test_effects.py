# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Effects: options checked by value, a fixed run order, declared inputs and outputs held."""

import math

import numpy as np
import pytest

from tactex_sim.effects import EFFECTS, Reading
from tactex_sim.errors import SceneError
from tactex_sim.scene import parse_scene
from tactex_sim.textures import texture
from tactex_sim.world import Contact, World

SLIDING = {'contact': Contact(True, np.array([0.2, 0.01, 0.02]), np.array([0.0, 0.0, 1.0]), 2.0),
           'edge velocity': np.array([0.015, 0.0, 0.0]), 'texture': texture('ridged polymer'),
           'sensor rotation': np.eye(3), 'sensor position': np.array([0.2, 0.0, 0.05]),
           'sample rate': 120.0, 'compression': 0.001, 'time': 3.0,
           'sensor filters': (math.inf, math.inf)}


def effect(name, **options):
    return EFFECTS[name](np.random.default_rng(0), 1.0, **options)


def applied(instance, inputs=SLIDING):
    reading = Reading(np.array([0.0, 0.0, 9.81]), np.zeros(3))
    instance.apply(reading, inputs)
    return reading


@pytest.mark.parametrize('name, option, value', [
    ('texture', 'slip_length_m', 0.0), ('texture', 'reference_force_n', 0.0),
    ('texture', 'slip_length_m', 5e-324), ('magnetometer', 'magnet_radius_m', 1e-310),
    ('texture', 'resonance_hz', 0.5), ('texture', 'rocking_per_m', -1.0),
    ('texture', 'damping_ratio', math.nan), ('texture', 'heading_rad', math.inf),
    ('texture', 'contact_length_m', '20'), ('texture', 'contact_width_m', True),
    ('sensor', 'gyro_range_dps', 4000.0), ('sensor', 'gyro_range_dps', 300.0),
    ('sensor', 'accel_range_g', 3.0), ('sensor', 'pressure_noise_pa', -1.0),
    ('imu_noise', 'accel_sd', -0.1), ('magnetometer', 'magnet_radius_m', 0.0),
    ('magnetometer', 'earth_field_t', [0.0, 2e-5]), ('magnetometer', 'noise_sd_t', 1.0),
    ('barometer', 'sea_level_pa', 0.0), ('barometer', 'temperature_c', -300.0)])
def test_an_option_outside_its_range_is_refused_by_name(name, option, value):
    with pytest.raises(SceneError, match=f"effect '{name}': option {option} must"):
        effect(name, **{option: value})


def test_the_range_is_stated_in_the_message():
    with pytest.raises(SceneError, match=r'slip_length_m must be in \[1e-06, 1\], got 0'):
        effect('texture', slip_length_m=0)


@pytest.mark.parametrize('scale', [-1.0, math.nan, math.inf])
def test_a_bad_noise_scale_is_refused(scale):
    with pytest.raises(SceneError, match='noise_scale must be finite and >= 0'):
        EFFECTS['imu_noise'](np.random.default_rng(0), scale)


def test_magnetometer_at_the_magnet_stays_finite():
    magnet = effect('magnetometer', noise_sd_t=0.0)
    at_magnet = dict(SLIDING, **{'sensor position': np.array([0.35, 0.25, 0.05])})
    assert np.all(np.isfinite(applied(magnet, at_magnet).mag))


def test_effects_run_in_registry_order_whatever_the_scene_order():
    forwards = parse_scene({'name': 'a', 'seed': 1, 'surface': {'kind': 'flat'},
                            'effects': ['contact', 'imu_noise', 'barometer']})
    backwards = parse_scene({'name': 'b', 'seed': 1, 'surface': {'kind': 'flat'},
                             'effects': ['barometer', 'imu_noise', 'contact']})
    worlds = [World(scene) for scene in (forwards, backwards)]
    assert [e.name for e in worlds[0].effects] == [e.name for e in worlds[1].effects] == [
        'contact', 'imu_noise', 'barometer']
    first, second = (world.next_sample() for world in worlds)
    np.testing.assert_array_equal(first.accel, second.accel)
    assert first.pressure == second.pressure


def test_an_effect_reading_an_input_it_did_not_declare_is_stopped():
    scene = parse_scene({'name': 'a', 'seed': 1, 'surface': {'kind': 'flat'},
                         'effects': ['imu_noise']})
    world = World(scene)
    noise = world.effects[0]
    noise.apply = lambda reading, inputs: inputs['contact']
    with pytest.raises(KeyError, match="effect 'imu_noise' reads 'contact' without declaring"):
        world.next_sample()


@pytest.mark.parametrize('name', list(EFFECTS))
def test_every_effect_changes_only_the_channels_it_declares(name):
    reading = applied(effect(name))
    changed = {'accel': not np.array_equal(reading.accel, [0.0, 0.0, 9.81]),
               'gyro': not np.array_equal(reading.gyro, np.zeros(3)),
               'mag': not np.all(np.isnan(reading.mag)),
               'pressure': not math.isnan(reading.pressure),
               'temperature': not math.isnan(reading.temperature)}
    assert {channel for channel, moved in changed.items() if moved} <= EFFECTS[name].writes


def test_model_parts_follow_what_the_enabled_effects_write():
    welded = World(parse_scene({'name': 'a', 'seed': 1, 'surface': {'kind': 'flat'},
                                'effects': ['contact']}))
    compliant = World(parse_scene({'name': 'b', 'seed': 1, 'surface': {'kind': 'flat'},
                                   'effects': ['contact', 'compliance']}))
    assert welded.model.nq < compliant.model.nq
