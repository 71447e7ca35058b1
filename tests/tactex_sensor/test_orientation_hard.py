# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Orientation from gravity (eqs. 3.1-3.6) under any reading."""

import math

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from support.hard_values import anything, finite, vectors

from tactex_sensor.errors import ReadingError
from tactex_sensor.orientation import orientation_from_gravity, rotate

pytestmark = pytest.mark.hard_case


def _direction(accel) -> np.ndarray:
    a = np.array(accel, dtype=float)
    a = a / np.max(np.abs(a))
    return a / np.linalg.norm(a)


@settings(max_examples=200)
@given(vectors(finite()), finite())
def test_any_finite_non_zero_reading_gives_the_unit_quaternion_lifting_it_to_up(accel, yaw):
    if not any(accel):
        with pytest.raises(ReadingError, match='finite non-zero'):
            orientation_from_gravity(accel, yaw)
        return
    q = orientation_from_gravity(accel, yaw)
    assert np.all(np.isfinite(q)) and abs(np.linalg.norm(q) - 1.0) < 1e-12
    np.testing.assert_allclose(rotate(q, _direction(accel)), [0.0, 0.0, 1.0], atol=1e-9)


@settings(max_examples=100)
@given(vectors(anything()), st.one_of(finite(), st.sampled_from([math.nan, math.inf])))
def test_a_non_finite_reading_or_yaw_is_a_reading_error(accel, yaw):
    if all(math.isfinite(v) for v in (*accel, yaw)) and any(accel):
        assert np.all(np.isfinite(orientation_from_gravity(accel, yaw)))
    else:
        with pytest.raises(ReadingError):
            orientation_from_gravity(accel, yaw)


@given(st.lists(finite(), max_size=5).filter(lambda v: len(v) != 3))
def test_a_reading_that_is_not_a_3_vector_is_a_reading_error(values):
    with pytest.raises(ReadingError, match='3-vector'):
        orientation_from_gravity(values)


@settings(max_examples=200)
@given(vectors(anything(), 4), vectors(anything(), 4))
def test_the_angle_between_any_two_quaternions_is_an_angle_or_nan_for_no_attitude(q_a, q_b):
    from tactex_sensor.orientation import angle_between, tilt_between
    attitudes = all(np.all(np.isfinite(q)) and any(q) for q in (q_a, q_b))
    for angle in (angle_between(q_a, q_b), tilt_between(q_a, q_b)):
        if attitudes:
            assert 0.0 <= angle <= math.pi + 1e-12
        else:  # a zero quaternion is no attitude, never the identity
            assert math.isnan(angle)
    if attitudes:
        assert angle_between(q_a, q_a) < 1e-6 and tilt_between(q_b, q_b) < 1e-6
