# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Device clock: unwrapping uint32 microseconds, and a drift-tolerant host-time mapping."""

import numpy as np
import pytest

from tactex_sensor.clock import DeviceClock


def test_unwrap_continues_across_the_uint32_wrap():
    clock = DeviceClock()
    start = (1 << 32) - 5000
    assert clock.unwrap(start) == start
    assert clock.unwrap(3000) == start + 8000


def test_backwards_jump_is_a_restart():
    clock = DeviceClock()
    clock.unwrap(10_000_000)
    clock.unwrap(1_000)
    assert clock.restarts == 1


@pytest.mark.parametrize('drift_ppm', [-150.0, 0.0, 150.0])
def test_stamps_track_the_true_sample_time_despite_drift_and_jitter(drift_ppm):
    rng = np.random.default_rng(3)
    clock = DeviceClock(max_drift_ppm=200.0)
    rate_hz = 350.0
    errors = []
    for i in range(350 * 120):  # two minutes, crossing nothing but drift
        true_s = i / rate_hz
        device_us = int(true_s * (1 + drift_ppm * 1e-6) * 1e6 + 4_294_000_000) % (1 << 32)
        delay_s = 0.0005 + rng.exponential(0.002)  # USB latency with a floor of 0.5 ms
        host_rx_ns = int((true_s + 1000.0 + delay_s) * 1e9)
        stamp_ns = clock.stamp_ns(device_us, host_rx_ns)
        errors.append(stamp_ns * 1e-9 - (true_s + 1000.0))
    settled = np.abs(np.array(errors[350 * 5:]))
    # Error stays within the latency floor plus a little, never the jitter (~2 ms).
    assert settled.max() < 1.5e-3
    assert np.all(np.diff(errors) < 1e-3)


def test_invalid_settings_are_rejected():
    with pytest.raises(ValueError, match='max_gap_s'):
        DeviceClock(max_gap_s=0)


def test_a_buffered_burst_is_stamped_at_the_sample_period_not_at_its_arrival():
    clock = DeviceClock()
    period_us = 2857
    raw = [1_000_000 + i * period_us for i in range(40)]  # 40 frames waited in the buffer
    arrival_ns = 5_000_000_000 + raw[-1] * 1000
    stamps = np.array(clock.stamp_batch(raw, arrival_ns))
    assert np.all(np.diff(stamps) == period_us * 1000)
    assert stamps[-1] == arrival_ns  # the smallest delay seen so far counts as none


def test_stamps_never_go_back_across_a_reconnect_with_a_late_first_read():
    clock = DeviceClock()
    period_us, true_offset_ns = 5000, 7 * 10**9
    stamps = []
    device = 1_000_000
    for _ in range(200):  # steady stream, 0.3 ms transport delay
        device += period_us
        stamps += clock.stamp_batch([device], device * 1000 + true_offset_ns + 300_000)
    clock.reset()  # unplugged for 1 s
    device += 1_000_000
    burst = [device + i * period_us for i in range(30)]  # the first read after it comes late
    stamps += clock.stamp_batch(burst, burst[-1] * 1000 + true_offset_ns + 80_000_000)
    device = burst[-1]
    for _ in range(200):  # then the normal delay again: the offset estimate drops 80 ms
        device += period_us
        stamps += clock.stamp_batch([device], device * 1000 + true_offset_ns + 300_000)
    assert np.all(np.diff(stamps) > 0)
    assert stamps[-1] == device * 1000 + true_offset_ns + 300_000
