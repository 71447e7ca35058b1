# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Effects: options checked by value, a fixed run order, declared inputs and outputs held."""

import ast
import dataclasses
import inspect
import math
import textwrap

import numpy as np
import pytest

from tactex_sim.effects import Effect, EFFECTS, Reading
from tactex_sim.errors import SceneError
from tactex_sim.inputs import Contact, INPUT_NAMES, Inputs
from tactex_sim.scene import parse_scene
from tactex_sim.textures import texture
from tactex_sim.world import World

SLIDING = Inputs(
    contact=Contact(True, np.array([0.2, 0.01, 0.02]), np.array([0.0, 0.0, 1.0]), 2.0),
    edge_velocity=np.array([0.015, 0.0, 0.0]), texture=texture('ridged polymer'),
    sensor_rotation=np.eye(3), sensor_position=np.array([0.2, 0.0, 0.05]),
    sample_rate_hz=120.0, compression_m=0.001, time_s=3.0,
    sensor_filters_hz=(math.inf, math.inf))


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
    ('barometer', 'sea_level_pa', 0.0), ('barometer', 'temperature_c', -300.0),
    # TOML reads a long whole number as an int past the float range
    pytest.param('texture', 'resonance_hz', 10**400, id='texture-resonance_hz-10**400')])
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
    at_magnet = dataclasses.replace(SLIDING, sensor_position=np.array([0.35, 0.25, 0.05]))
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


def test_an_effect_gets_only_the_inputs_it_declared():
    scene = parse_scene({'name': 'a', 'seed': 1, 'surface': {'kind': 'flat'},
                         'effects': ['contact', 'imu_noise', 'barometer']})
    world = World(scene)
    seen = {}
    for effect in world.effects:
        effect.apply = lambda reading, inputs, name=effect.name: seen.setdefault(name, inputs)
    world.next_sample()
    filled = {name: {f for f in INPUT_NAMES if getattr(inputs, f) is not None}
              for name, inputs in seen.items()}
    assert filled == {'contact': set(), 'imu_noise': set(),
                      'barometer': {'compression_m', 'time_s'}}


def test_an_effect_declaring_an_input_the_world_lacks_fails_when_defined():
    with pytest.raises(TypeError, match=r"effect 'sonar' reads \['echo'\], which the world"):
        type('Sonar', (Effect,), {'name': 'sonar', 'reads': frozenset({'echo'})})


def _attributes_used(function, owner: str, *, stored: bool) -> set[str]:
    """Attributes of the argument `owner` that `function` reads (or, `stored`, assigns)."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(function)))
    context = ast.Store if stored else ast.Load
    return {node.attr for node in ast.walk(tree)
            if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
            and node.value.id == owner and isinstance(node.ctx, context)}


@pytest.mark.parametrize('name', list(EFFECTS))
def test_every_effect_declares_exactly_the_inputs_and_channels_its_apply_uses(name):
    cls = EFFECTS[name]
    if cls.apply is Effect.apply:  # builds model parts only
        assert not cls.reads
        return
    assert _attributes_used(cls.apply, 'inputs', stored=False) == cls.reads
    augmented = {node.target.attr for node in ast.walk(ast.parse(textwrap.dedent(
        inspect.getsource(cls.apply)))) if isinstance(node, ast.AugAssign)
        and isinstance(node.target, ast.Attribute)
        and getattr(node.target.value, 'id', None) == 'reading'}
    written = _attributes_used(cls.apply, 'reading', stored=True) | augmented
    assert written == cls.writes & set(Reading.__slots__)


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
