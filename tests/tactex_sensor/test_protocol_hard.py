# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Teensy wire protocol: any sample round-trips or is refused, any byte stream decodes."""

import math
import struct

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from support.hard_values import anything, vectors

from tactex_sensor.errors import FrameError
from tactex_sensor.protocol import encode, FRAME_SIZE, FrameDecoder, Sample

pytestmark = pytest.mark.hard_case

float32s = st.floats(width=32)  # every float32: NaN, +-inf, subnormals, +-0.0, +-max
samples = st.builds(Sample, st.integers(-2**40, 2**40), st.integers(-2**40, 2**40),
                    vectors(float32s), vectors(float32s), vectors(float32s), float32s,
                    float32s)


def _bits(value: float) -> bytes:
    return struct.pack('<f', value)


@settings(max_examples=150)
@given(samples)
def test_any_float32_sample_round_trips_bit_for_bit(sample):
    decoded = FrameDecoder().feed(encode(sample))
    assert len(decoded) == 1
    got = decoded[0]
    assert got.sequence == sample.sequence % 2**16
    assert got.device_time_us == sample.device_time_us % 2**32
    sent = (*sample.accel, *sample.gyro, *sample.mag, sample.pressure_pa, sample.temperature_c)
    received = (*got.accel, *got.gyro, *got.mag, got.pressure_pa, got.temperature_c)
    for a, b in zip(sent, received, strict=True):
        assert _bits(a) == _bits(b) or (math.isnan(a) and math.isnan(b))


@settings(max_examples=100)
@given(anything())
def test_a_value_beyond_float32_is_a_frame_error_not_a_silent_inf(value):
    sample = Sample(1, 2, (value, 0.0, 0.0), (0.0,) * 3, (0.0,) * 3, 101325.0, 20.0)
    if math.isfinite(value) and abs(value) > float(np.finfo(np.float32).max) * (1 + 2**-24):
        with pytest.raises(FrameError, match='float32|too large'):
            encode(sample)
    else:
        assert len(encode(sample)) == FRAME_SIZE


@settings(max_examples=150)
@given(st.binary(max_size=400), st.lists(samples, max_size=4), st.binary(max_size=200),
       st.integers(1, 64))
def test_any_byte_stream_decodes_without_raising_and_keeps_every_frame(garbage, sent, tail,
                                                                      read_size):
    stream = garbage + b''.join(encode(s) for s in sent) + tail
    decoder = FrameDecoder()
    decoded = []
    for start in range(0, len(stream), read_size):  # reads of any size
        decoded += decoder.feed(stream[start:start + read_size])
    stats = decoder.stats
    assert stats.frames == len(decoded) and stats.dropped >= 0
    assert stats.discarded_bytes + FRAME_SIZE * stats.frames <= len(stream)
    # Garbage may hide frames of its own, never lose the real ones: they come in order.
    found = iter((s.sequence, s.device_time_us) for s in decoded)
    assert all(any(key == (s.sequence % 2**16, s.device_time_us % 2**32) for key in found)
               for s in sent)


@given(st.binary(max_size=FRAME_SIZE - 1))
def test_a_partial_frame_waits_for_the_rest(head):
    frame = encode(Sample(7, 8, (1.0, 2.0, 3.0), (0.0,) * 3, (0.0,) * 3, 1.0, 2.0))
    decoder = FrameDecoder()
    assert decoder.feed(head + frame[:FRAME_SIZE // 2]) == []  # too short for any frame
    assert [s.sequence for s in decoder.feed(frame[FRAME_SIZE // 2:])] == [7]
    assert decoder.feed(b'') == []
