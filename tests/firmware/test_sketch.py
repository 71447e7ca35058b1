# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The Teensy sketch itself, compiled against an Arduino mock and run in simulated time."""

import math
import struct

from firmware_build import compile_cpp, FIRMWARE, FIRMWARE_SOURCES, MOCK, run_sketch, SKETCH
import pytest

from tactex_common import chips
from tactex_sensor.link import SerialLink
from tactex_sensor.protocol import FrameDecoder
from tactex_sensor.reader import TeensyReader

# What the simulator's fake chips measure (tests/firmware/cpp/sketch_sim.cpp).
ACCEL = (0.5, -1.0, 9.80665)
GYRO = (0.5, -0.25, 1.0)
MAG = (2.0e-5, -4.0e-6, 4.3e-5)
# AN3785's registers in the fake barometer: 96.587 kPa, Tadc 507.
PRESSURE_PA = ((0x3ECE / 8 + ((0xB3F9 - 65536) / 8192 + (0x33C8 >> 2) / 2**22 * 507) * 410
                + (0xC517 - 65536) / 16384 * 507) * 65 / 1023 + 50) * 1000
TEMPERATURE_C = 25 + (507 - 472) / -5.35
NAN_BITS = 0x7FC00000
# One LSB at the sketch's ranges (tactex_common.chips, through tactex_ranges.h).
ACCEL_LSB, GYRO_LSB, MAG_LSB = (chips.accel_range().lsb_si, chips.gyro_range().lsb_si,
                                chips.mag_range().lsb_si)
PERIOD_120_US, PERIOD_350_US = 1e6 / 120, 1e6 / 350


def _decode(stream: bytes):
    decoder = FrameDecoder()
    samples = decoder.feed(stream)
    assert decoder.stats.dropped == 0 and decoder.stats.discarded_bytes == 0
    return samples, decoder.stats


def _bits(value: float) -> int:
    return struct.unpack('<I', struct.pack('<f', value))[0]


def _channels(sample) -> dict[str, tuple[float, ...]]:
    return {'accel': sample.accel, 'gyro': sample.gyro, 'mag': sample.mag,
            'pressure': (sample.pressure_pa,), 'temperature': (sample.temperature_c,)}


def test_sketch_compiles_as_gnu_plus_plus_14_without_exceptions():
    # Teensyduino builds Teensy 3.x code with -std=gnu++14 -fno-exceptions -fno-rtti.
    compile_cpp([SKETCH, *FIRMWARE_SOURCES], include=[MOCK, FIRMWARE],
                flags=('-std=gnu++14', '-fno-exceptions', '-fno-rtti', '-Wall', '-Wextra',
                       '-Werror'))


def test_sketch_sends_one_frame_per_tick_in_si_units_at_120_hz(sketch_sim):
    stream, counters = run_sketch(sketch_sim, '--ticks', '240')
    samples, stats = _decode(stream)
    assert len(samples) == 240 and stats.lost_frames == 0
    assert [s.sequence for s in samples] == list(range(240))
    assert counters['period_us'] == pytest.approx(PERIOD_120_US, abs=1e-3)
    steps = {b.device_time_us - a.device_time_us for a, b in zip(samples, samples[1:],
                                                                  strict=False)}
    assert steps <= {8333, 8334}  # the tick's stamp, not the send time
    for sample in samples:
        assert sample.accel == pytest.approx(ACCEL, abs=ACCEL_LSB)
        assert sample.gyro == pytest.approx(GYRO, abs=GYRO_LSB)
        assert sample.mag == pytest.approx(MAG, abs=MAG_LSB)
        assert sample.pressure_pa == pytest.approx(PRESSURE_PA, rel=1e-6)
        assert sample.temperature_c == pytest.approx(TEMPERATURE_C, rel=1e-6)
    assert counters['blocking_writes'] == 0 and counters['early_reads'] == 0


def test_sketch_keeps_up_at_350_hz_within_the_i2c_budget(sketch_sim):
    stream, counters = run_sketch(sketch_sim, '--ticks', '700', '--command', '0:3')
    samples, stats = _decode(stream)
    assert len(samples) == 700 and stats.lost_frames == 0
    assert counters['period_us'] == pytest.approx(PERIOD_350_US, abs=1e-3)
    # Three 6-byte reads (84 bits each), on every second tick the barometer's 4-byte read
    # (66 bits) and conversion command (29 bits): 347 bits at 400 kHz = 867.5 us; once a
    # second also two 1-byte reads (39 bits each) that re-check the LSM9DS0: 1062.5 us.
    assert counters['max_bus_us'] == pytest.approx(867.5 + 2 * 97.5)
    assert counters['max_busy_us'] < PERIOD_350_US / 2
    # A conversion takes 3 ms, longer than a tick: a new pressure every second frame.
    assert counters['early_reads'] == 0
    assert counters['results_read'] == pytest.approx(700 / 2, abs=2)
    steps = {b.device_time_us - a.device_time_us for a, b in zip(samples[1:], samples[2:],
                                                                  strict=False)}
    assert steps <= {2857, 2858}


