# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Device time of the Teensy: uint32 microseconds unwrapped, then mapped to host time.

The mapping `host = device + offset` uses the smallest transport delay seen so far:
each sample gives `host_rx - device`, which is the true offset plus a positive delay.
The estimate follows any smaller value at once and otherwise creeps upwards at the
largest clock drift allowed, so it tracks crystals that run slow or fast without
following the jitter of USB reads. Samples that arrive in one read are stamped
together: the newest of them waited least in the buffers, so it alone updates the offset.
Stamps never go back, across reconnects and device restarts too.

Bad input and how long it lasts: a device time that jumps backwards or further than
`max_gap_s` (a restart, a corrupted frame) starts the mapping over at the next read,
whose stamps are then late by that read's transport delay only; a corrupted time ahead
by less than one sample period, followed by good ones, pulls the estimate early by less
than that period, and the creep takes it back. So from the first good read after bad
device times stop, stamps are within the larger of one sample period and the longest
transport delay (tests/tactex_sensor/test_clock_hard.py). Offsets are kept relative to the
first observation, so stamps keep nanosecond resolution at any epoch.
"""

from __future__ import annotations

from collections.abc import Sequence
import math

_WRAP_US = 1 << 32


class DeviceClock:
    """Unwrap device microseconds and stamp samples in host nanoseconds.

    Args:
        max_drift_ppm: the largest rate difference between the two clocks (ppm).
        max_gap_s: a device-time jump larger than this (forwards or backwards) is a
            device restart: the clock starts over.
    """

    def __init__(self, *, max_drift_ppm: float = 200.0, max_gap_s: float = 5.0) -> None:
        if not (math.isfinite(max_drift_ppm) and max_drift_ppm >= 0):
            raise ValueError(f'max_drift_ppm must be finite and >= 0, got {max_drift_ppm!r}')
        if not (math.isfinite(max_gap_s) and max_gap_s > 0):
            raise ValueError(f'max_gap_s must be finite and > 0, got {max_gap_s!r}')
        self._drift = max_drift_ppm * 1e-6
        self._max_gap_us = int(max_gap_s * 1e6)
        self._last_raw: int | None = None
        self._device_us = 0
        self._base_ns = 0  # the first observed offset; the estimate is kept relative to it
        self._offset_ns: float | None = None
        self._last_stamp_ns: int | None = None
        self.restarts = 0

    def reset(self) -> None:
        """Start over (after a reconnect)."""
        self._last_raw = None
        self._offset_ns = None

    def unwrap(self, raw_us: int) -> int:
        """Return the monotonic device time (us) of a raw reading (taken modulo 2^32)."""
        raw_us = int(raw_us) % _WRAP_US
        if self._last_raw is None:
            self._device_us = raw_us
        else:
            step = (raw_us - self._last_raw) % _WRAP_US
            if step > self._max_gap_us:
                # Backwards (step near 2^32) or a long silence: the device restarted.
                self.restarts += 1
                self._offset_ns = None
                self._device_us = raw_us
            else:
                self._device_us += step
        self._last_raw = raw_us
        return self._device_us

    def stamp_ns(self, raw_us: int, host_rx_ns: int) -> int:
        """Return the host time (ns) at which the sample with device time `raw_us` was taken."""
        return self.stamp_batch([raw_us], host_rx_ns)[0]

    def stamp_batch(self, raw_us: Sequence[int], host_rx_ns: int) -> list[int]:
        """Host times (ns) of samples read together at `host_rx_ns`, strictly increasing.

        When the offset estimate drops (a smaller delay was seen, or the link reconnected),
        a stamp that would not follow the previous one is placed 1 us after it.
        """
        if not raw_us:
            return []
        previous_us = self._device_us
        fresh = self._offset_ns is None
        device_us = [self.unwrap(raw) for raw in raw_us]
        if fresh or self._offset_ns is None:  # a restart inside unwrap also clears it
            previous_us = device_us[-1]
            self._offset_ns = None
        observed = int(host_rx_ns) - device_us[-1] * 1000
        if self._offset_ns is None:
            self._base_ns, self._offset_ns = observed, 0.0
        else:
            creep = self._drift * max(0, device_us[-1] - previous_us) * 1000
            self._offset_ns = min(self._offset_ns + creep, float(observed - self._base_ns))
        offset_ns = self._base_ns + math.floor(self._offset_ns)
        stamps = []
        for device in device_us:
            stamp = device * 1000 + offset_ns
            if self._last_stamp_ns is not None and stamp <= self._last_stamp_ns:
                stamp = self._last_stamp_ns + 1000
            stamps.append(stamp)
            self._last_stamp_ns = stamp
        return stamps
