# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Write firmware/teensy_tactile/tactex_ranges.h from tactex_common.chips (the one source).

The firmware selects the LSM9DS0 ranges this header names; tests/firmware checks that
the committed header is what this writes. Run it after changing a range in chips.py:
    .venv/bin/python tools/write_firmware_ranges.py
"""

from __future__ import annotations

from pathlib import Path
import sys

from tactex_common import chips

HEADER = Path(__file__).resolve().parents[1] / 'firmware' / 'teensy_tactile' / 'tactex_ranges.h'


def header_text() -> str:
    """The header's text for the ranges configured in tactex_common.chips."""
    return (
        '// Copyright 2026 The tactex authors\n'
        '// SPDX-License-Identifier: Apache-2.0\n'
        '// The LSM9DS0 ranges the firmware selects. Written by tools/write_firmware_ranges.py\n'
        '// from tactex_common/chips.py, which the simulator and the Madgwick filter read too:\n'
        '// change them there, not here.\n'
        '#ifndef TACTEX_RANGES_H_\n'
        '#define TACTEX_RANGES_H_\n\n'
        '#include "tactex_sensors.h"\n\n'
        'namespace tactex {\n'
        'namespace ranges {\n\n'
        f'constexpr lsm9ds0::AccelRange kAccel = lsm9ds0::AccelRange::k{chips.ACCEL_RANGE_G}G;\n'
        f'constexpr lsm9ds0::GyroRange kGyro = lsm9ds0::GyroRange::k{chips.GYRO_RANGE_DPS}Dps;\n'
        f'constexpr lsm9ds0::MagRange kMag = lsm9ds0::MagRange::k{chips.MAG_RANGE_GAUSS}Gauss;\n\n'
        '}  // namespace ranges\n'
        '}  // namespace tactex\n\n'
        '#endif  // TACTEX_RANGES_H_\n')


def main() -> int:
    """Write the header; print where."""
    HEADER.write_text(header_text(), encoding='utf-8')
    print(f'wrote {HEADER}')
    return 0


if __name__ == '__main__':
    sys.exit(main())
