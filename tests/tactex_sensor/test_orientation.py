# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Orientation from gravity (eqs. 3.1-3.6): exact, and stable where the cross product vanishes."""

import math

from hypothesis import given
from hypothesis import strategies as st
import numpy as np
import pytest

from tactex_sensor.errors import ReadingError
from tactex_sensor.orientation import orientation_from_gravity, rotate

unit_components = st.floats(-1.0, 1.0, allow_nan=False)


@given(unit_components, unit_components, unit_components, st.floats(-math.pi, math.pi))
def test_measured_gravity_maps_onto_world_up(x, y, z, yaw):
    accel = np.array([x, y, z])
    if np.linalg.norm(accel) < 1e-6:
        return
    q = orientation_from_gravity(9.81 * accel, yaw)
    assert abs(np.linalg.norm(q) - 1.0) < 1e-12
    np.testing.assert_allclose(rotate(q, accel / np.linalg.norm(accel)), [0, 0, 1],
                               atol=1e-9)


@pytest.mark.parametrize('accel', [(0, 0, 9.81), (0, 0, -9.81), (1e-12, 0, -9.81),
                                   (0, -1e-300, -9.81), (1e-9, 1e-9, 9.81),
                                   (1e300, 0, -1e300), (3.4e38, 3.4e38, 3.4e38),
                                   (0, 5e-324, 0), (1e-320, 0, -1e-320)])
def test_aligned_and_opposite_gravity_are_exact(accel):
    q = orientation_from_gravity(accel)
    assert np.all(np.isfinite(q))
    direction = np.array(accel) / np.max(np.abs(accel))  # no overflow, no underflow
    np.testing.assert_allclose(rotate(q, direction / np.linalg.norm(direction)), [0, 0, 1],
                               atol=1e-12)


def test_base_yaw_rotates_about_world_z():
    q = orientation_from_gravity((0, 0, 9.81), math.pi / 2)
    np.testing.assert_allclose(rotate(q, (1, 0, 0)), (0, 1, 0), atol=1e-12)


@pytest.mark.parametrize('accel', [(0, 0, 0), (math.nan, 0, 9.8), (0, math.inf, 0),
                                   (-0.0, 0.0, -0.0), (1.0, 2.0)])
def test_zero_or_non_finite_accel_is_rejected(accel):
    with pytest.raises(ReadingError, match='finite non-zero'):
        orientation_from_gravity(accel)


@pytest.mark.parametrize('yaw', [math.nan, math.inf])
def test_non_finite_base_yaw_is_rejected(yaw):
    with pytest.raises(ReadingError, match='base_yaw_rad'):
        orientation_from_gravity((0.0, 0.0, 9.81), yaw)
