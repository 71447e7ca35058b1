# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Trajectory playback: any trajectory is refused whole or plays finite, in-limit goals."""

import math

from hypothesis import event, example, given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from support.hard_values import anything, finite, vectors

from tactex_description.geometry import JOINT_STATE_NAMES
from tactex_driver.errors import TrajectoryRejected
from tactex_driver.playback import hold, JointLimits, plan

pytestmark = pytest.mark.hard_case

LIMITS = JointLimits.of_robot()
HOME = np.array([0.0, -0.5, 0.3, 0.8, 0.0])


@st.composite
def trajectories(draw):
    """A sane trajectory, then (usually) one time, position or velocity made extreme."""
    names = draw(st.lists(st.sampled_from(JOINT_STATE_NAMES), min_size=1, max_size=5,
                          unique=True))
    count = draw(st.integers(1, 4))
    point_times = np.cumsum(draw(st.lists(st.floats(0.5, 5.0), min_size=count,
                                          max_size=count)))
    column = [JOINT_STATE_NAMES.index(n) for n in names]
    positions = HOME[column] + np.array(draw(st.lists(
        st.lists(st.floats(-0.05, 0.05), min_size=len(names), max_size=len(names)),
        min_size=count, max_size=count)))
    velocities = np.zeros((count, len(names))) if draw(st.booleans()) else None
    part = draw(st.sampled_from(['none', 'time', 'position', 'velocity']))
    bad = draw(st.one_of(anything(), st.sampled_from([1e-300, 5e-324, 0.0])))
    point = draw(st.integers(0, count - 1))
    if part == 'time':
        point_times[point] = bad if point == 0 else point_times[point - 1] + bad
    elif part == 'position':
        positions[point, draw(st.integers(0, len(names) - 1))] = bad
    elif part == 'velocity' and velocities is not None:
        velocities[point, draw(st.integers(0, len(names) - 1))] = bad
    return (names, point_times.tolist(), positions.tolist(),
            [] if velocities is None else velocities.tolist())


@settings(max_examples=150)
@given(trajectories(), st.lists(anything(), min_size=1, max_size=6))
@example((['joint1', 'joint2'], [5e-324, 2.0, 3.0, 4.0],
          [[0.0, -0.46875], [0.0, -0.5], [0.0, -0.5], [0.0, -0.5]], []), [0.0])
@example((['joint1', 'joint2', 'joint3'], [1.0, 2.0],
          [[0.0, -0.5, 0.3], [5e-324, -0.5, 0.3]], []), [0.0])  # a subnormal step (make hunt)
def test_any_trajectory_is_refused_or_plays_finite_goals_within_the_limits(trajectory,
                                                                          sample_times):
    names, point_times, positions, velocities = trajectory
    try:
        accepted = plan(names, point_times, positions, velocities, HOME, LIMITS)
    except TrajectoryRejected as err:
        assert str(err)
        event('refused')
        return
    event('accepted')
    assert math.isfinite(accepted.duration_s) and accepted.duration_s >= 0
    for t in sample_times:
        if math.isnan(t):
            with pytest.raises(ValueError, match='NaN'):
                accepted.sample(t)
            continue
        goal = accepted.sample(t)
        assert np.all(np.isfinite(goal))
        assert np.all(goal >= LIMITS.lower) and np.all(goal <= LIMITS.upper)


@settings(max_examples=60)
@given(vectors(anything(), 5))
def test_a_non_finite_current_state_refuses_every_trajectory(current):
    if all(math.isfinite(v) for v in current):
        return
    with pytest.raises(TrajectoryRejected, match='not 5 finite positions'):
        plan(['joint1'], [1.0], [[0.0]], [], np.array(current), LIMITS)
    with pytest.raises(ValueError, match='non-finite'):
        hold(np.array(current), LIMITS)


@settings(max_examples=60)
@given(vectors(finite(), 5))
def test_holding_any_finite_pose_stays_within_the_limits(pose):
    goal = hold(np.array(pose), LIMITS).sample(0.0)
    assert np.all(goal >= LIMITS.lower) and np.all(goal <= LIMITS.upper)


@given(st.sampled_from([math.nan, math.inf, -1.0]))
def test_a_bad_start_tolerance_is_a_clear_error(tolerance):
    with pytest.raises(ValueError, match='start_tolerance'):
        plan(['joint1'], [1.0], [[0.0]], [], HOME, LIMITS, start_tolerance=tolerance)
