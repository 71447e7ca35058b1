# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The firmware's C++ framing against the Python protocol: bit-exact frames, CRC, counter wraps."""

import random
import struct
import subprocess

from firmware_build import FIRMWARE, MOCK
import pytest

from tactex_sensor.clock import DeviceClock
from tactex_sensor.protocol import crc16_ccitt_false, encode, FRAME_SIZE, FrameDecoder, Sample

# float32 bit patterns with a meaning of their own.
QUIET_NAN = 0x7FC00000
SPECIAL_BITS = {
    'nan': QUIET_NAN, '-nan': 0xFFC00000, 'inf': 0x7F800000, '-inf': 0xFF800000,
    '-0.0': 0x80000000, '0.0': 0x00000000, 'max': 0x7F7FFFFF, '-max': 0xFF7FFFFF,
    'min normal': 0x00800000, 'min subnormal': 0x00000001, 'max subnormal': 0x007FFFFF,
}


def _bits(value: float) -> int:
    return struct.unpack('<I', struct.pack('<f', value))[0]


def _float(bits: int) -> float:
    return struct.unpack('<f', struct.pack('<I', bits))[0]


def _ordinary(tick: int) -> list[int]:
    values = (0.1 * tick, -0.2, 9.80665, 0.01, 0.02 * tick, -0.03, 2.1e-5, -4.0e-6, 4.3e-5,
              101325.0 + tick, 23.5)
    return [_bits(v) for v in values]


def _cases() -> list[tuple[int, int, list[int]]]:
    """(tick, device time, 11 float bit patterns): consecutive ticks across both wraps."""
    cases = []
    period_us = 2857
    first_tick = 65536 - 4
    first_time = (1 << 32) - 3 * period_us
    for i in range(8):
        cases.append((first_tick + i, (first_time + i * period_us) % (1 << 32),
                      _ordinary(first_tick + i)))
    for i, bits in enumerate(SPECIAL_BITS.values()):
        tick = first_tick + 8 + i
        cases.append((tick, (first_time + (8 + i) * period_us) % (1 << 32), [bits] * 11))
    return cases


def _encode_with_cpp(frame_tool, cases) -> bytes:
    lines = [f'{tick} {time_us} ' + ' '.join(f'{b:08x}' for b in bits)
             for tick, time_us, bits in cases]
    result = subprocess.run([str(frame_tool), 'encode'], input='\n'.join(lines).encode(),
                            capture_output=True, check=True)
    return result.stdout


def _python_sample(tick: int, time_us: int, bits: list[int]) -> Sample:
    values = [_float(b) for b in bits]
    return Sample(tick % 65536, time_us, tuple(values[0:3]), tuple(values[3:6]),
                  tuple(values[6:9]), values[9], values[10])


def test_crc_matches_the_ccitt_false_check_value_and_python(frame_tool):
    rng = random.Random(19)
    for data in (b'123456789', b'', bytes(rng.randrange(256) for _ in range(300))):
        result = subprocess.run([str(frame_tool), 'crc'], input=data, capture_output=True,
                                check=True)
        assert int(result.stdout, 16) == crc16_ccitt_false(data)
    assert crc16_ccitt_false(b'123456789') == 0x29B1


def test_host_frames_decode_bit_exact_with_python_encode(frame_tool):
    cases = _cases()
    stream = _encode_with_cpp(frame_tool, cases)
    assert len(stream) == FRAME_SIZE * len(cases)
    decoder = FrameDecoder()
    samples = decoder.feed(stream)
    assert decoder.stats.frames == len(cases) and decoder.stats.dropped == 0
    assert decoder.stats.discarded_bytes == 0
    for i, (case, sample) in enumerate(zip(cases, samples, strict=True)):
        cpp_frame = stream[i * FRAME_SIZE:(i + 1) * FRAME_SIZE]
        assert cpp_frame == encode(_python_sample(*case)), f'frame {i} differs'
        assert encode(sample) == cpp_frame, f'frame {i} does not survive decode + encode'


def test_special_float_values_keep_their_bits(frame_tool):
    cases = [case for case in _cases() if len(set(case[2])) == 1]
    samples = FrameDecoder().feed(_encode_with_cpp(frame_tool, cases))
    for (_, _, bits), sample in zip(cases, samples, strict=True):
        decoded = (*sample.accel, *sample.gyro, *sample.mag, sample.pressure_pa,
                   sample.temperature_c)
        assert [_bits(v) for v in decoded] == bits


def test_sequence_and_microsecond_counters_wrap_without_lost_frames(frame_tool):
    cases = _cases()
    samples = FrameDecoder().feed(_encode_with_cpp(frame_tool, cases))
    assert [s.sequence for s in samples[:8]] == [65532, 65533, 65534, 65535, 0, 1, 2, 3]
    assert samples[2].device_time_us > samples[3].device_time_us  # uint32 wrapped here
    decoder = FrameDecoder()
    decoder.feed(_encode_with_cpp(frame_tool, cases))
    assert decoder.stats.lost_frames == 0 and decoder.stats.out_of_order == 0
    clock = DeviceClock()
    unwrapped = [clock.unwrap(s.device_time_us) for s in samples]
    assert all(b - a == 2857 for a, b in zip(unwrapped, unwrapped[1:], strict=False))


@pytest.mark.parametrize('path', sorted(
    p for folder in (FIRMWARE, MOCK.parent) for p in folder.rglob('*')
    if p.suffix in ('.ino', '.h', '.cpp')), ids=lambda p: p.name)
def test_every_firmware_source_has_the_copyright_header(path):
    lines = path.read_text(encoding='utf-8').splitlines()
    assert lines[0] == '// Copyright 2026 The tactex authors'
    assert lines[1] == '// SPDX-License-Identifier: Apache-2.0'
    assert lines[2].startswith('// ') and len(lines[2]) <= 99
    assert max(len(line) for line in lines) <= 99