@pytest.mark.parametrize(('chip', 'channels'), [
    ('gyro', {'gyro'}),
    ('accel_mag', {'accel', 'mag'}),
    ('barometer', {'pressure', 'temperature'}),
])
def test_missing_chip_sends_nan_in_its_channels_and_the_stream_goes_on(sketch_sim, chip,
                                                                        channels):
    stream, _ = run_sketch(sketch_sim, '--ticks', '360', '--absent', chip)
    samples, stats = _decode(stream)
    assert len(samples) == 360 and stats.lost_frames == 0
    for sample in samples:
        for name, values in _channels(sample).items():
            if name in channels:
                assert [_bits(v) for v in values] == [NAN_BITS] * len(values), name
            else:
                assert all(math.isfinite(v) for v in values), name


def test_chip_that_answers_later_is_picked_up_within_a_second(sketch_sim):
    stream, _ = run_sketch(sketch_sim, '--ticks', '360', '--absent', 'gyro', '--absent',
                           'barometer', '--appear-tick', '60')
    samples, _ = _decode(stream)
    finite = [i for i, s in enumerate(samples)
              if all(math.isfinite(v) for v in (*s.gyro, s.pressure_pa))]
    assert finite and finite == list(range(finite[0], 360))
    assert 60 < finite[0] <= 60 + 120 + 2  # the next once-a-second check, then one conversion


def test_missing_chip_surfaces_in_the_reader_diagnostics(sketch_sim):
    stream, _ = run_sketch(sketch_sim, '--ticks', '120', '--absent', 'barometer')

    class Port:
        in_waiting = len(stream)

        def read(self, size):
            return stream

    now_ns = [0]
    reader = TeensyReader(SerialLink('sim', 250000, opener=lambda *a, **k: Port()),
                          lambda: now_ns[0])
    reader.health()
    stamped = reader.poll()
    now_ns[0] = 1_000_000_000
    ok, summary, values = reader.health()
    assert len(stamped) == 120 and not ok
    assert summary == 'streaming at 120 Hz; NaN samples on pressure, temperature since the ' \
        'last report'
    assert values['nan_pressure'] == values['nan_temperature'] == '120'
    assert values['nan_accel'] == values['nan_gyro'] == values['nan_mag'] == '0'


def test_stalled_host_costs_frames_not_time(sketch_sim):
    stream, counters = run_sketch(sketch_sim, '--ticks', '700', '--command', '0:3',
                                  '--stall', '100:200')
    samples, stats = _decode(stream)
    # The host reads nothing after ticks 100..299: frames 100..107 fill the 8 USB packets,
    # frames 108..300 are skipped (tick 300 comes before the host's next read). Their
    # sequence numbers are spent, so the host counts them as lost.
    assert stats.lost_frames == 300 - 108 + 1 and len(samples) == 700 - 193
    assert counters['blocking_writes'] == 0
    assert counters['max_busy_us'] < PERIOD_350_US / 2
    assert [s.sequence for s in samples] == sorted(s.sequence for s in samples)


def test_sequence_and_device_time_wrap_in_a_long_run(sketch_sim):
    ticks = 65536 + 100
    start_us = 2**32 - 3_000_000  # micros() wraps 3 s into the run
    stream, _ = run_sketch(sketch_sim, '--ticks', str(ticks), '--start-us', str(start_us))
    samples, stats = _decode(stream)
    assert len(samples) == ticks and stats.lost_frames == 0 and stats.out_of_order == 0
    assert [s.sequence for s in samples[65534:65538]] == [65534, 65535, 0, 1]
    wrapped = [i for i in range(1, ticks) if samples[i].device_time_us
               < samples[i - 1].device_time_us]
    assert len(wrapped) == 1
    assert 8333 <= (samples[wrapped[0]].device_time_us - samples[wrapped[0] - 1].device_time_us
                    ) % 2**32 <= 8334
