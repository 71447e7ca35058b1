# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Time laws and their stretching to the joint limits."""

import math

import numpy as np
import pytest

from tactex_description.speed_ramp import ramped_law
from tactex_trajectory.errors import SweepRefused
from tactex_trajectory.timing import (
    ACCELERATION_LIMITS,
    concatenate,
    JointPath,
    min_jerk_law,
    move_duration,
    ramp_duration,
    timed_move,
    VELOCITY_LIMITS,
)


def test_limits_come_from_the_robot_description():
    np.testing.assert_allclose(VELOCITY_LIMITS, 2.0)
    np.testing.assert_allclose(ACCELERATION_LIMITS, 4.0)


def test_min_jerk_rests_at_both_ends_and_peaks_in_the_middle():
    law = min_jerk_law(0.02, 2.0)
    t = np.linspace(0.0, 2.0, 2001)
    assert law.position(np.array([0.0, 2.0])).tolist() == pytest.approx([0.0, 0.02])
    assert law.speed(np.array([0.0, 2.0])).tolist() == pytest.approx([0.0, 0.0])
    assert np.max(law.speed(t)) == pytest.approx(1.875 * 0.02 / 2.0, rel=1e-6)
    np.testing.assert_allclose(np.gradient(law.position(t), t), law.speed(t), atol=1e-5)


def test_ramped_law_holds_the_speed_between_its_ramps():
    law = ramped_law(0.1, 0.015, 0.5)
    t = np.linspace(0.0, law.duration_s, 20001)
    assert law.position(np.array([law.duration_s]))[0] == pytest.approx(0.1)
    cruise = (t > 0.5) & (t < law.duration_s - 0.5)
    np.testing.assert_allclose(law.speed(t[cruise]), 0.015)
    assert law.speed(np.array([0.0]))[0] == 0.0
    np.testing.assert_allclose(np.gradient(law.position(t), t), law.speed(t), atol=1e-6)
    np.testing.assert_allclose(np.gradient(law.speed(t), t), law.acceleration(t), atol=1e-4)
    assert np.all(np.diff(law.position(t)) >= 0)


def test_moves_are_stretched_within_the_joint_limits():
    path = JointPath(np.array([0.0, 1.0]), np.array([[0.0, 0.0, 0.0, 0.0],
                                                     [2.0, -1.0, 0.5, 1.0]]))
    move = timed_move(path, move_duration(path))
    dense = move.interpolant()
    t = np.linspace(0.0, move.duration_s, 4001)
    assert np.all(np.abs(dense.derivative(1)(t)) <= VELOCITY_LIMITS + 1e-6)
    assert np.all(np.abs(move.accelerations) <= ACCELERATION_LIMITS + 1e-6)
    np.testing.assert_allclose(move.positions[[0, -1]], path.joints, atol=1e-12)
    np.testing.assert_allclose(move.velocities[[0, -1]], 0.0, atol=1e-12)


def test_a_move_can_be_capped_by_its_edge_speed():
    path = JointPath(np.array([0.0, 0.02]), np.array([[0.0] * 4, [0.01] * 4]))
    assert move_duration(path, peak_speed=0.01) == pytest.approx(1.875 * 0.02 / 0.01)
    assert move_duration(path, minimum_s=7.0) == 7.0


def test_a_speed_the_joints_cannot_follow_is_refused_with_the_fastest_that_works():
    path = JointPath(np.linspace(0.0, 0.1, 11), np.outer(np.linspace(0.0, 2.0, 11), [1.0] * 4))
    with pytest.raises(SweepRefused, match=r'cannot follow the path at 200.0 mm/s.*slide at '
                                           r'most 8\d\.\d mm/s'):
        ramp_duration(path, 0.2, 0.05)
    assert ramp_duration(path, 0.015, 0.05) == pytest.approx(math.pi * 0.015 / 0.1)


def test_parts_join_end_to_start():
    path = JointPath(np.array([0.0, 1.0]), np.array([[0.0] * 4, [0.1] * 4]))
    first = timed_move(path, 1.0)
    joined = concatenate([first, first])
    assert joined.duration_s == pytest.approx(2.0)
    assert len(joined.times_s) == 2 * len(first.times_s) - 1
    assert np.all(np.diff(joined.times_s) > 0)
