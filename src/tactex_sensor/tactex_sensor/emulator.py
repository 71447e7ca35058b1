# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Teensy emulator on a pseudo-terminal: real frames at a real rate, with faults on request.

The emulator owns a pty pair and a stable symlink to its slave side, so a reader opens
one path for the whole session, as it would a udev name, even across a simulated
disconnect (the pty is closed, and a new one appears behind the same link later).
"""

from __future__ import annotations

from dataclasses import dataclass
import enum
import errno
import math
import os
from pathlib import Path
import time

import numpy as np

from tactex_common import chips
from tactex_common.channels import CHANNELS
from tactex_common.constants import (
    EARTH_FIELD_T,
    FLOAT32_MAX,
    SEA_LEVEL_PRESSURE_PA,
    STANDARD_GRAVITY_M_S2,
)
from tactex_common.pty_link import PtyLink
from tactex_common.tables import read_table
from tactex_sensor.protocol import encode, Sample


class FaultKind(enum.Enum):
    """Faults the emulator can inject."""

    GARBAGE = 'garbage'  # ARG random bytes between two frames
    CRC = 'crc'  # the next ARG frames carry a wrong checksum
    DROP = 'drop'  # the next ARG frames are never sent
    STALL = 'stall'  # nothing is sent for ARG seconds, then the stream resumes
    DISCONNECT = 'disconnect'  # the device vanishes for ARG seconds


_DEFAULT_ARG = {FaultKind.GARBAGE: 64, FaultKind.CRC: 1, FaultKind.DROP: 1,
                FaultKind.STALL: 0.5, FaultKind.DISCONNECT: 1.0}
# The largest argument of each kind: a megabyte of garbage, a million frames, a day.
_MAX_ARG = {FaultKind.GARBAGE: 1_000_000, FaultKind.CRC: 1_000_000, FaultKind.DROP: 1_000_000,
            FaultKind.STALL: 86_400.0, FaultKind.DISCONNECT: 86_400.0}


@dataclass(frozen=True)
class Fault:
    """A fault of `kind` at `at_s` seconds after start, with its argument."""

    kind: FaultKind
    at_s: float
    arg: float

    @classmethod
    def parse(cls, spec: str) -> Fault:
        """Parse `KIND@SECONDS[:ARG]`, e.g. `garbage@2:100`, `disconnect@5:1.5`.

        Raises:
            ValueError: the spec is malformed; the message lists the kinds.
        """
        kinds = ', '.join(k.value for k in FaultKind)
        try:
            name, _, rest = spec.partition('@')
            kind = FaultKind(name)
            at, _, arg = rest.partition(':')
            fault = cls(kind, float(at), float(arg) if arg else float(_DEFAULT_ARG[kind]))
        except ValueError:
            raise ValueError(f'bad fault {spec!r}: expected KIND@SECONDS[:ARG] with KIND '
                             f'one of {kinds}') from None
        if not (math.isfinite(fault.at_s) and fault.at_s >= 0 and math.isfinite(fault.arg)
                and fault.arg >= 0):
            raise ValueError(f'bad fault {spec!r}: time and argument must be finite and >= 0')
        if fault.arg > _MAX_ARG[kind]:
            raise ValueError(f'bad fault {spec!r}: the argument of {kind.value} is at most '
                             f'{_MAX_ARG[kind]:g}')
        return fault


class Motion(enum.Enum):
    """Signal sources."""

    STATIC = 'static'  # motionless, tilted by the given roll and pitch
    SWAY = 'sway'  # compliant-body tilt of a few degrees at 2 Hz plus texture vibration


class SignalSource:
    """Physically consistent samples of a sensor at rest or swaying, with noise."""

    def __init__(self, motion: Motion = Motion.STATIC, *, roll_rad: float = 0.0,
                 pitch_rad: float = 0.0, seed: int = 0) -> None:
        self.motion = motion
        self.roll = roll_rad
        self.pitch = pitch_rad
        self._rng = np.random.default_rng(seed)

    def sample(self, t_s: float) -> tuple[tuple, tuple, tuple, float, float]:
        """Return accel, gyro, mag, pressure, temperature at time `t_s`."""
        roll, pitch, roll_rate, pitch_rate = self.roll, self.pitch, 0.0, 0.0
        vibration = np.zeros(3)
        if self.motion is Motion.SWAY:
            amplitude, omega = math.radians(3.0), 2 * math.pi * 2.0
            roll += amplitude * math.sin(omega * t_s)
            roll_rate = amplitude * omega * math.cos(omega * t_s)
            pitch += amplitude * math.sin(0.7 * omega * t_s)
            pitch_rate = amplitude * 0.7 * omega * math.cos(0.7 * omega * t_s)
            vibration = np.array([0.4, 0.4, 0.8]) * math.sin(2 * math.pi * 60.0 * t_s)
        cr, sr, cp, sp = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch)
        # World -> sensor rotation of a roll-pitch attitude (R^T of Ry(pitch) Rx(roll)).
        world_to_sensor = np.array([[cp, 0.0, -sp], [sr * sp, cr, sr * cp],
                                    [cr * sp, -sr, cr * cp]])
        gravity = (0.0, 0.0, STANDARD_GRAVITY_M_S2)
        accel = world_to_sensor @ gravity + vibration + self._rng.normal(0, 0.02, 3)
        gyro = np.array([roll_rate, pitch_rate * cr, -pitch_rate * sr]) \
            + self._rng.normal(0, 0.002, 3)
        mag = world_to_sensor @ EARTH_FIELD_T + self._rng.normal(0, 2e-7, 3)
        pressure = SEA_LEVEL_PRESSURE_PA + 150.0 * (1.0 + math.sin(0.5 * t_s)) \
            + self._rng.normal(0, 2.0)
        temperature = 24.0 + 0.01 * t_s
        return tuple(accel), tuple(gyro), tuple(mag), pressure, temperature


REPLAY_COLUMNS = ('t',) + CHANNELS


def reported(accel, gyro, mag, pressure: float, temperature: float
             ) -> tuple[tuple, tuple, tuple, float, float]:
    """A sample as the firmware reports it: each chip's configured range and resolution."""
    return (tuple(chips.quantise(accel, chips.accel_range().lsb_si)),
            tuple(chips.quantise(gyro, chips.gyro_range().lsb_si)),
            tuple(chips.quantise(mag, chips.mag_range().lsb_si)),
            float(chips.quantise_pressure(pressure)), temperature)


