# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Texture vibration from physics: the footprint filters, the body answers, no stray gain."""

import math

import numpy as np
import pytest

from tactex_description import edge
from tactex_sim import vibration
from tactex_sim.effects import EFFECTS, Reading
from tactex_sim.inputs import Contact, Inputs
from tactex_sim.textures import Texture

SPEED = 0.015
NORMAL = np.array([0.0, 0.0, 1.0])


def ridges(period_m: float, height_m: float = 100e-6, angle: float = 0.0) -> Texture:
    """Smooth, slippery ridges (no roughness, no stick-slip), crests across the path."""
    return Texture('test ridges', ridge_period=period_m, ridge_height=height_m,
                   ridge_angle=angle, roughness_rms=0.0, friction=0.3, softness=1.0)


def slide(surface, *, speed=SPEED, force=1.0, x=0.2013, **options):
    """One sample's texture signal: (normal accel, rocking rate) sliding along +x."""
    texture_effect = EFFECTS['texture'](np.random.default_rng(0), 1.0, **options)
    reading = Reading(np.zeros(3), np.zeros(3))
    texture_effect.apply(reading, Inputs(
        contact=Contact(True, np.array([x, 0.0, 0.02]), NORMAL, force),
        edge_velocity=np.array([speed, 0.0, 0.0]), texture=surface,
        sensor_rotation=np.eye(3), sample_rate_hz=120.0,
        sensor_filters_hz=(math.inf, math.inf)))
    # The rocking axis is n x d = z x x = +y.
    return reading.accel[2], reading.gyro[1]


def test_the_signal_is_the_footprint_averaged_profile_through_the_body_no_gain():
    surface = ridges(0.004)
    options = EFFECTS['texture'].defaults
    length, width = options['contact_length_m'].default, options['contact_width_m'].default
    accel, rate = slide(surface)
    expected_accel = expected_rate = 0.0
    for amplitude, k, phase in surface.waves():
        felt = amplitude * vibration.footprint_gain(k[0], k[1], length, width)
        frequency = SPEED * abs(k[0]) / (2 * math.pi)
        angle = k[0] * 0.2013 + phase
        expected_accel -= SPEED ** 2 * felt * k[0] ** 2 * math.cos(angle) * float(
            vibration.transmissibility(frequency, edge.normal_resonance_hz(),
                                       edge.SKIN_DAMPING_RATIO))
        expected_rate -= edge.rocking_per_metre() * SPEED * felt * k[0] * math.sin(
            angle) * float(vibration.transmissibility(frequency, edge.rocking_resonance_hz(),
                                                      edge.SKIN_DAMPING_RATIO))
    assert accel == pytest.approx(expected_accel, rel=1e-9)
    assert rate == pytest.approx(expected_rate, rel=1e-9)
    # 4 mm ridges 100 um high at 15 mm/s: a few hundredths of m/s^2 and of rad/s.
    assert 0.005 < abs(accel) < 0.2 and 0.001 < abs(rate) < 0.1


def test_ridges_as_fine_as_the_footprint_cancel_under_it():
    length = EFFECTS['texture'].defaults['contact_length_m'].default
    coarse = max(abs(slide(ridges(10 * length), x=x)[0]) for x in np.linspace(0.2, 0.21, 41))
    matched = Texture('matched', ridge_period=length, ridge_height=100e-6, friction=0.3)
    fine = max(abs(slide(matched, x=x)[0]) for x in np.linspace(0.2, 0.21, 41))
    assert fine < 0.05 * coarse


def test_ridges_along_the_path_are_averaged_over_the_edge_width():
    across = max(abs(slide(ridges(0.003), x=x)[1]) for x in np.linspace(0.2, 0.21, 41))
    oblique = max(abs(slide(ridges(0.003, angle=0.6), x=x)[1])
                  for x in np.linspace(0.2, 0.21, 41))
    assert oblique < 0.5 * across


def test_acceleration_grows_with_the_square_of_speed_and_rocking_with_speed():
    surface = ridges(0.02)  # 0.75 Hz at 15 mm/s: far below both resonances
    slow, fast = slide(surface, speed=0.01), slide(surface, speed=0.02)
    assert fast[0] / slow[0] == pytest.approx(4.0, rel=0.01)
    assert fast[1] / slow[1] == pytest.approx(2.0, rel=0.01)


def test_a_light_touch_cannot_pull_the_edge_down_faster_than_its_force_allows():
    accel, _ = slide(ridges(0.0015, 300e-6), speed=0.5, force=1e-3)
    assert abs(accel) <= 1e-3 / edge.body_mass_kg() + 1e-12


def test_no_sliding_no_signal():
    assert slide(ridges(0.004), speed=0.0) == (0.0, 0.0)
