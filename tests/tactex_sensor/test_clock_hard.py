# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Device clock under any device times, and how soon it recovers from bad ones.

Recovery: from the first good sample after bad device times stop, stamps are within the
larger of one sample period and the longest transport delay (here 3 ms).
"""

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest

from tactex_sensor.clock import DeviceClock

pytestmark = pytest.mark.hard_case

RATE_HZ = 350.0
PERIOD_US = 1e6 / RATE_HZ
EPOCH_NS = 1_763_000_000 * 10**9  # a 2025 host clock: stamps need 61 bits
MAX_DELAY_S = 0.003
raw_times = st.one_of(st.integers(0, 2**32 - 1), st.integers(-2**63, 2**63),
                      st.sampled_from([0, 2**32 - 1, 2**31]))


@settings(max_examples=100)
@given(st.lists(st.tuples(raw_times, st.integers(0, 10**7)), max_size=40))
def test_stamps_increase_and_are_never_later_than_their_arrival(readings):
    clock = DeviceClock()
    host_ns = EPOCH_NS
    previous = None
    for raw_us, wait_ns in readings:
        host_ns += wait_ns
        stamp = clock.stamp_ns(raw_us, host_ns)
        # Later than the arrival only by the 1 us that keeps the stamps increasing.
        assert stamp <= (host_ns if previous is None else max(host_ns, previous + 1000))
        assert previous is None or stamp > previous
        previous = stamp


@settings(max_examples=100)
@given(st.lists(st.integers(0, 2**32 - 1), max_size=40))
def test_unwrapped_time_never_runs_backwards(raw_times_us):
    clock = DeviceClock()
    unwrapped = [clock.unwrap(raw) for raw in raw_times_us]
    for before, after, raw in zip(unwrapped, unwrapped[1:], raw_times_us[1:], strict=False):
        assert after >= before or after == raw  # only a restart starts over


@settings(max_examples=60)
@given(st.lists(st.tuples(raw_times, st.floats(0.0, MAX_DELAY_S)), min_size=1, max_size=30),
       st.integers(0, 2**32 - 1), st.floats(-150.0, 150.0), st.integers(0, 2**32))
def test_stamps_recover_within_the_stated_time_after_bad_device_times_stop(
        bad, start_us, drift_ppm, seed):
    rng = np.random.default_rng(seed)
    clock = DeviceClock(max_drift_ppm=200.0)
    errors = []
    sample = 0

    def good(count: int) -> None:
        nonlocal sample
        for _ in range(count):
            true_s = sample / RATE_HZ
            device_us = int(start_us + true_s * (1 + drift_ppm * 1e-6) * 1e6) % 2**32
            host_ns = EPOCH_NS + int((true_s + rng.uniform(0.0002, MAX_DELAY_S)) * 1e9)
            errors.append((clock.stamp_ns(device_us, host_ns) - EPOCH_NS) * 1e-9 - true_s)
            sample += 1

    good(350)
    for raw_us, lateness_s in bad:  # corrupted device times at plausible host times
        sample += 1
        clock.stamp_ns(raw_us, EPOCH_NS + int((sample / RATE_HZ + lateness_s) * 1e9))
    errors.clear()
    good(350)
    # Plus one microsecond: the device counts whole microseconds.
    assert np.abs(errors).max() <= max(PERIOD_US * 1e-6, MAX_DELAY_S) + 1e-6


@pytest.mark.parametrize('setting', [dict(max_drift_ppm=float('nan')),
                                     dict(max_gap_s=float('inf')), dict(max_gap_s=0.0),
                                     dict(max_drift_ppm=-1.0)])
def test_settings_that_are_not_finite_or_out_of_range_are_refused(setting):
    with pytest.raises(ValueError, match=f'{next(iter(setting))} must be finite'):
        DeviceClock(**setting)


@given(st.integers(0, 2**32 - 1), st.integers(0, 10**6))
def test_stamps_keep_nanosecond_resolution_at_any_epoch(start_us, step_ns):
    clock = DeviceClock(max_drift_ppm=0.0)
    clock.stamp_ns(start_us, EPOCH_NS)
    # One microsecond later on both clocks, with no extra delay: exactly 1000 ns later.
    assert clock.stamp_ns(start_us + 1, EPOCH_NS + 1000 + step_ns) == EPOCH_NS + 1000
