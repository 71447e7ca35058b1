# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""XM430-W350 control table (Protocol 2.0) and the unit conversions of its raw values.

Addresses and units from ROBOTIS's e-Manual for the XM430-W350. Positions are 4096
counts per revolution with 2048 at 0 rad; velocity is 0.229 rev/min per count; current
is 2.69 mA per count.
"""

from __future__ import annotations

import math

import numpy as np

MODEL_NUMBER = 0  # 2 bytes
FIRMWARE_VERSION = 6  # 1 byte
ID = 7  # 1 byte
BAUD_RATE = 8  # 1 byte, a code of BAUD_RATES
OPERATING_MODE = 11  # 1 byte
TEMPERATURE_LIMIT = 31  # 1 byte, degC (factory 80)
MAX_VOLTAGE_LIMIT = 32  # 2 bytes, 0.1 V (factory 160)
MIN_VOLTAGE_LIMIT = 34  # 2 bytes, 0.1 V (factory 95)
MAX_POSITION_LIMIT = 48  # 4 bytes, counts (factory 4095); position mode only
MIN_POSITION_LIMIT = 52  # 4 bytes, counts (factory 0)
TORQUE_ENABLE = 64  # 1 byte
HARDWARE_ERROR_STATUS = 70  # 1 byte
PROFILE_ACCELERATION = 108  # 4 bytes
PROFILE_VELOCITY = 112  # 4 bytes
GOAL_POSITION = 116  # 4 bytes
MOVING = 122  # 1 byte
PRESENT_CURRENT = 126  # 2 bytes, signed
PRESENT_VELOCITY = 128  # 4 bytes, signed
PRESENT_POSITION = 132  # 4 bytes, signed
PRESENT_INPUT_VOLTAGE = 144  # 2 bytes, 0.1 V
PRESENT_TEMPERATURE = 146  # 1 byte, degC
TABLE_SIZE = 256

XM430_W350_MODEL = 1020
STATE_BLOCK_START = PRESENT_CURRENT  # current, velocity, position: one sync read
STATE_BLOCK_LENGTH = PRESENT_POSITION + 4 - PRESENT_CURRENT  # 10 bytes

# Baud Rate (address 8) codes and their line rates; 1 (57600) is the factory setting.
BAUD_RATES = {0: 9600, 1: 57600, 2: 115200, 3: 1_000_000, 4: 2_000_000, 5: 3_000_000,
              6: 4_000_000, 7: 4_500_000}
VOLT_PER_UNIT = 0.1
# The XM430-W350's operating supply range and its recommended voltage (e-Manual).
SUPPLY_RANGE_V = (10.0, 14.8)
RECOMMENDED_V = 12.0

MODE_POSITION = 3
MODE_CURRENT_BASED_POSITION = 5
# The modes that hold a goal position (an arm in velocity or PWM mode would not hold).
HOLDING_MODES = (MODE_POSITION, MODE_CURRENT_BASED_POSITION)
# IDs a servo can have (Protocol 2.0: 253 and 254 are reserved and broadcast).
SERVO_ID_RANGE = (0, 252)

# Hardware error status bits (address 70).
ERROR_INPUT_VOLTAGE = 0x01
ERROR_OVERHEATING = 0x04
ERROR_MOTOR_ENCODER = 0x08
ERROR_ELECTRICAL_SHOCK = 0x10
ERROR_OVERLOAD = 0x20
HARDWARE_ERROR_NAMES = {ERROR_INPUT_VOLTAGE: 'input voltage', ERROR_OVERHEATING: 'overheating',
                        ERROR_MOTOR_ENCODER: 'motor encoder',
                        ERROR_ELECTRICAL_SHOCK: 'electrical shock', ERROR_OVERLOAD: 'overload'}

COUNTS_PER_REV = 4096
CENTER_COUNT = 2048
RAD_PER_COUNT = 2.0 * math.pi / COUNTS_PER_REV
RAD_S_PER_VELOCITY_UNIT = 0.229 * 2.0 * math.pi / 60.0
# Velocity Limit (address 44) holds 0..1023 units; a profile velocity above it is capped.
PROFILE_VELOCITY_RANGE_RAD_S = (RAD_S_PER_VELOCITY_UNIT, 1023 * RAD_S_PER_VELOCITY_UNIT)
AMPERE_PER_CURRENT_UNIT = 2.69e-3
POSITION_COUNT_RANGE = (0, COUNTS_PER_REV - 1)


def position_to_rad(counts):
    """Raw present/goal position -> joint angle (rad)."""
    return (np.asarray(counts, dtype=float) - CENTER_COUNT) * RAD_PER_COUNT


def rad_to_position(radians):
    """Joint angle (rad) -> raw goal position, rounded and kept within one turn."""
    counts = np.rint(np.asarray(radians, dtype=float) / RAD_PER_COUNT) + CENTER_COUNT
    return np.clip(counts, *POSITION_COUNT_RANGE).astype(np.int64)


def velocity_to_rad_s(units):
    """Raw present velocity -> rad/s."""
    return np.asarray(units, dtype=float) * RAD_S_PER_VELOCITY_UNIT


def rad_s_to_velocity(rad_s):
    """rad/s -> raw profile velocity, within PROFILE_VELOCITY_RANGE_RAD_S (0 means unlimited).

    Raises:
        ValueError: a speed that is not finite (NaN would become 0 on the wire).
    """
    rad_s = np.asarray(rad_s, dtype=float)
    if not np.all(np.isfinite(rad_s)):
        raise ValueError(f'profile velocity must be finite, got {rad_s!r}')
    low, high = (round(v / RAD_S_PER_VELOCITY_UNIT) for v in PROFILE_VELOCITY_RANGE_RAD_S)
    return np.clip(np.rint(rad_s / RAD_S_PER_VELOCITY_UNIT), low, high).astype(np.int64)


def current_to_ampere(units):
    """Raw present current -> A."""
    return np.asarray(units, dtype=float) * AMPERE_PER_CURRENT_UNIT


def describe_hardware_error(status: int) -> str:
    """Names of the bits set in a hardware error status byte."""
    names = [name for bit, name in HARDWARE_ERROR_NAMES.items() if status & bit]
    return ', '.join(names) if names else f'unknown ({status:#04x})'
