# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Trajectory validation: refused as a whole with the reason, or played within the limits."""

import math

import numpy as np
import pytest

from tactex_driver.errors import TrajectoryRejected
from tactex_driver.playback import JointLimits, plan

LIMITS = JointLimits.of_robot()
HOME = np.zeros(5)
ARM = ['joint1', 'joint2', 'joint3', 'joint4']


def plan_arm(times, rows, velocities=(), current=HOME, **kwargs):
    return plan(ARM, times, rows, list(velocities) or [[] for _ in times], current, LIMITS,
                **kwargs)


def test_limits_come_from_the_robot_description():
    assert LIMITS.names == ('joint1', 'joint2', 'joint3', 'joint4', 'gripper')
    assert LIMITS.upper[0] == pytest.approx(0.9 * math.pi)
    assert LIMITS.velocity[0] == 2.0


def test_accepted_trajectory_starts_at_the_state_and_ends_at_the_last_point():
    trajectory = plan_arm([0.0, 1.0, 2.0], [[0, 0, 0, 0], [0.3, 0.1, 0.0, 0.2],
                                            [0.5, 0.2, -0.1, 0.3]])
    np.testing.assert_allclose(trajectory.sample(0.0), HOME)
    np.testing.assert_allclose(trajectory.sample(2.0)[:4], [0.5, 0.2, -0.1, 0.3])
    np.testing.assert_allclose(trajectory.sample(99.0)[:4], [0.5, 0.2, -0.1, 0.3])
    assert trajectory.duration_s == 2.0


def test_unnamed_joints_hold_their_position():
    current = np.array([0.1, 0.2, 0.3, 0.4, 0.01])
    trajectory = plan(['joint2'], [1.0], [[0.25]], [[]], current, LIMITS)
    np.testing.assert_allclose(trajectory.sample(1.0), [0.1, 0.25, 0.3, 0.4, 0.01])


def test_shape_preserving_interpolation_never_overshoots_between_points():
    rows = [[0.0, 0, 0, 0], [1.0, 0, 0, 0], [1.0, 0, 0, 0], [0.2, 0, 0, 0]]
    trajectory = plan_arm([0.0, 1.0, 1.5, 3.0], rows)
    samples = np.array([trajectory.sample(t)[0] for t in np.linspace(0, 3, 601)])
    assert samples.max() <= 1.0 + 1e-12 and samples.min() >= -1e-12


@pytest.mark.parametrize('names, times, rows, match', [
    ([], [1.0], [[]], 'names no joints'),
    (['joint9'], [1.0], [[0.1]], 'unknown joint'),
    (['joint1', 'joint1'], [1.0], [[0.1, 0.1]], 'repeat'),
    (ARM, [], [], 'no points'),
    (ARM, [1.0], [[0.1, 0.2]], 'each point needs 4 positions'),
    (ARM, [1.0], [[math.nan, 0, 0, 0]], 'NaN'),
    (ARM, [1.0], [[math.inf, 0, 0, 0]], 'NaN or infinity'),
    (ARM, [2.0, 1.0], [[0.1, 0, 0, 0], [0.2, 0, 0, 0]], 'strictly increasing'),
    (ARM, [1.0, 1.0], [[0.1, 0, 0, 0], [0.2, 0, 0, 0]], 'strictly increasing'),
    (ARM, [math.nan], [[0.1, 0, 0, 0]], 'finite'),
    (ARM, [1.0, 2.0], [[0.05, 0, 0, 0], [0.1, 0, 2.0, 0]], 'joint3 = 2.0000 is outside'),
    (ARM, [1.0], [[0.5, 0, 0, 0]], 'first point is 0.500 from the current joint1'),
    (ARM, [0.0, 0.5], [[0.0, 0, 0, 0], [2.0, 0, 0, 0]], 'joint1 would move at'),
    (ARM, [2.0], [[0.5, 0, 0, 0]], 'first point is 0.500 from'),
])
def test_bad_trajectories_are_refused_with_the_reason(names, times, rows, match):
    with pytest.raises(TrajectoryRejected, match=match):
        plan(names, times, rows, [[] for _ in times], HOME, LIMITS)


def test_point_velocities_beyond_the_limit_are_refused():
    with pytest.raises(TrajectoryRejected, match='velocity'):
        plan_arm([1.0], [[0.05, 0, 0, 0]], velocities=[[3.0, 0, 0, 0]])


def test_hermite_overshoot_past_a_limit_is_refused():
    top = LIMITS.upper[2]
    with pytest.raises(TrajectoryRejected, match='leaves the position limits'):
        plan_arm([1.0, 2.0], [[0, 0, top - 0.05, 0], [0, 0, top - 0.05, 0]],
                 velocities=[[0, 0, 1.5, 0], [0, 0, 0, 0]],
                 current=np.array([0, 0, top - 0.1, 0, 0]))


def test_samples_are_always_within_the_limits():
    low, high = LIMITS.lower[1], LIMITS.upper[1]
    trajectory = plan_arm([3.0], [[0, high, 0, 0]], current=np.array([0, high - 0.05, 0, 0, 0]),
                          start_tolerance=10.0)
    for t in np.linspace(0, 3, 50):
        q = trajectory.sample(t)
        assert np.all(q >= LIMITS.lower) and np.all(q <= LIMITS.upper)
    assert low < high
