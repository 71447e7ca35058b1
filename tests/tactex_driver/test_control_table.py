# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""XM430-W350 raw units: 4096 counts per turn with 2048 at zero, 0.229 rpm, 2.69 mA."""

import math

import numpy as np
import pytest

from tactex_driver import control_table as ct


def test_position_counts_roundtrip_and_centre():
    assert ct.position_to_rad(2048) == 0.0
    assert math.isclose(ct.position_to_rad(3072), math.pi / 2)
    angles = np.linspace(-3.0, 3.0, 101)
    np.testing.assert_allclose(ct.position_to_rad(ct.rad_to_position(angles)), angles,
                               atol=ct.RAD_PER_COUNT / 2)


def test_goal_counts_stay_within_one_turn():
    assert ct.rad_to_position(10.0) == 4095 and ct.rad_to_position(-10.0) == 0


def test_velocity_and_current_units():
    assert math.isclose(float(ct.velocity_to_rad_s(100)), 100 * 0.229 * 2 * math.pi / 60)
    assert math.isclose(float(ct.current_to_ampere(-1000)), -2.69)
    assert ct.rad_s_to_velocity(0.0) == 1  # 0 would mean "no limit" to the servo


@pytest.mark.parametrize('speed', [float('nan'), float('inf'), -float('inf')])
def test_a_profile_velocity_that_is_not_finite_never_reaches_the_wire(speed):
    with pytest.raises(ValueError, match='must be finite'):
        ct.rad_s_to_velocity(speed)  # NaN cast to int and masked to 32 bits read 0: no limit


def test_a_profile_velocity_beyond_the_velocity_limit_register_is_capped():
    assert ct.rad_s_to_velocity(1e8) == 1023 and ct.rad_s_to_velocity(-5.0) == 1


def test_state_block_is_current_velocity_position():
    assert (ct.STATE_BLOCK_START, ct.STATE_BLOCK_LENGTH) == (126, 10)


def test_hardware_error_names():
    assert ct.describe_hardware_error(0x24) == 'overheating, overload'