class ReplaySource:
    """Samples replayed from a recorded CSV, interpolated at the emulator's times.

    The header names at least t, ax, ay, az, gx, gy, gz, mx, my, mz, baro (SI units, t in
    s) and optionally temp.

    Values are linearly interpolated and the recording loops.

    Raises:
        ValueError: an unreadable table (`tactex_common.errors.TableError`), a missing
            column, t not increasing, or under 2 rows.
    """

    def __init__(self, path: Path) -> None:
        table = read_table(path)
        missing = [c for c in REPLAY_COLUMNS if c not in table.columns]
        if missing:
            raise ValueError(f'{path}: missing column(s) {", ".join(missing)}; need '
                             f'{", ".join(REPLAY_COLUMNS)} (+ optional temp)')
        if len(table) < 2:
            raise ValueError(f'{path}: needs at least 2 rows, has {len(table)}')
        names = list(REPLAY_COLUMNS[1:]) + (['temp'] if 'temp' in table.columns else [])
        t = table.numeric('t')
        with np.errstate(over='ignore', invalid='ignore'):  # a span past float: refused
            steps, span = np.diff(t), t[-1] - t[0]
        if not np.all(np.isfinite(t)) or np.any(steps <= 0) or not np.isfinite(span):
            raise ValueError(f'{path}: column t must be finite and strictly increasing (a '
                             'finite span)')
        self._t = t - t[0]
        self._period = self._t[-1]
        self._values = np.stack([table.numeric(name) for name in names], axis=1)
        if 'temp' in names and np.any(np.abs(self._values[:, -1]) > FLOAT32_MAX):
            raise ValueError(f"{path}: column temp holds values beyond the frame's float32 "
                             f'(at most {FLOAT32_MAX:.3g})')

    def sample(self, t_s: float) -> tuple[tuple, tuple, tuple, float, float]:
        """Return accel, gyro, mag, pressure, temperature at time `t_s` (looping)."""
        t = t_s % self._period if self._period > 0 else 0.0
        row = [float(np.interp(t, self._t, column)) for column in self._values.T]
        temperature = row[10] if len(row) > 10 else 24.0
        return tuple(row[0:3]), tuple(row[3:6]), tuple(row[6:9]), row[9], temperature


