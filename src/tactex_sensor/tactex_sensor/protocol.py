# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Teensy wire protocol version 1: frame encoding, a streaming decoder and its drop counters.

One 56-byte little-endian frame per sample: sync `A5 5A`, version 1, payload length
50, uint16 sequence, uint32 device time (us), accel (m/s^2), gyro (rad/s), magnetic
field (T), pressure (Pa), temperature (degC) as float32, and a CRC-16/CCITT-FALSE of
bytes 2..53. A channel whose chip does not answer is sent as NaN.
"""

from __future__ import annotations

import binascii
from dataclasses import dataclass, fields
import struct
from typing import NamedTuple

from tactex_sensor.errors import FrameError

SYNC = b'\xa5\x5a'
VERSION = 1
PAYLOAD_LENGTH = 50
FRAME_SIZE = 56
DEFAULT_BAUD = 250000
_FRAME = struct.Struct('<2sBBHI3f3f3fff')
_CRC = struct.Struct('<H')
_SEQUENCE_MODULUS = 1 << 16


class Sample(NamedTuple):
    """One sensor sample as it travels on the wire (SI units, sensor frame)."""

    sequence: int
    device_time_us: int
    accel: tuple[float, float, float]
    gyro: tuple[float, float, float]
    mag: tuple[float, float, float]
    pressure_pa: float
    temperature_c: float


def crc16_ccitt_false(data: bytes) -> int:
    """CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, no reflection, xorout 0."""
    return binascii.crc_hqx(data, 0xFFFF)


def encode(sample: Sample, *, version: int = VERSION) -> bytes:
    """Return the 56-byte frame of `sample` (`version` other than 1 only for tests).

    Values are rounded to float32 (NaN and inf travel as they are); sequence and device
    time wrap.

    Raises:
        FrameError: a finite value beyond float32's range, or a non-integer counter.
    """
    try:
        body = _FRAME.pack(SYNC, version, PAYLOAD_LENGTH, sample.sequence % _SEQUENCE_MODULUS,
                           sample.device_time_us % (1 << 32), *sample.accel, *sample.gyro,
                           *sample.mag, sample.pressure_pa, sample.temperature_c)
    except (struct.error, OverflowError, TypeError) as err:
        raise FrameError(f'sample does not fit a protocol frame ({err}): {sample!r}') from None
    return body + _CRC.pack(crc16_ccitt_false(body[2:]))


@dataclass
class DecoderStats:
    """What the decoder saw: frames, drops by reason, lost frames and discarded bytes."""

    frames: int = 0
    crc_errors: int = 0
    bad_version: int = 0
    bad_length: int = 0
    lost_frames: int = 0
    out_of_order: int = 0
    discarded_bytes: int = 0

    @property
    def dropped(self) -> int:
        """Frames rejected by the decoder (CRC, version, length)."""
        return self.crc_errors + self.bad_version + self.bad_length

    def as_dict(self) -> dict[str, int]:
        """Counters by name, for diagnostics."""
        return {f.name: getattr(self, f.name) for f in fields(self)}


class FrameDecoder:
    """Turn a byte stream into samples, resynchronising on the sync bytes after any garbage.

    `feed` accepts reads of any size (a frame may be split anywhere) and never raises
    on bad bytes: a candidate frame with a wrong version, length or CRC is dropped and
    counted, and the search resumes one byte after its sync so a real frame hidden
    inside it is still found.
    """

    def __init__(self) -> None:
        self._buffer = bytearray()
        self._last_sequence: int | None = None
        self.stats = DecoderStats()

    def reset_sequence(self) -> None:
        """Forget the last sequence number (after a reconnect), so no gap is counted."""
        self._last_sequence = None
        self._buffer.clear()

    def feed(self, data: bytes) -> list[Sample]:
        """Add `data` to the stream and return the samples completed by it."""
        buffer = self._buffer
        buffer += data
        samples: list[Sample] = []
        stats = self.stats
        position = 0
        end = len(buffer)
        while True:
            start = buffer.find(SYNC, position)
            if start < 0:
                # Keep a trailing first sync byte: its partner may come with the next read.
                keep = 1 if end > position and buffer[end - 1] == SYNC[0] else 0
                stats.discarded_bytes += end - position - keep
                position = end - keep
                break
            stats.discarded_bytes += start - position
            if end - start < FRAME_SIZE:
                position = start
                break
            version = buffer[start + 2]
            length = buffer[start + 3]
            if version != VERSION:
                stats.bad_version += 1
            elif length != PAYLOAD_LENGTH:
                stats.bad_length += 1
            elif binascii.crc_hqx(buffer[start + 2:start + 54], 0xFFFF) != \
                    buffer[start + 54] | (buffer[start + 55] << 8):
                stats.crc_errors += 1
            else:
                fields_ = _FRAME.unpack_from(buffer, start)
                samples.append(Sample(fields_[3], fields_[4], fields_[5:8], fields_[8:11],
                                      fields_[11:14], fields_[14], fields_[15]))
                self._count_sequence(fields_[3])
                position = start + FRAME_SIZE
                continue
            # Rejected candidate: its first sync byte is garbage, look again just after it.
            stats.discarded_bytes += 1
            position = start + 1
        del buffer[:position]
        stats.frames += len(samples)
        return samples

    def _count_sequence(self, sequence: int) -> None:
        last = self._last_sequence
        self._last_sequence = sequence
        if last is None:
            return
        gap = (sequence - last - 1) % _SEQUENCE_MODULUS
        if gap >= _SEQUENCE_MODULUS // 2:
            self.stats.out_of_order += 1
        else:
            self.stats.lost_frames += gap
