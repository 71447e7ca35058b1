# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The firmware selects the LSM9DS0 ranges of tactex_common.chips, the one source."""

from pathlib import Path

from support.scripts import load_script

from tactex_common import chips

ROOT = Path(__file__).resolve().parents[2]


def _writer():
    return load_script('tools/write_firmware_ranges.py')


def test_the_committed_header_is_written_from_chips():
    writer = _writer()
    assert writer.HEADER.read_text(encoding='utf-8') == writer.header_text(), (
        'firmware/teensy_tactile/tactex_ranges.h is stale: run tools/write_firmware_ranges.py')


def test_the_sketch_takes_its_ranges_from_the_header():
    sketch = (ROOT / 'firmware' / 'teensy_tactile' / 'teensy_tactile.ino').read_text()
    assert '#include "tactex_ranges.h"' in sketch
    for name in ('kAccel', 'kGyro', 'kMag'):
        assert f'tactex::ranges::{name};' in sketch


def test_the_configured_ranges_are_the_chips():
    assert chips.accel_range().nominal == chips.ACCEL_RANGE_G
    assert chips.gyro_range().nominal == chips.GYRO_RANGE_DPS
    assert chips.mag_range().nominal == chips.MAG_RANGE_GAUSS
