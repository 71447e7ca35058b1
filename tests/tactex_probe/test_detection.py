# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Contact detection: light touches are contacts, bumps, bursts and NaN are not."""

import math

import numpy as np
import pytest

from tactex_probe.detection import Channel, ContactDetector, DetectorConfig

RATE_HZ = 120.0
BASE_PA = 101325.0
GRAVITY = np.array([0.0, 0.0, -9.81])


def stamp(i):
    return int(round(i / RATE_HZ * 1e9))


def armed(rng, samples=60, **config):
    """A detector armed in free air on an ideal barometer (2 Pa noise, no quantisation)."""
    config.setdefault('resolution_pa', 0.0)
    detector = ContactDetector(DetectorConfig(**config))
    for _ in range(samples):
        detector.learn(BASE_PA + rng.normal(0.0, 2.0), GRAVITY + rng.normal(0.0, 0.02, 3))
    return detector


def feed(detector, pressures, accels=None):
    events = []
    for i, pressure in enumerate(pressures):
        accel = None if accels is None else accels[i]
        event = detector.update(stamp(i), pressure, accel)
        if event is not None:
            events.append(event)
    return events


def test_light_touch_is_a_contact_with_its_onset():
    rng = np.random.default_rng(1)
    detector = armed(rng)
    onset = 40
    # A touch at 1 mm/s: 1500 Pa/s, i.e. 12.5 Pa per sample, up to a 0.03 N proxy.
    rise = np.clip((np.arange(120) - onset) * 12.5, 0.0, 75.0)
    events = feed(detector, BASE_PA + rise + rng.normal(0.0, 2.0, 120))
    assert len(events) == 1 and events[0].channel is Channel.PRESSURE
    assert abs(events[0].onset_ns - stamp(onset)) < stamp(1.5)
    assert events[0].detected_ns > events[0].onset_ns


def test_an_mpl115a2_repeating_one_code_gives_no_false_contact():
    # Its 10-bit codes 63.5 Pa apart, one code of noise: most free-air readings repeat the
    # median code, so the median absolute deviation is 0; the spread must not follow it.
    from tactex_common import chips
    rng = np.random.default_rng(5)

    def reading(pa):
        return float(chips.quantise_pressure(pa + rng.normal(0.0, 0.5 * chips.PRESSURE_LSB_PA)))
    detector = ContactDetector(DetectorConfig(resolution_pa=chips.PRESSURE_LSB_PA))
    for _ in range(60):
        detector.learn(reading(BASE_PA), GRAVITY)
    assert detector.spread_pa >= chips.PRESSURE_LSB_PA
    events = []
    for i in range(1200):  # 10 s in free air
        event = detector.update(stamp(i), reading(BASE_PA), None)
        events += [event] if event is not None else []
    assert events == []
    # A real press (0.5 N, 1250 Pa) is still found.
    pressed = feed(detector, [reading(BASE_PA + min(1250.0, 25.0 * i)) for i in range(120)])
    assert len(pressed) == 1


@pytest.mark.parametrize('seed', range(8))
def test_the_onset_of_a_touch_read_through_10_bit_codes_with_a_code_of_noise_is_found(seed):
    # A 5 mm/s descent rises 62.5 Pa a sample at 120 Hz: one MPL115A2 code, as much as
    # its noise. The onset is fitted through the whole rise, not the three samples that
    # crossed the threshold, so it is found within a few samples (0.1 mm of descent).
    from tactex_common import chips
    rng = np.random.default_rng(seed)

    def reading(pa):
        return float(chips.quantise_pressure(pa + rng.normal(0.0, chips.PRESSURE_LSB_PA)))
    detector = ContactDetector()
    for _ in range(60):
        detector.learn(reading(BASE_PA), GRAVITY)
    onset = 100
    events = feed(detector, [reading(BASE_PA + 62.5 * max(0, i - onset)) for i in range(200)])
    assert len(events) == 1
    assert abs(events[0].onset_ns - stamp(onset)) <= stamp(3)


