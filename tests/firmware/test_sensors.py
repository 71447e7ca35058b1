# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The firmware's sensor maths: LSM9DS0 counts to SI, MPL115A2 coefficients and compensation."""

import math
import subprocess

import pytest

G = 9.80665
# Datasheet sensitivities per range code: mg/LSB, mdps/LSB, mgauss/LSB.
ACCEL_MG = {0: 0.061, 1: 0.122, 2: 0.183, 3: 0.244, 4: 0.732}
GYRO_MDPS = {0: 8.75, 1: 17.5, 2: 70.0}
MAG_MGAUSS = {0: 0.08, 1: 0.16, 2: 0.32, 3: 0.48}
COUNTS = (1, -1, 32767, -32768, 12345)


def _ask(tool, *lines: str) -> list[list[str]]:
    result = subprocess.run([str(tool)], input='\n'.join(lines) + '\n', capture_output=True,
                            text=True, check=True)
    return [line.split() for line in result.stdout.splitlines()]


def _floats(words: list[str]) -> list[float]:
    return [float.fromhex(w) for w in words]


@pytest.mark.parametrize(('kind', 'table', 'to_si'), [
    ('accel', ACCEL_MG, 1e-3 * G),                  # mg -> m/s^2
    ('gyro', GYRO_MDPS, 1e-3 * math.pi / 180),      # mdps -> rad/s
    ('mag', MAG_MGAUSS, 1e-3 * 1e-4),               # mgauss -> gauss -> T
])
def test_counts_convert_with_the_datasheet_sensitivity_of_each_range(sensor_tool, kind, table,
                                                                     to_si):
    requests = [f'{kind} {code} {x} {COUNTS[1]} {COUNTS[2]}' for code in table for x in COUNTS]
    answers = _ask(sensor_tool, *requests)
    for request, answer in zip(requests, answers, strict=True):
        code, *counts = (int(w) for w in request.split()[1:])
        expected = [c * table[code] * to_si for c in counts]
        assert _floats(answer) == pytest.approx(expected, rel=1e-6), request


def test_full_scale_bits_in_the_setup_follow_the_configured_range(sensor_tool):
    for accel, gyro, mag in [(0, 0, 0), (1, 1, 1), (4, 2, 3)]:
        (answer,) = _ask(sensor_tool, f'setup {accel} {gyro} {mag}')
        writes = dict(word.split('=') for word in answer)
        assert (int(writes['g23'], 16) >> 4) & 0x3 == gyro
        assert (int(writes['xm21'], 16) >> 3) & 0x7 == accel
        assert (int(writes['xm25'], 16) >> 5) & 0x3 == mag
        # Powered, all axes, block data update; magnetometer in continuous mode.
        assert writes['g20'] == 'bf' and int(writes['g23'], 16) & 0x80
        assert writes['xm20'] == '8f' and writes['xm26'] == '00'


def test_an3785_worked_example_gives_96_59_kpa(sensor_tool):
    # Registers 0x00..0x0B of the example in Freescale AN3785: Padc 0x6680, Tadc 0x7EC0,
    # a0 0x3ECE, b1 0xB3F9, b2 0xC517, c12 0x33C8. The expected numbers are derived here
    # from the datasheet's fixed-point formats, not copied.
    (answer,) = _ask(sensor_tool, 'mpl115a2 66 80 7e c0 3e ce b3 f9 c5 17 33 c8')
    a0, b1, b2, c12 = _floats(answer[:4])
    padc, tadc = int(answer[4]), int(answer[5])
    pressure_pa, temperature_c = _floats(answer[6:])
    assert (a0, b1, b2) == (0x3ECE / 8, (0xB3F9 - 65536) / 8192, (0xC517 - 65536) / 16384)
    assert c12 == pytest.approx((0x33C8 >> 2) / 2**22, rel=1e-7)
    assert (padc, tadc) == (0x6680 >> 6, 0x7EC0 >> 6) == (410, 507)
    assert (a0, b1, b2, c12) == pytest.approx((2009.75, -2.37585, -0.92047, 0.00079), abs=1e-5)
    pcomp = a0 + (b1 + c12 * tadc) * padc + b2 * tadc
    assert pcomp == pytest.approx(733.2, abs=0.05)
    assert pressure_pa == pytest.approx((pcomp * 65 / 1023 + 50) * 1000, rel=1e-6)
    assert pressure_pa / 1000 == pytest.approx(96.59, abs=0.005)
    assert temperature_c == pytest.approx(25 + (507 - 472) / -5.35, rel=1e-6)


def test_negative_c12_decodes_as_twos_complement(sensor_tool):
    (answer,) = _ask(sensor_tool, 'mpl115a2 80 00 80 00 00 00 00 00 00 00 ff fc')
    assert _floats(answer[:4])[3] == -1 / 2**22
    assert int(answer[4]) == int(answer[5]) == 512


def test_missing_channel_pattern_is_the_quiet_nan_0x7fc00000(sensor_tool):
    assert _ask(sensor_tool, 'missing') == [['7fc00000']]
