# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The Teensy stream without ROS: serial link -> decoder -> host-stamped samples, plus health."""

from __future__ import annotations

from collections.abc import Callable
import math

from tactex_sensor.clock import DeviceClock
from tactex_sensor.link import LinkState, SerialLink
from tactex_sensor.protocol import FrameDecoder, Sample

CHANNEL_GROUPS = ('accel', 'gyro', 'mag', 'pressure', 'temperature')


class TeensyReader:
    """Poll the link, decode frames and stamp each sample in host time.

    Args:
        link: the serial link.
        now_ns: host clock (ns) read when bytes arrive.
    """

    def __init__(self, link: SerialLink, now_ns: Callable[[], int]) -> None:
        self.link = link
        self._now_ns = now_ns
        self.decoder = FrameDecoder()
        self.clock = DeviceClock()
        self.nan_samples = dict.fromkeys(CHANNEL_GROUPS, 0)
        self._connects_seen = 0
        self._rate_frames = 0
        self._rate_time_ns: int | None = None
        self._nan_seen = dict(self.nan_samples)

    def poll(self) -> list[tuple[int, Sample]]:
        """Read what is available and return (stamp_ns, sample) pairs."""
        data = self.link.read()
        if self.link.connects != self._connects_seen:
            # A new connection: partial frames and sequence history are void.
            self._connects_seen = self.link.connects
            self.decoder.reset_sequence()
            self.clock.reset()
        if not data:
            return []
        received_ns = self._now_ns()
        samples = self.decoder.feed(data)
        for sample in samples:
            self._count_nan(sample)
        stamps = self.clock.stamp_batch([s.device_time_us for s in samples], received_ns)
        return list(zip(stamps, samples, strict=True))

    def _count_nan(self, sample: Sample) -> None:
        for group, values in (('accel', sample.accel), ('gyro', sample.gyro),
                              ('mag', sample.mag), ('pressure', (sample.pressure_pa,)),
                              ('temperature', (sample.temperature_c,))):
            if not all(math.isfinite(v) for v in values):
                self.nan_samples[group] += 1

    def health(self) -> tuple[bool, str, dict[str, str]]:
        """Return (ok, summary, key/values) for diagnostics; resets the rate window."""
        now = self._now_ns()
        frames = self.decoder.stats.frames
        rate = 0.0
        if self._rate_time_ns is not None and now > self._rate_time_ns:
            rate = (frames - self._rate_frames) * 1e9 / (now - self._rate_time_ns)
        self._rate_frames, self._rate_time_ns = frames, now
        values = {'port': self.link.port, 'link': self.link.state.value,
                  'rate_hz': f'{rate:.1f}', 'connects': str(self.link.connects),
                  'disconnects': str(self.link.disconnects),
                  'last_error': self.link.last_error,
                  'clock_restarts': str(self.clock.restarts)}
        values.update({k: str(v) for k, v in self.decoder.stats.as_dict().items()})
        values.update({f'nan_{k}': str(v) for k, v in self.nan_samples.items()})
        if self.link.state is not LinkState.CONNECTED:
            return False, f'disconnected: {self.link.last_error}', values
        if rate == 0.0:
            return False, 'connected, no frames', values
        broken = [k for k, v in self.nan_samples.items() if v > self._nan_seen[k]]
        self._nan_seen = dict(self.nan_samples)
        summary = f'streaming at {rate:.0f} Hz'
        if broken:
            summary += f'; NaN samples on {", ".join(broken)} since the last report'
        return not broken, summary, values
