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
"""

from __future__ import annotations

from collections.abc import Sequence

_WRAP_US = 1 << 32


class DeviceClock:
    """Unwrap device microseconds and stamp samples in host nanoseconds.

    Args:
        max_drift_ppm: the largest rate difference between the two clocks (ppm).
        max_gap_s: a device-time jump larger than this (forwards or backwards) is a
            device restart: the clock starts over.
    """

    def __init__(self, *, max_drift_ppm: float = 200.0, max_gap_s: float = 5.0) -> None:
        if max_drift_ppm < 0 or max_gap_s <= 0:
            raise ValueError(f'need max_drift_ppm >= 0 and max_gap_s > 0, got '
                             f'{max_drift_ppm!r}, {max_gap_s!r}')
        self._drift = max_drift_ppm * 1e-6
        self._max_gap_us = int(max_gap_s * 1e6)
        self._last_raw: int | None = None
        self._device_us = 0
        self._offset_ns: float | None = None
        self._last_stamp_ns: int | None = None
        self.restarts = 0

    def reset(self) -> None:
        """Start over (after a reconnect)."""
        self._last_raw = None
        self._offset_ns = None

    def unwrap(self, raw_us: int) -> int:
        """Return the monotonic device time (us) of a raw uint32 reading."""
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
        observed = float(host_rx_ns - device_us[-1] * 1000)
        if self._offset_ns is None:
            self._offset_ns = observed
        else:
            creep = self._drift * max(0, device_us[-1] - previous_us) * 1000
            self._offset_ns = min(self._offset_ns + creep, observed)
        stamps = []
        for device in device_us:
            stamp = device * 1000 + int(self._offset_ns)
            if self._last_stamp_ns is not None and stamp <= self._last_stamp_ns:
                stamp = self._last_stamp_ns + 1000
            stamps.append(stamp)
            self._last_stamp_ns = stamp
        return stamps
