# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The `sensor` effect: what a real LSM9DS0 and MPL115A2 report, in the scenes that declare it."""

import dataclasses
import math

import numpy as np
import pytest

from tactex_common import chips
from tactex_sim.collect import record_sweep
from tactex_sim.effects import EFFECTS, Reading
from tactex_sim.inputs import Inputs
from tactex_sim.scene import load_scene, resolve_scene
from tactex_sim.sweep import plan_sweep, play, SweepParameters
from tactex_sim.textures import TEXTURES
from tactex_sim.world import World


def shipped(name: str):
    """A shipped scene (each declares the chip model)."""
    return load_scene(resolve_scene(name))


def without_chips(name: str):
    """A shipped scene with its `sensor` declaration taken out: the physics alone."""
    scene = shipped(name)
    return dataclasses.replace(scene, effects=tuple(e for e in scene.effects if e != 'sensor'))


def chip(**options):
    return EFFECTS['sensor'](np.random.default_rng(0), 1.0, pressure_noise_pa=0.0, **options)


def reported(effect, accel=(0.0, 0.0, 9.81), gyro=(0.0, 0.0, 0.0), mag=(2e-5, 0.0, -4e-5),
             pressure=101325.0, t=0.0):
    reading = Reading(np.array(accel, dtype=float), np.array(gyro, dtype=float))
    reading.mag = np.array(mag, dtype=float)
    reading.pressure = pressure
    effect.apply(reading, Inputs(time_s=t))
    return reading


@pytest.mark.parametrize('scene', ['uneven_texture', 'even_texture', 'probe'])
def test_a_scene_gets_the_chips_only_when_it_declares_them(scene):
    assert [e.name for e in World(shipped(scene)).effects][-1] == 'sensor'
    assert 'sensor' not in [e.name for e in World(without_chips(scene)).effects]


def test_a_245_dps_gyro_clips_a_fast_rocking_at_its_rail_and_none_without_the_chip():
    rail = chips.gyro_range(245).rails_si[1]
    fast = (6.0, -6.0, 1.0)  # rad/s: past +-245 dps (4.3 rad/s), within +-500 dps
    clipped = reported(chip(gyro_range_dps=245.0), gyro=fast).gyro
    assert list(clipped[:2]) == [rail, chips.gyro_range(245).rails_si[0]]
    assert clipped[2] == pytest.approx(1.0, abs=chips.gyro_range(245).lsb_si)
    wide = reported(chip(gyro_range_dps=500.0), gyro=fast).gyro
    assert wide == pytest.approx(fast, abs=chips.gyro_range(500).lsb_si)


def test_every_axis_is_a_whole_count_of_the_configured_range():
    reading = reported(chip(), accel=(0.123456, -4.56789, 9.80665), gyro=(0.01, -0.02, 0.3))
    for values, lsb in ((reading.accel, chips.accel_range().lsb_si),
                        (reading.gyro, chips.gyro_range().lsb_si)):
        counts = values / lsb
        assert np.allclose(counts, np.rint(counts), atol=1e-9)


def test_the_magnetometer_updates_at_its_100_hz_output_data_rate():
    effect = chip()
    times = np.arange(0, 35) / 350.0  # a 350 Hz stream
    values = [reported(effect, mag=(1e-7 * k, 0.0, 0.0), t=t).mag[0]
              for k, t in enumerate(times)]
    assert len(set(values)) == 10  # 0.1 s at 100 Hz


def test_the_barometer_reports_the_start_of_its_conversion_as_a_10_bit_code():
    effect = chip()
    reported(effect, pressure=100000.0, t=0.0)
    step = reported(effect, pressure=101000.0, t=1 / 120).pressure
    expected = 101000.0 - chips.PRESSURE_CONVERSION_S * 120 * 1000.0
    assert abs(step - expected) <= chips.PRESSURE_LSB_PA / 2 + 1e-9
    assert (step - chips.PRESSURE_MIN_PA) / chips.PRESSURE_LSB_PA == pytest.approx(
        round((step - chips.PRESSURE_MIN_PA) / chips.PRESSURE_LSB_PA), abs=1e-6)


def test_a_missing_channel_stays_missing():
    effect = chip()
    reading = Reading(np.zeros(3), np.zeros(3))
    effect.apply(reading, Inputs(time_s=0.0))
    assert np.isnan(reading.mag).all() and math.isnan(reading.pressure)


@pytest.mark.slow
def test_no_texture_of_the_default_scene_drives_a_channel_past_its_full_scale():
    scene = shipped('uneven_texture')
    limits = {'accel': chips.accel_range().full_scale_si, 'gyro': chips.gyro_range().full_scale_si}
    at_rails = total = 0
    for name in TEXTURES:
        parameters = SweepParameters.draw(scene, np.random.default_rng(3))
        plan = plan_sweep(scene, parameters)
        world = World(scene, seed=3, patch_texture=name,
                      texture_heading_rad=parameters.heading_rad)
        samples = []
        play(world, plan, samples.append)
        for channel, limit in limits.items():
            values = np.abs(np.array([getattr(s, channel) for s in samples]))
            assert values.max() <= limit, (name, channel, values.max())
        rails = chips.gyro_range().rails_si[1]
        at_rails += int((np.abs([s.gyro for s in samples]) >= rails).any(axis=1).sum())
        total += len(samples)
    assert at_rails < 0.001 * total


@pytest.mark.slow
def test_a_recording_carries_whole_counts_with_the_chips_and_the_physics_alone_without(
        tmp_path):
    from tactex_classify.data.bags import read_recording
    scene = shipped('uneven_texture')
    bare = without_chips('uneven_texture')
    lsb = chips.gyro_range().lsb_si
    whole = {}
    for name, variant in (('chips', scene), ('bare', bare)):
        path = record_sweep(variant, 'wood', 0, tmp_path / name, np.random.SeedSequence(0))
        recording = read_recording(path)
        gyro = recording.values[:, [recording.channels.index(c) for c in ('gx', 'gy', 'gz')]]
        whole[name] = np.allclose(gyro / lsb, np.rint(gyro / lsb), atol=1e-6)
    assert whole == {'chips': True, 'bare': False}
