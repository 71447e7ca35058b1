# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What the module's chips can report: LSM9DS0 and MPL115A2 datasheet figures (one source).

The firmware (through the header tools/write_firmware_config.py writes), the emulator,
the Madgwick filter's plausibility checks and the simulator's `sensor` effect all read
the ranges here.

Sources:
- STMicroelectronics, LSM9DS0 iNEMO inertial module datasheet, DocID024763 Rev 2
  (2013): Table 3 (full scales, sensitivities, gyro rate noise density 0.03 dps/sqrt(Hz)),
  Tables 21-22 (gyro output data rate and cut-off), Tables 83-84 (accelerometer output
  data rate and anti-alias bandwidth), Table 87 (magnetometer data rate). Outputs are
  16-bit two's complement: a channel saturates at -32768 and +32767 counts.
- Freescale, MPL115A2 datasheet Rev 9 (2013): 50-115 kPa, 10-bit pressure and temperature
  ADC (Padc, Tadc), resolution 0.15 kPa, accuracy +-1 kPa, conversion time 1.6 ms
  (start to data ready); AN3785 for the compensation the firmware applies.
"""

from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np

from tactex_common.constants import STANDARD_GRAVITY_M_S2

TESLA_PER_GAUSS = 1e-4
# 16-bit two's complement outputs.
COUNTS_MIN, COUNTS_MAX = -32768, 32767


@dataclass(frozen=True)
class Range:
    """One selectable full scale of an LSM9DS0 sensor.

    Attributes:
        nominal: the full scale as the datasheet names it (+-, in its unit).
        unit_si: one of that unit in SI (m/s^2 per g, rad/s per dps, T per gauss).
        lsb: sensitivity in the datasheet unit per count (mg, mdps, mgauss: 1e-3 of it).
        code: the register's FS bit code (the firmware's enum value).
    """

    nominal: float
    unit_si: float
    lsb: float
    code: int

    @property
    def lsb_si(self) -> float:
        """One count in SI units."""
        return self.lsb * 1e-3 * self.unit_si

    @property
    def full_scale_si(self) -> float:
        """The nominal full scale in SI units (what the datasheet guarantees)."""
        return self.nominal * self.unit_si

    @property
    def rails_si(self) -> tuple[float, float]:
        """The lowest and highest value the chip can report (SI): the 16-bit rails."""
        return COUNTS_MIN * self.lsb_si, COUNTS_MAX * self.lsb_si


G, DPS, GAUSS = STANDARD_GRAVITY_M_S2, math.radians(1.0), TESLA_PER_GAUSS
# Full scale (datasheet unit) -> Range; LSM9DS0 Table 3.
ACCEL_RANGES = {2: Range(2, G, 0.061, 0), 4: Range(4, G, 0.122, 1), 6: Range(6, G, 0.183, 2),
                8: Range(8, G, 0.244, 3), 16: Range(16, G, 0.732, 4)}
GYRO_RANGES = {245: Range(245, DPS, 8.75, 0), 500: Range(500, DPS, 17.5, 1),
               2000: Range(2000, DPS, 70.0, 2)}
MAG_RANGES = {2: Range(2, GAUSS, 0.08, 0), 4: Range(4, GAUSS, 0.16, 1),
              8: Range(8, GAUSS, 0.32, 2), 12: Range(12, GAUSS, 0.48, 3)}

# The ranges this module is run with: the firmware selects them (tactex_ranges.h is
# written from these), the Madgwick filter trusts readings within them, and the
# simulator's `sensor` effect defaults to them. +-4 g: at +-2 g a lift-off transient of
# the compliant body reaches the rail (one sample in a thousand in simulation); the
# sweeps' rates stay within +-245 dps (tactex sim stats).
ACCEL_RANGE_G = 4
GYRO_RANGE_DPS = 245
MAG_RANGE_GAUSS = 2

# Output data rates and filters as the firmware configures them (LSM9DS0 Tables 21, 83,
# 84, 87): gyro 380 Hz with a 100 Hz cut-off, accelerometer 400 Hz behind a 194 Hz
# anti-alias filter, magnetometer 100 Hz.
GYRO_ODR_HZ, GYRO_CUTOFF_HZ = 380.0, 100.0
ACCEL_ODR_HZ, ACCEL_BANDWIDTH_HZ = 400.0, 194.0
MAG_ODR_HZ = 100.0
# Gyro rate noise density (Table 3), dps/sqrt(Hz), and the white noise it gives behind
# the 100 Hz cut-off (a first-order filter's noise bandwidth is pi/2 times its cut-off).
GYRO_NOISE_DPS_PER_SQRT_HZ = 0.03
GYRO_NOISE_SD_RAD_S = math.radians(GYRO_NOISE_DPS_PER_SQRT_HZ
                                   * math.sqrt(math.pi / 2 * GYRO_CUTOFF_HZ))

# MPL115A2: 10-bit pressure code over 50-115 kPa (the compensated value's scale).
PRESSURE_MIN_PA, PRESSURE_MAX_PA = 50e3, 115e3
PRESSURE_COUNTS = 1023
PRESSURE_LSB_PA = (PRESSURE_MAX_PA - PRESSURE_MIN_PA) / PRESSURE_COUNTS
PRESSURE_RESOLUTION_PA = 150.0
PRESSURE_CONVERSION_S = 1.6e-3


def accel_range(g: float = ACCEL_RANGE_G) -> Range:
    """The accelerometer range of +-`g` g.

    Raises:
        ValueError: not one of the chip's ranges (the message lists them).
    """
    return _pick(ACCEL_RANGES, g, 'accelerometer', 'g')


def gyro_range(dps: float = GYRO_RANGE_DPS) -> Range:
    """The gyro range of +-`dps` deg/s (ValueError: not one of the chip's)."""
    return _pick(GYRO_RANGES, dps, 'gyro', 'dps')


def mag_range(gauss: float = MAG_RANGE_GAUSS) -> Range:
    """The magnetometer range of +-`gauss` gauss (ValueError: not one of the chip's)."""
    return _pick(MAG_RANGES, gauss, 'magnetometer', 'gauss')


def _pick(ranges: dict[int, Range], value: float, what: str, unit: str) -> Range:
    if value not in ranges:
        raise ValueError(f'the LSM9DS0 {what} has no +-{value!r} {unit} range; it has '
                         f'{", ".join(f"+-{v}" for v in ranges)} {unit}')
    return ranges[value]


def to_counts(values, lsb_si: float, low: int = COUNTS_MIN, high: int = COUNTS_MAX
              ) -> np.ndarray:
    """SI values as the chip's integer output: rounded to counts, held at the rails.

    NaN stays NaN (a chip that did not answer); +-inf goes to the rail of its sign.
    """
    # Held a count beyond the rails before scaling (no overflow, +-inf included); clip
    # and rint keep NaN.
    held = np.minimum(np.maximum(np.asarray(values, dtype=float), (low - 1) * lsb_si),
                      (high + 1) * lsb_si)
    return np.minimum(np.maximum(np.rint(held / lsb_si), low), high)


def quantise(values, lsb_si: float, low: int = COUNTS_MIN, high: int = COUNTS_MAX
             ) -> np.ndarray:
    """What the chip reports for `values` (SI): saturated at the rails, a whole count each."""
    return to_counts(values, lsb_si, low, high) * lsb_si


def quantise_pressure(pascal) -> np.ndarray:
    """The MPL115A2's reading of `pascal`: a 10-bit code over 50-115 kPa, held at its ends."""
    counts = to_counts(np.asarray(pascal, dtype=float) - PRESSURE_MIN_PA, PRESSURE_LSB_PA, 0,
                       PRESSURE_COUNTS)
    return PRESSURE_MIN_PA + counts * PRESSURE_LSB_PA


def first_order_gain(frequency_hz, cutoff_hz: float):
    """Magnitude response of a first-order low-pass at `frequency_hz` (1 at DC).

    Plain arithmetic: a float for a float (the per-sample path), an array for an array.
    """
    ratio = frequency_hz / cutoff_hz
    return 1.0 / (1.0 + ratio * ratio) ** 0.5
