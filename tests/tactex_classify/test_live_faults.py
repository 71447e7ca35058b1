# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The online classifier survives every fault of a live stream, counts it, and recovers.

Bad numbers, clock jumps, an off rate, frozen and saturated streams, a failing model:
each is counted, and the next good window is classified.
"""

import math

import numpy as np
import pytest

from tactex_classify.models.checkpoint import StreamSpec
from tactex_classify.online.evidence import EvidenceSettings
from tactex_classify.online.live import LiveSettings, OnlineClassifier
from tactex_classify.online.stream_health import (
    CONTINUES,
    HELD,
    RateJudge,
    RESTARTED,
    Timeline,
    window_fault,
)
from tactex_common import chips
from tactex_common.channels import CHANNELS

RATE_HZ = 120.0
PERIOD_NS = 8_333_333
START_NS = 10**12
SPEC = StreamSpec(tuple(CHANNELS), 32, 16, RATE_HZ)
WARMUP_AND_WINDOW = 8 + SPEC.window  # samples from a fresh start to the first window


def texture_model(windows):
    """A stand-in model: class 1 when ax averages above 0.5, confidently."""
    high = windows[:, :, 0].mean(axis=1) > 0.5
    proba = np.full((len(windows), 2), 0.005)
    proba[np.arange(len(windows)), high.astype(int)] = 0.995
    return proba


class Stream:
    """A 10-channel stream of texture 1 (ax 1.0) with chip noise, fed to a classifier."""

    def __init__(self, classifier, seed=0):
        self.classifier, self.rng = classifier, np.random.default_rng(seed)
        self.stamp, self.results = START_NS, []

    def sample(self, *, imu=None, stamp=None, step=PERIOD_NS):
        """One sample on every topic, then a step of the classifier; returns its results."""
        self.stamp = self.stamp + step if stamp is None else stamp
        noise = self.rng.normal(0, 0.01, 10)
        values = {'imu': imu if imu is not None else tuple(noise[:6] + (1.0, 0, 9.8, 0, 0, 0)),
                  'mag': tuple(noise[6:9] * 1e-6 + 2e-5), 'pressure': (101_300.0 + noise[9],)}
        for role, value in values.items():
            self.classifier.windows.add(role, self.stamp, value, self.stamp)
        results = self.classifier.step()
        self.results += results
        return results

    def run(self, count, **kwargs):
        return [r for _ in range(count) for r in self.sample(**kwargs)]


def online(**live):
    return OnlineClassifier(texture_model, SPEC, 2,
                            live=LiveSettings(contact='always', **live),
                            evidence=EvidenceSettings(threshold=0.99), newest_only=False)


def test_a_sample_beyond_float32_is_dropped_and_counted_and_the_next_window_classified():
    classifier = online()
    stream = Stream(classifier)
    stream.run(100)
    stream.sample(imu=(1e300, 0.0, 9.8, 0.0, 0.0, 0.0))
    after = stream.run(SPEC.window + SPEC.hop)
    assert classifier.windows.counts['invalid'] == 1
    assert after and all(r.estimate.class_id == 1 for r in after)


@pytest.mark.parametrize('failure', ['raises', 'NaN', 'wrong shape'])
def test_a_model_call_that_fails_skips_its_window_counts_it_and_the_next_is_classified(failure):
    calls = []

    def flaky(windows):
        calls.append(len(windows))
        if len(calls) == 3:
            if failure == 'raises':
                raise RuntimeError('out of memory')
            return np.full((len(windows), 2), np.nan) if failure == 'NaN' else np.ones(3)
        return texture_model(windows)
    classifier = OnlineClassifier(flaky, SPEC, 2, live=LiveSettings(contact='always'))
    stream = Stream(classifier)
    stream.run(SPEC.window + 4 * SPEC.hop)
    assert classifier.faults['model_errors'] == 1
    assert len(stream.results) == len(calls) - 1 >= 3
    assert classifier.last_fault == ''  # a later window was classified


def test_one_future_stamped_sample_is_dropped_and_the_stream_goes_on_unbroken():
    classifier = online()
    stream = Stream(classifier)
    stream.run(100)
    windows_before = classifier.windows.counts['windows']
    stream.sample(stamp=stream.stamp + 3600 * 10**9)  # one sample an hour ahead
    stream.stamp -= 3600 * 10**9
    stream.run(SPEC.hop * 2)
    counts = classifier.windows.counts
    assert counts['off_timeline'] == 3 and counts['resyncs'] == 0  # its three topics
    assert counts['late'] == 0 and counts['windows'] > windows_before


@pytest.mark.parametrize('jump_s', [-30.0, -0.6, 0.6, 86_400.0])
def test_stamps_that_jump_and_stay_restart_the_stream_counted_and_classification_resumes(
        jump_s):
    classifier = online()
    stream = Stream(classifier)
    stream.run(200)
    assert stream.results[-1].estimate.decided
    stream.sample(stamp=stream.stamp + int(jump_s * 1e9))  # the simulator restarted
    after = stream.run(WARMUP_AND_WINDOW + 2)
    assert classifier.windows.counts['resyncs'] == 1
    assert classifier.resets.get('stamps jumped') == 1
    assert after and len(after[0].estimate.spans_ns) == 1  # evidence started again
    assert after[-1].estimate.class_id == 1


def test_old_samples_arriving_after_a_restart_do_not_switch_the_timeline_back():
    classifier = online()
    stream = Stream(classifier)
    stream.run(100)
    old = stream.stamp
    stream.sample(stamp=old - 30 * 10**9)
    stream.run(5)
    for k in range(1, 4):  # three old magnetometer samples still in flight
        classifier.windows.add('mag', old + k * PERIOD_NS, (2e-5, 0, 0), old)
    stream.run(WARMUP_AND_WINDOW)
    assert classifier.windows.counts['resyncs'] == 1
    assert classifier.windows.counts['off_timeline'] >= 3


def burst_stamps(stream, count):
    """`count` samples stamped 0.1 ms apart (a driver that stamps a buffered burst)."""
    return stream.run(count, step=100_000)


def test_a_burst_refuses_the_stream_only_while_its_rate_is_off_then_it_resumes():
    classifier = online()
    stream = Stream(classifier)
    stream.run(300)
    burst_stamps(stream, 200)
    assert classifier.faults['refused'] > 0 and 'rate' in classifier.last_fault
    refused = classifier.faults['refused']
    after = stream.run(400)
    assert after and after[-1].estimate.decided and after[-1].estimate.class_id == 1
    assert classifier.faults['refused'] == refused
    assert classifier.rate.refusal == ''


def test_twenty_milliseconds_of_stamp_jitter_never_refuses_the_stream():
    classifier = online()
    stream = Stream(classifier)
    rng = np.random.default_rng(1)
    base = START_NS
    for i in range(800):
        stream.sample(stamp=base + i * PERIOD_NS + int(rng.uniform(-10e6, 10e6)))
    assert classifier.faults['refused'] == 0
    assert stream.results and stream.results[-1].estimate.class_id == 1


@pytest.mark.parametrize('rate', [-5, 0, math.nan, math.inf, '120', None, True])
def test_a_stated_rate_that_is_no_rate_is_a_clear_error_naming_it_and_changes_nothing(rate):
    classifier = online()
    error = classifier.rate.stated(rate)
    assert f'sensor_rate_hz {rate!r} is not a rate' in error
    stream = Stream(classifier)
    assert stream.run(100) and classifier.faults['refused'] == 0


def test_a_stated_rate_off_the_models_refuses_until_the_stamps_say_otherwise():
    judge = RateJudge(SPEC, 0.05)
    assert judge.stated(350.0) == ''
    assert 'trained at 120 Hz, the stream runs at 350 Hz' in judge.refusal
    judge.measured(121.0)
    assert judge.refusal == ''


def test_the_rate_judge_has_hysteresis():
    judge = RateJudge(SPEC, 0.10)
    judge.measured(120.0)
    judge.measured(140.0)  # 17 % off: refused
    assert judge.refusal
    judge.measured(130.0)  # 8 %: within the tolerance, not within half of it
    assert judge.refusal
    judge.measured(125.0)  # 4 %: back
    assert judge.refusal == ''
    judge.measured(130.0)  # 8 %: stays accepted
    assert judge.refusal == ''


def test_a_frozen_stream_gives_no_decision_and_says_so_then_a_live_one_is_decided():
    classifier = online()
    stream = Stream(classifier)
    frozen = (1.0, 0.0, 9.8, 0.01, 0.0, 0.0)
    results = stream.run(300, imu=frozen)
    assert not results and classifier.faults['frozen'] > 0
    assert classifier.last_fault == 'frozen window'
    after = stream.run(SPEC.window + 2 * SPEC.hop)
    assert after and after[-1].estimate.decided


def test_a_saturated_gyro_gives_no_decision_and_names_the_channel():
    classifier = online()
    stream = Stream(classifier)
    rail = chips.gyro_range(245).rails_si[1]
    results = []
    for i in range(300):
        results += stream.sample(imu=(1.0 + 0.01 * (i % 3), 0.0, 9.8, 0.0, rail, 0.0))
    assert not results and classifier.faults['saturated'] > 0
    assert classifier.last_fault == 'saturated gy window'


def test_values_beyond_a_rail_that_vary_are_not_saturation():
    values = np.random.default_rng(0).normal(0, 1, (32, 10))
    values[:, 4] = np.linspace(50.0, 60.0, 32)  # beyond every gyro range, never repeated
    assert window_fault(values, CHANNELS) == ''


def test_a_pressure_only_window_at_rest_is_not_frozen():
    assert window_fault(np.full((32, 1), 101_300.0), ('baro',)) == ''


def test_the_timeline_holds_one_outlier_and_restarts_on_three_agreeing_stamps():
    timeline = Timeline(jump_ns=500_000_000)
    assert timeline.judge(0) == CONTINUES
    assert timeline.judge(10 * 10**9) == HELD
    assert timeline.judge(PERIOD_NS) == CONTINUES  # the outlier is forgotten
    assert [timeline.judge(-10**9 + k * PERIOD_NS) for k in range(3)] == [HELD, HELD,
                                                                           RESTARTED]
    assert timeline.near(-10**9 + 3 * PERIOD_NS) and not timeline.near(PERIOD_NS * 100)