def test_acceleration_bump_in_free_air_is_not_a_contact():
    rng = np.random.default_rng(2)
    detector = armed(rng)
    accels = np.tile(GRAVITY, (120, 1))
    accels[50:60] += [8.0, -5.0, 6.0]  # the arm jerks
    assert feed(detector, BASE_PA + rng.normal(0.0, 2.0, 120), accels) == []
    assert not detector.in_contact


def test_noise_bursts_are_not_contacts():
    rng = np.random.default_rng(3)
    detector = armed(rng)
    pressures = BASE_PA + rng.normal(0.0, 2.0, 240)
    for start in (30, 90, 150):
        pressures[start:start + 6] += 400.0 * np.array([1, -1, 1, -1, 1, -1])
    assert feed(detector, pressures) == []


def test_nan_samples_mid_descent_neither_count_nor_break_detection():
    rng = np.random.default_rng(4)
    detector = armed(rng)
    rise = np.clip((np.arange(120) - 40) * 30.0, 0.0, None)
    pressures = BASE_PA + rise + rng.normal(0.0, 2.0, 120)
    pressures[20:30] = np.nan
    pressures[42:44] = np.nan  # inside the debounce run
    events = feed(detector, pressures)
    assert len(events) == 1
    assert stamp(40) - stamp(2) < events[0].onset_ns < stamp(46)


def test_contact_ends_only_after_a_sustained_drop():
    rng = np.random.default_rng(5)
    detector = armed(rng)
    pressures = np.concatenate([np.full(10, BASE_PA + 500.0), np.full(2, BASE_PA),
                                np.full(5, BASE_PA + 500.0), np.full(10, BASE_PA)])
    events = feed(detector, pressures)
    assert len(events) == 1  # the two-sample dip did not end it
    assert not detector.in_contact  # the long drop did


def test_nothing_is_detected_before_the_baseline_is_learnt():
    detector = ContactDetector()
    assert not detector.armed
    assert feed(detector, np.full(50, BASE_PA + 1000.0)) == []


def test_baseline_spread_ignores_a_burst_while_learning():
    rng = np.random.default_rng(6)
    detector = ContactDetector(DetectorConfig(resolution_pa=0.0))
    for i in range(60):
        detector.learn(BASE_PA + rng.normal(0.0, 2.0) + (5000.0 if i == 30 else 0.0))
    assert detector.spread_pa < 4.0
    assert detector.threshold_pa == pytest.approx(DetectorConfig().min_rise_pa)


def test_force_proxy_is_the_rise_over_the_calibration():
    rng = np.random.default_rng(7)
    detector = armed(rng, pa_per_newton=2500.0)
    assert detector.force_proxy(detector.baseline_pa + 3750.0) == pytest.approx(1.5)


def test_accelerometer_stands_in_without_a_barometer():
    detector = ContactDetector()
    tilted = np.array([0.0, math.sin(0.05), -math.cos(0.05)]) * 9.81  # body bent by 2.9 deg
    for _ in range(40):
        detector.learn(math.nan, GRAVITY)
    assert detector.armed and not detector.uses_pressure
    bump = [GRAVITY] * 20 + [tilted] * 5 + [GRAVITY] * 20  # too short to count
    assert feed(detector, np.full(45, math.nan), bump) == []
    bent = [GRAVITY] * 20 + [tilted] * 30
    events = feed(detector, np.full(50, math.nan), bent)
    assert len(events) == 1 and events[0].channel is Channel.ACCEL


@pytest.mark.parametrize('option, value', [
    ('debounce', 0), ('sigmas', -1.0), ('min_rise_pa', math.nan), ('release_fraction', 1.0),
    ('baseline_samples', 2.5)])
def test_config_refuses_unusable_values(option, value):
    with pytest.raises(ValueError, match=option):
        DetectorConfig(**{option: value})
