# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Bring-up checks of the tactile module: frames arrive, at the rate, intact, every chip answers.

Listens to the Teensy's port for a while (nothing is sent to it) and decodes what comes
as teensy_node does: the frame rate against the firmware's, frames dropped for their
CRC or protocol version, frames lost in sequence, and channels sent as NaN (a chip that
does not answer on I2C).
"""

from __future__ import annotations

from collections.abc import Callable
import math
import time

import serial

from tactex_common.bringup import Check, FAIL, OK, WARN
from tactex_sensor.protocol import FrameDecoder, Sample, VERSION

RATE_TOLERANCE = 0.1  # of the expected frame rate
MAX_DROPPED_SHARE = 0.01  # of the frames: more is a bad cable or a noisy line
FIRMWARE = 'firmware/teensy_tactile (docs/guides/real-arm.md, Teensy firmware)'
CHIP_OF = {'accel': 'LSM9DS0 accelerometer', 'gyro': 'LSM9DS0 gyro',
           'mag': 'LSM9DS0 magnetometer', 'pressure': 'MPL115A2 pressure',
           'temperature': 'MPL115A2 temperature'}


def listen(port: str, baud: int, seconds: float, *,
           opener: Callable[..., serial.SerialBase] = serial.Serial
           ) -> tuple[FrameDecoder, list[Sample], float]:
    """Decode what `port` sends for `seconds`: (decoder with its counters, samples, seconds).

    Raises:
        OSError: the port cannot be opened (pyserial's SerialException is one).
    """
    decoder, samples = FrameDecoder(), []
    with opener(port, baud, timeout=0.05) as link:
        link.reset_input_buffer()  # bytes queued before we listened are not the rate
        start = time.monotonic()
        while (elapsed := time.monotonic() - start) < seconds:
            samples += decoder.feed(link.read(max(1, link.in_waiting)))
    return decoder, samples, elapsed


def stream_checks(port: str, baud: int, expected_hz: float | None, seconds: float = 2.0, *,
                  opener: Callable[..., serial.SerialBase] = serial.Serial) -> list[Check]:
    """The checks of the frames `port` sends in `seconds` (see the module docstring).

    `expected_hz` None: the rate is reported, not checked.
    """
    try:
        decoder, samples, elapsed = listen(port, baud, seconds, opener=opener)
    except (OSError, ValueError) as err:
        return [Check('Teensy stream', FAIL, f'cannot open {port} at {baud} baud: {err}',
                      'close whatever holds the port (a running teensy_node, a serial '
                      'monitor) and check the baud rate (250000)')]
    stats = decoder.stats
    if not samples:
        if stats.bad_version:
            found = f'{stats.bad_version} frames of another protocol version'
            fix = f'flash {FIRMWARE}: this workspace reads protocol version {VERSION}'
        elif stats.discarded_bytes:
            found = f'{stats.discarded_bytes} bytes but no frame'
            fix = (f'is this the Teensy, at {baud} baud? Flash {FIRMWARE} if it runs another '
                   'sketch')
        else:
            found = 'no byte'
            fix = (f'is the Teensy powered and flashed with {FIRMWARE}? Unplug and plug it in; '
                   'another process may be reading the port')
        return [Check('Teensy stream', FAIL, f'{found} in {elapsed:.1f} s on {port}', fix)]
    rate = len(samples) / elapsed
    checks = [Check('Teensy stream', OK, f'{len(samples)} frames of protocol version '
                    f'{VERSION} in {elapsed:.1f} s')]
    checks.append(_rate_check(rate, expected_hz))
    dropped = stats.dropped + stats.lost_frames
    share = dropped / max(1, len(samples) + dropped)
    checks.append(Check(
        'Teensy frames intact', OK if not dropped else WARN if share <= MAX_DROPPED_SHARE
        else FAIL, f'{stats.crc_errors} CRC errors, {stats.bad_version} of another version, '
        f'{stats.lost_frames} lost in sequence, {stats.out_of_order} out of order',
        '' if not dropped else 'use a shorter, shielded USB cable and a port without a hub'))
    checks.append(_chip_check(samples))
    return checks


def _rate_check(rate: float, expected_hz: float | None) -> Check:
    if expected_hz is None:
        return Check('Teensy frame rate', OK, f'{rate:.1f} Hz')
    if abs(rate - expected_hz) <= RATE_TOLERANCE * expected_hz:
        return Check('Teensy frame rate', OK, f'{rate:.1f} Hz (expected {expected_hz:g} Hz +- '
                     f'{100 * RATE_TOLERANCE:.0f} %)')
    return Check('Teensy frame rate', FAIL, f'{rate:.1f} Hz, expected {expected_hz:g} Hz +- '
                 f'{100 * RATE_TOLERANCE:.0f} %', 'give --sensor-rate the rate the firmware was '
                 'built with (TACTEX_RATE_HZ, 120 after power-on); a slower stream means the I2C '
                 'reads overrun the period: check the wiring and pull-ups')


def _chip_check(samples: list[Sample]) -> Check:
    silent = [chip for group, chip in CHIP_OF.items()
              if all(not all(math.isfinite(v) for v in _values(sample, group))
                     for sample in samples)]
    if silent:
        return Check('Teensy chips', FAIL, f'{", ".join(silent)} sent only NaN',
                     'the chip does not answer on I2C: check its wiring, supply and address '
                     '(firmware/teensy_tactile/tactex_sensors.h lists the addresses)')
    return Check('Teensy chips', OK, 'every channel carries numbers')


def _values(sample: Sample, group: str) -> tuple[float, ...]:
    if group in ('pressure', 'temperature'):
        return (sample.pressure_pa if group == 'pressure' else sample.temperature_c,)
    return getattr(sample, group)