class TeensyEmulator:
    """Stream protocol frames on a pty at `rate_hz`, injecting `faults`.

    Args:
        link: path of the symlink that points at the current pty.
        rate_hz: frames per second.
        source: where samples come from.
        faults: faults to inject, by time.
        start_time_us: device clock at start (near 2**32 to test the wrap).
    """

    def __init__(self, link: Path, rate_hz: float, source: SignalSource | ReplaySource, *,
                 faults: tuple[Fault, ...] = (), start_time_us: int = 0) -> None:
        if not (math.isfinite(rate_hz) and 0 < rate_hz <= 2000):
            raise ValueError(f'rate_hz must be in (0, 2000], got {rate_hz!r}')
        self.link = Path(link)
        self.rate_hz = rate_hz
        self.source = source
        self._faults = sorted(faults, key=lambda f: f.at_s)
        self._start_time_us = start_time_us
        self._pty = PtyLink(self.link)
        self.frames_sent = 0
        self.frames_overflowed = 0
        self._rng = np.random.default_rng(1)

    def __enter__(self) -> TeensyEmulator:
        self.open()
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()

    def open(self) -> None:
        """Create the pty and point the link at it."""
        self._pty.open(blocking=False)

    def close(self) -> None:
        """Close the pty and remove the link; safe to call twice."""
        self._pty.close()

    def run(self, duration_s: float = math.inf, *, sequence_start: int = 0) -> None:
        """Stream until `duration_s` has passed (forever by default) or `close`."""
        period = 1.0 / self.rate_hz
        start = time.monotonic()
        faults = list(self._faults)
        corrupt = drop = 0
        sequence = sequence_start
        index = 0
        end = start + duration_s

        def pause(seconds: float) -> bool:
            """Sleep up to `seconds`, never past the end; True while time is left."""
            time.sleep(max(0.0, min(seconds, end - time.monotonic())))
            return time.monotonic() < end

        while True:
            due = start + index * period
            now = time.monotonic()
            if due >= end or now >= end or self._pty.master is None:
                return  # done, or closed from another thread
            if due > now:
                time.sleep(due - now)
            t_s = due - start
            while faults and faults[0].at_s <= t_s:
                fault = faults.pop(0)
                if fault.kind is FaultKind.GARBAGE:
                    self._write(self._rng.integers(0, 256, int(fault.arg), np.uint8).tobytes())
                elif fault.kind is FaultKind.CRC:
                    corrupt += int(fault.arg)
                elif fault.kind is FaultKind.DROP:
                    drop += int(fault.arg)
                elif fault.kind is FaultKind.STALL:
                    if not pause(fault.arg):
                        return
                else:
                    self.close()
                    if not pause(fault.arg):
                        return
                    self.open()
            accel, gyro, mag, pressure, temperature = reported(*self.source.sample(t_s))
            device_us = (self._start_time_us + int(round(t_s * 1e6))) % (1 << 32)
            frame = encode(Sample(sequence, device_us, accel, gyro, mag, pressure,
                                  temperature))
            sequence = (sequence + 1) % (1 << 16)
            index += 1
            if drop:
                drop -= 1
                continue
            if corrupt:
                corrupt -= 1
                frame = frame[:-1] + bytes([frame[-1] ^ 0xFF])
            self._write(frame)

    def _write(self, data: bytes) -> None:
        if self._pty.master is None:
            return
        try:
            os.write(self._pty.master, data)
            self.frames_sent += 1
        except OSError as err:
            # Nobody reads and the pty is full, or the reader went away: a USB CDC
            # device drops data the host does not collect.
            if err.errno not in (errno.EAGAIN, errno.EIO):
                raise
            self.frames_overflowed += 1
