# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Hard cases: the live stream's judges and the online classifier never raise or latch.

The timeline, the rate judge and the window faults take any values; the classifier goes
on whatever its model answers.
"""


from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
import numpy as np
import pytest
from support.hard_values import (
    anything,
    finite_as_float,
    FLOAT64_MAX,
    NON_FINITE,
    parsed_numbers,
)

from tactex_classify.models.checkpoint import StreamSpec
from tactex_classify.online import stream_health as health
from tactex_classify.online.live import LiveSettings, OnlineClassifier
from tactex_common.channels import CHANNELS

pytestmark = pytest.mark.hard_case

ANY_STAMPS = st.integers(-2 ** 63, 2 ** 63 - 1)
SPEC = StreamSpec(tuple(CHANNELS), 16, 8, 120.0)
PERIOD_NS = 8_333_333


@settings(max_examples=200)
@given(st.lists(ANY_STAMPS, max_size=30))
def test_the_timeline_judges_any_stamps_and_its_newest_is_one_it_kept(stamps):
    timeline = health.Timeline(jump_ns=500_000_000)
    kept = []
    for stamp in stamps:
        verdict = timeline.judge(stamp)
        assert verdict in (health.CONTINUES, health.HELD, health.RESTARTED)
        if verdict != health.HELD:
            kept.append(stamp)
        assert timeline.latest_ns is None or timeline.latest_ns in kept
        assert isinstance(timeline.near(stamp), bool)


@settings(max_examples=200)
@given(st.one_of(parsed_numbers(), st.none(), st.text(max_size=5)))
@example(10**400)  # a metadata rate written as a whole number past the float range
def test_the_rate_judge_takes_any_stated_or_measured_rate(rate):
    judge = health.RateJudge(SPEC, 0.05)
    error = judge.stated(rate)
    valid = finite_as_float(rate) and rate > 0
    assert (error == '') == valid
    if isinstance(rate, float) or rate is None:
        judge.measured(rate)
    assert isinstance(judge.refusal, str)


@settings(max_examples=150)
@given(hnp.arrays(np.float64, st.tuples(st.integers(1, 40), st.just(len(CHANNELS))),
                  elements=anything()))
def test_window_faults_of_any_values_are_named_or_empty(values):
    fault = health.window_fault(values, CHANNELS)
    assert fault in ('', 'frozen') or fault.startswith('saturated ')


@given(st.sampled_from([*NON_FINITE, FLOAT64_MAX, -1e300, 3.5e38]))
def test_a_value_beyond_float32_does_not_fit_it(value):
    assert not health.fits_float32((0.0, value))


@settings(max_examples=60, deadline=None)
@given(st.one_of(hnp.arrays(np.float64, st.tuples(st.integers(0, 3), st.integers(0, 3)),
                            elements=anything()),
                 st.just(None), st.text(max_size=3)))
@example(np.full((1, 2), -3.4028234663852886e38))  # negative probabilities (make hunt)
def test_whatever_the_model_answers_the_classifier_goes_on(answer):
    rng = np.random.default_rng(0)
    answers = iter([answer])

    def model(windows):
        given_answer = next(answers, None)
        if given_answer is None:
            return np.tile([0.2, 0.8], (len(windows), 1))
        return given_answer
    classifier = OnlineClassifier(model, SPEC, 2, live=LiveSettings(contact='always'))
    results = []
    for i in range(80):
        stamp = 10**12 + i * PERIOD_NS
        classifier.windows.add('imu', stamp, tuple(rng.normal(size=6)), stamp)
        classifier.windows.add('mag', stamp, tuple(rng.normal(size=3) * 1e-5), stamp)
        classifier.windows.add('pressure', stamp, (101_000.0,), stamp)
        results += classifier.step()
    assert results and np.all(np.isfinite(results[-1].estimate.probabilities))
