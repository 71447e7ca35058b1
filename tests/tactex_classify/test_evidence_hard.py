# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Evidence accumulation and the live window core under any probabilities, samples and stamps.

Recovery: after any run of windows (any probabilities a model can give, any stamps), the
evidence leads with the true class at most RECOVERY_WINDOWS windows after windows that
favour it clearly (0.995) begin. After any burst of bad samples (NaN, extremes, stamps
repeated, going back or jumping), the live core cuts a window of clean samples at most
RECOVERY_SAMPLES IMU samples after clean samples begin.
"""

import math

from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
import numpy as np
import pytest
from support.hard_values import anything, finite, FLOAT32_MAX, FLOAT64_MAX, vectors

from tactex_classify.models.checkpoint import StreamSpec
from tactex_classify.online.evidence import Evidence, EvidenceSettings, union_seconds
from tactex_classify.online.live import (
    LiveSettings,
    LiveWindows,
    MEDIAN_OF,
    PressureContact,
    WARMUP,
    Window,
)
from tactex_common.channels import CHANNELS

pytestmark = pytest.mark.hard_case

PERIOD_NS = 8_333_333  # 120 Hz
START_NS = 10 ** 12
RECOVERY_WINDOWS = 3
ROS_STAMPS = st.integers(-2 ** 31 * 10 ** 9, 2 ** 31 * 10 ** 9)
# What a model can answer: any non-negative finite numbers (not normalised), extremes too.
model_probabilities = st.one_of(st.sampled_from([0.0, -0.0, 5e-324, 1e-300, 1.0, 1e300]),
                                st.floats(0.0, 1.0))


def probability_vectors(classes):
    return hnp.arrays(np.float64, classes, elements=model_probabilities)


@st.composite
def window_runs(draw, max_size=12):
    classes = draw(st.integers(1, 5))
    windows = draw(st.lists(st.tuples(probability_vectors(classes), ROS_STAMPS, ROS_STAMPS),
                            max_size=max_size))
    return classes, windows


def assert_valid(estimate, classes):
    assert 0 <= estimate.class_id < classes
    assert estimate.probabilities.shape == (classes,)
    assert np.all(np.isfinite(estimate.probabilities)) and np.all(estimate.probabilities >= 0)
    assert estimate.probabilities.sum() == pytest.approx(1.0)
    assert estimate.probabilities[estimate.class_id] == estimate.probabilities.max()
    assert math.isfinite(estimate.contact_seconds) and estimate.contact_seconds >= 0


@example((2, [(np.zeros(2), 0, 0), (np.array([0.0, 1.0]), 0, -PERIOD_NS)]), 0.0, 1)
@settings(max_examples=150)
@given(window_runs(), st.floats(0.0, 1.0), st.integers(1, 4))
def test_any_windows_give_a_distribution_led_by_its_class_and_a_non_negative_time(
        run, threshold, min_windows):
    classes, windows = run
    evidence = Evidence(classes, PERIOD_NS, EvidenceSettings(threshold, min_windows))
    for proba, start, end in windows:
        assert_valid(evidence.add(proba, start, end), classes)


@settings(max_examples=100)
@given(window_runs(), st.integers(0, 4))
def test_the_evidence_follows_the_true_class_within_the_stated_windows(run, true_class):
    classes, windows = run
    true_class %= classes
    evidence = Evidence(classes, PERIOD_NS)
    for proba, start, end in windows:
        evidence.add(proba, start, end)
    clear = np.full(classes, 0.005 / max(classes - 1, 1))
    clear[true_class] = 0.995
    for index in range(RECOVERY_WINDOWS):
        estimate = evidence.add(clear, START_NS + index * PERIOD_NS,
                                START_NS + (index + 1) * PERIOD_NS)
    assert estimate.class_id == true_class


@example(3, np.array([math.nan, 0.5, 0.5]))
@settings(max_examples=100)
@given(st.integers(1, 4), st.one_of(
    hnp.arrays(np.float64, st.integers(0, 6), elements=anything()),
    hnp.arrays(np.float64, (2, 2), elements=finite())))
def test_a_window_that_is_no_distribution_is_refused_and_changes_nothing(classes, proba):
    if proba.shape == (classes,) and np.all(np.isfinite(proba)) and np.all(proba >= 0):
        return
    evidence = Evidence(classes, PERIOD_NS)
    before = evidence.add(np.full(classes, 1.0 / classes), 0, PERIOD_NS)
    with pytest.raises(ValueError, match='probabilities'):
        evidence.add(proba, PERIOD_NS, 2 * PERIOD_NS)
    after = evidence.add(np.full(classes, 1.0 / classes), PERIOD_NS, 2 * PERIOD_NS)
    assert evidence.windows == 2
    np.testing.assert_allclose(after.probabilities, before.probabilities)


@example([(0, -PERIOD_NS)])
@settings(max_examples=150)
@given(st.lists(st.tuples(ROS_STAMPS, ROS_STAMPS), max_size=8))
def test_the_union_of_any_spans_is_finite_non_negative_and_at_most_their_sum(spans):
    total = union_seconds(spans)
    assert math.isfinite(total) and total >= 0
    assert total <= sum(max(end - start, 0) for start, end in spans) * 1e-9 + 1e-9


STREAM = StreamSpec(tuple(CHANNELS), 16, 8, 1e9 / PERIOD_NS)
WIDTHS = {'imu': 6, 'mag': 3, 'pressure': 1}
# Warm-up, then a window; the gap rule's median may take as long again to see the new rate.
RECOVERY_SAMPLES = WARMUP + 3 * STREAM.window
stamp_steps = st.one_of(st.sampled_from([0, -1, -PERIOD_NS, 10 ** 15]),
                        st.integers(0, 4 * PERIOD_NS))


@st.composite
def bad_samples(draw):
    role = draw(st.sampled_from(sorted(WIDTHS)))
    return role, draw(stamp_steps), draw(vectors(anything(), WIDTHS[role]))


def feed(core, stamp, samples):
    """Add (role, stamp step, values) samples, polling after each; return events, stamp."""
    events = []
    for role, step, values in samples:
        stamp += step
        core.add(role, stamp, values, stamp)
        events += core.poll()
    return events, stamp


def clean_samples(count):
    rng = np.random.default_rng(0)
    samples = []
    for _ in range(count):
        samples.append(('imu', PERIOD_NS, tuple(rng.normal(size=6))))
        samples.append(('mag', 0, tuple(rng.normal(size=3))))
        samples.append(('pressure', 0, (101325.0 + rng.normal(),)))
    return samples


def assert_window(event):
    assert event.values.shape == (STREAM.window, len(STREAM.channels))
    assert np.all(np.isfinite(event.values))
    assert event.start_ns <= event.end_ns


@settings(max_examples=80, deadline=None)
@given(st.lists(bad_samples(), max_size=40), st.sampled_from(['always', 'pressure']))
def test_the_live_core_cuts_only_finite_whole_windows_from_any_samples(samples, contact):
    core = LiveWindows(STREAM, LiveSettings(contact=contact))
    events, _ = feed(core, START_NS, samples)
    for event in events:
        if isinstance(event, Window):
            assert_window(event)
    assert all(count >= 0 for count in core.counts.values())


@settings(max_examples=40, deadline=None)
@given(st.lists(bad_samples(), min_size=1, max_size=40))
def test_the_live_core_cuts_clean_windows_within_the_stated_samples_after_bad_ones(samples):
    core = LiveWindows(STREAM, LiveSettings(contact='always'))
    _, stamp = feed(core, START_NS, samples)
    newest = max([stamp] + [core.latest_ns(role) or stamp for role in WIDTHS])
    events, _ = feed(core, newest, clean_samples(RECOVERY_SAMPLES))
    windows = [e for e in events if isinstance(e, Window) and e.start_ns > newest]
    assert windows
    assert_window(windows[0])


def pressure_rule(readings, start_ns=0):
    settings = LiveSettings()
    rule = PressureContact(settings.contact_pa, settings.baseline_tau_s)
    feed_pressures(rule, readings, start_ns)
    return rule


def feed_pressures(rule, readings, start_ns):
    """Readings one period apart from the period after `start_ns`; return the last stamp."""
    stamps = start_ns + PERIOD_NS * np.arange(1, len(readings) + 1)
    rule.update(stamps, np.array(readings, dtype=float))
    return int(stamps[-1]) if len(readings) else start_ns


@example([(0, -FLOAT64_MAX), (10 ** 9, FLOAT64_MAX), (2 * 10 ** 9, 0.0)])
@settings(max_examples=100)
@given(st.lists(st.tuples(ROS_STAMPS, anything()), max_size=20))
def test_the_pressure_baseline_stays_finite_after_any_readings(readings):
    settings = LiveSettings()
    rule = PressureContact(settings.contact_pa, settings.baseline_tau_s)
    for stamp, pressure in readings:
        rule.update(np.array([stamp]), np.array([pressure]))
    assert rule.baseline is None or math.isfinite(rule.baseline)


@settings(max_examples=100)
@given(st.lists(st.tuples(st.integers(0, 19), anything()), max_size=8))
def test_single_wild_readings_leave_the_pressure_baseline_where_it_was(wild):
    readings = [101325.0] * 60
    for position, value in wild:  # at most one wild reading in any three
        readings[3 * position + 1] = value
    rule = pressure_rule(readings)
    assert not rule.touching and rule.baseline == pytest.approx(101325.0, abs=1e-6)
    press = [101325.0 + 2 * rule.contact_pa] * 3
    feed_pressures(rule, press, 60 * PERIOD_NS)
    assert rule.touching


@example([FLOAT32_MAX])
@settings(max_examples=100)
@given(st.lists(st.floats(101325.0, allow_infinity=False), max_size=20))
def test_the_pressure_rule_forgets_any_high_readings_at_the_next_free_air_ones(readings):
    rule = pressure_rule(readings)
    stamp = feed_pressures(rule, [101325.0] * MEDIAN_OF, len(readings) * PERIOD_NS)
    assert not rule.touching and abs(rule.baseline - 101325.0) <= rule.contact_pa / 2
    feed_pressures(rule, [101325.0 + 2 * rule.contact_pa] * 3, stamp)
    assert rule.touching


@pytest.mark.parametrize('threshold', [0.5, 0.99])
def test_an_estimate_carries_the_python_types_a_ros_message_takes(threshold):
    # A TextureEstimate's bool field refuses numpy.bool_: rclpy's generated C code asserts
    # PyBool_Check, and under a colcon build (assertions kept) classifier_node aborted.
    evidence = Evidence(2, PERIOD_NS, EvidenceSettings(threshold=threshold, min_windows=1))
    for index in range(3):
        estimate = evidence.add(np.array([0.9, 0.1]), index * PERIOD_NS, (index + 1) * PERIOD_NS)
        assert type(estimate.decided) is bool
        assert type(estimate.class_id) is int and type(estimate.contact_seconds) is float
