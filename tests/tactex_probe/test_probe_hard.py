# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Contact detection, normal estimation, the profile and the tilt search under any input.

Recovery: after any burst of bad samples (any pressure, any accel, any stamps), a
pressure-armed detector is out of contact at most RELEASE_SAMPLES free-air samples after
the burst stops, and then finds the next real touch with its onset; an accel-armed one
(no barometer) is out of contact at most `accel_debounce` samples after it.
"""

import math

from hypothesis import assume, example, given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from support.hard_values import anything, finite, FLOAT32_MAX, FLOAT64_MAX, vectors

from tactex_probe.alignment import MAX_TILT_STEP_RAD, next_tilt, TouchResult
from tactex_probe.detection import ContactDetector, DetectorConfig, MEDIAN_OF
from tactex_probe.errors import ProbeError
from tactex_probe.normals import (
    align,
    bearing_point,
    estimate_normal,
    mean_quaternion,
    NormalEstimate,
    SensorWindow,
)
from tactex_probe.profile import horizontal, normal_from_slope, slope_at

pytestmark = pytest.mark.hard_case

RATE_HZ = 120.0
PERIOD_NS = int(1e9 / RATE_HZ)
BASE_PA = 101325.0
GRAVITY = np.array([0.0, 0.0, -9.81])
CONFIG = DetectorConfig()
# An ideal barometer (2 Pa noise, no 10-bit steps): the touches below rise 12.5 Pa a sample.
IDEAL = DetectorConfig(resolution_pa=0.0)
# Free-air samples after a bad burst within which a detector has left contact: the
# median of MEDIAN_OF readings is back at the baseline, then `debounce` samples below.
RELEASE_SAMPLES = MEDIAN_OF - 1 + CONFIG.debounce
# Header stamps a ROS Time can carry (int32 seconds), ns.
ROS_STAMPS = st.integers(-2 ** 31 * 10 ** 9, 2 ** 31 * 10 ** 9)
stamp_steps = st.one_of(st.sampled_from([0, -1, -PERIOD_NS, 10 ** 15]),
                        st.integers(0, 10 * PERIOD_NS))
bad_samples = st.tuples(stamp_steps, anything(),
                        st.one_of(st.none(), vectors(anything())))


def armed_detector(seed: int, pressure: bool = True) -> ContactDetector:
    rng = np.random.default_rng(seed)
    detector = ContactDetector(IDEAL)
    for _ in range(CONFIG.baseline_samples):
        detector.learn(BASE_PA + rng.normal(0.0, 2.0) if pressure else math.nan,
                       GRAVITY + rng.normal(0.0, 0.02, 3))
    assert detector.armed
    return detector


def feed(detector, start_ns, samples):
    """Feed (stamp step, pressure, accel) samples; return the events and the last stamp."""
    events, stamp = [], start_ns
    for step, pressure, accel in samples:
        stamp += step
        event = detector.update(stamp, pressure, accel)
        if event is not None:
            events.append(event)
    return events, stamp


def assert_valid(event):
    assert isinstance(event.onset_ns, int) and isinstance(event.detected_ns, int)
    assert math.isfinite(event.snr) and event.snr > 0


@settings(max_examples=100)
@given(ROS_STAMPS, st.lists(bad_samples, max_size=30), st.booleans(), st.integers(0, 3))
def test_the_detector_takes_any_stream_and_reports_only_valid_events(start, samples, pressure,
                                                                     seed):
    detector = armed_detector(seed, pressure)
    events, _ = feed(detector, start, samples)
    for event in events:
        assert_valid(event)


@example(0, [(0, 202699.0, None), (0, 0.0, None), (0, FLOAT32_MAX, None)], 0)
@settings(max_examples=60)
@given(ROS_STAMPS, st.lists(bad_samples, min_size=1, max_size=30), st.integers(0, 3))
def test_the_detector_recovers_and_finds_the_next_touch_after_bad_samples_stop(start, bad,
                                                                               seed):
    detector = armed_detector(seed)
    _, stamp = feed(detector, start, bad)
    _, stamp = feed(detector, stamp, [(PERIOD_NS, BASE_PA, None)] * RELEASE_SAMPLES)
    assert not detector.in_contact
    # A touch at 1 mm/s: 12.5 Pa per sample from the sample after `stamp`.
    ramp = [(PERIOD_NS, BASE_PA + 12.5 * i, None) for i in range(1, 40)]
    events, _ = feed(detector, stamp, ramp)
    assert len(events) == 1
    assert_valid(events[0])
    assert abs(events[0].onset_ns - stamp) < 2 * PERIOD_NS


@settings(max_examples=60)
@given(ROS_STAMPS, st.lists(bad_samples, min_size=1, max_size=30), st.integers(0, 3))
def test_an_accel_detector_leaves_contact_after_bad_samples_stop(start, bad, seed):
    detector = armed_detector(seed, pressure=False)
    _, stamp = feed(detector, start, bad)
    feed(detector, stamp, [(PERIOD_NS, math.nan, GRAVITY)] * CONFIG.accel_debounce)
    assert not detector.in_contact


@example([(0.0, (0.0, 0.0, FLOAT32_MAX))], False)
@example([(1e300, None), (FLOAT64_MAX, None)], True)  # a median that overflowed (make hunt)
@settings(max_examples=80)
@given(st.lists(st.tuples(anything(), st.one_of(st.none(), vectors(anything()))),
                min_size=1, max_size=3), st.booleans())
def test_a_few_wild_free_air_samples_do_not_blind_the_detector(wild, pressure):
    detector = ContactDetector(IDEAL)
    for pressure_pa, accel in wild:
        detector.learn(pressure_pa if pressure else math.nan, accel)
    rng = np.random.default_rng(1)
    for _ in range(CONFIG.baseline_samples):  # the clean samples outnumber the wild ones
        detector.learn(BASE_PA + rng.normal(0.0, 2.0) if pressure else math.nan,
                       GRAVITY + rng.normal(0.0, 0.02, 3))
    assert math.isfinite(detector.threshold_pa) or not pressure
    free_air, _ = feed(detector, 0, [(PERIOD_NS, BASE_PA, GRAVITY)] * 40)
    assert free_air == [] and not detector.in_contact
    if pressure:
        touch = [(PERIOD_NS, BASE_PA + 12.5 * i, None) for i in range(1, 40)]
    else:  # the body bent by about 8.7 degrees, held
        touch = [(PERIOD_NS, math.nan, GRAVITY + [0.0, 1.5, 0.0])] * 2 * CONFIG.accel_debounce
    events, _ = feed(detector, 0, touch)
    assert len(events) == 1
    assert_valid(events[0])


def assert_rotation(matrix):
    assert np.all(np.isfinite(matrix))
    np.testing.assert_allclose(matrix @ matrix.T, np.eye(3), atol=1e-9)
    assert np.linalg.det(matrix) == pytest.approx(1.0, abs=1e-9)


def unit(vector):
    vector = np.asarray(vector, dtype=float)
    scaled = vector / np.max(np.abs(vector))
    return scaled / np.linalg.norm(scaled)


@example((1e300, 1e300, 0.0), (0.0, 0.0, 5e-324))
@settings(max_examples=200)
@given(vectors(anything()), vectors(anything()))
def test_align_turns_any_direction_onto_any_other_or_refuses_a_zero_or_non_finite_one(
        measured, target):
    usable = all(np.all(np.isfinite(v)) and np.any(np.asarray(v) != 0)
                 for v in (measured, target))
    if not usable:
        with pytest.raises(ProbeError, match='finite, non-zero'):
            align(measured, target)
        return
    rotation = align(measured, target)
    assert_rotation(rotation)
    np.testing.assert_allclose(rotation @ unit(measured), unit(target), atol=1e-9)


@example([(1e300, 1e300, 0.0, 0.0)])
@settings(max_examples=100)
@given(st.lists(vectors(finite(), 4), min_size=1, max_size=6))
def test_the_mean_of_any_finite_quaternions_is_a_unit_quaternion(quaternions):
    assume(any(np.any(np.asarray(q) != 0) for q in quaternions))
    mean = mean_quaternion(quaternions)
    assert np.all(np.isfinite(mean)) and np.linalg.norm(mean) == pytest.approx(1.0)


LEVEL_JOINTS = np.array([0.0, 0.3, 0.2, -0.5])


@st.composite
def windows(draw):
    """A free-air and a pressed window, each a plausible one with any field made extreme."""
    made = []
    for pressed in (False, True):
        fields = {'quaternion': np.array([1.0, 0.0, 0.0, 0.0]), 'accel': -GRAVITY.copy(),
                  'joints': LEVEL_JOINTS.copy(), 'compression_m': 0.002 * pressed}
        name = draw(st.sampled_from(['none', *fields]))
        if name == 'compression_m':
            fields[name] = draw(anything())
        elif name != 'none':
            fields[name] = np.array(draw(vectors(anything(), len(fields[name]))))
        made.append(SensorWindow(**fields))
    return made


@settings(max_examples=150)
@given(windows())
def test_any_windows_give_a_unit_normal_on_the_face_or_a_clear_error(pair):
    free, pressed = pair
    try:
        estimate = estimate_normal(free, pressed)
    except ProbeError as err:
        assert 'window' in str(err)
        return
    for vector in (estimate.normal, estimate.gravity_normal):
        assert np.all(np.isfinite(vector)) and np.linalg.norm(vector) == pytest.approx(1.0)
    assert_rotation(estimate.deformation)
    assert_rotation(estimate.face_rotation)
    assert np.all(np.isfinite(estimate.face_centre))
    assert all(math.isfinite(v) for v in (estimate.deflection_rad, estimate.turn_rad,
                                          estimate.agreement_rad))
    assert np.all(np.isfinite(bearing_point(estimate)))


@example(1e300, (FLOAT64_MAX, FLOAT64_MAX, 0.0))
@settings(max_examples=150)
@given(finite(), vectors(finite()))
def test_any_finite_slope_gives_a_unit_normal_in_the_probing_plane(slope, direction):
    along = horizontal(direction)
    assert np.linalg.norm(along) == pytest.approx(1.0) and along[2] == 0.0
    normal = normal_from_slope(slope, direction)
    assert np.all(np.isfinite(normal)) and np.linalg.norm(normal) == pytest.approx(1.0)
    assert normal[2] >= 0.0
    assert float(np.dot(normal, np.cross(along, [0.0, 0.0, 1.0]))) == pytest.approx(0.0)


@given(st.sampled_from([math.nan, math.inf, -math.inf]), vectors(finite()))
def test_a_non_finite_slope_or_direction_is_a_clear_error(bad, direction):
    with pytest.raises(ProbeError, match='finite'):
        normal_from_slope(bad, direction)
    with pytest.raises(ProbeError, match='finite'):
        horizontal((bad, *direction[1:]))


@settings(max_examples=100)
@given(st.lists(vectors(st.floats(-1.0, 1.0)), max_size=5), st.floats(-1.0, 1.0),
       vectors(finite()))
def test_the_slope_of_any_points_on_the_table_is_finite(points, s, direction):
    assert math.isfinite(slope_at([np.array(p) for p in points], s, direction))


def touch(tilt: float, turn: float) -> TouchResult:
    estimate = NormalEstimate(np.zeros(3), np.zeros(3), np.eye(3), 0.0, turn, 0.0,
                              np.zeros(3), np.eye(3), 0.0)
    return TouchResult(tilt, estimate, estimate)


@settings(max_examples=150)
@given(st.lists(st.tuples(st.floats(-1.5, 1.5), finite()), min_size=1, max_size=6))
def test_the_next_tilt_after_any_touches_is_finite_and_one_bounded_step_away(touches):
    made = [touch(tilt, turn) for tilt, turn in touches]
    tilt = next_tilt(made)
    assert math.isfinite(tilt)
    assert abs(tilt - made[-1].tilt) <= MAX_TILT_STEP_RAD + 1e-12


def test_the_next_tilt_without_a_touch_is_a_clear_error():
    with pytest.raises(ValueError, match='at least one touch'):
        next_tilt([])
