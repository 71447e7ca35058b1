# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Path fitting, pose solving, time laws and whole sweep plans under any contacts and settings.

Every input either gives a path of unit normals across unit tangents over increasing arc
length, and a plan whose times strictly increase and whose joints stay within the limits
(the driver accepts it), or a clear TrajectoryError (ValueError for bad settings).
Planning keeps no state, so there is nothing to recover.
"""

import functools
import math

from hypothesis import example, given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from support.hard_values import anything, finite, FLOAT32_MAX, FLOAT64_MAX, vectors

from tactex_description.speed_ramp import ramped_law
from tactex_driver.playback import JointLimits
from tactex_sim.scene import load_scene, resolve_scene
from tactex_trajectory.errors import PathError, SweepRefused, TrajectoryError
from tactex_trajectory.path import path_from_contacts, PathSettings
from tactex_trajectory.planner import plan_sweep, SweepSettings
from tactex_trajectory.poses import solve_poses
from tactex_trajectory.simulated_sweeps import probe_like_pathway
from tactex_trajectory.timing import (
    JointPath,
    MAX_PART_S,
    min_jerk_law,
    move_duration,
    timed_move,
)

pytestmark = pytest.mark.hard_case

START_JOINTS = np.array([0.0, -0.3, 0.3, 1.2, 0.0])
LIMITS = JointLimits.of_robot()
# Positive finite values that break arithmetic: subnormal, tiny, huge.
EXTREME_POSITIVE = (5e-324, 1e-300, FLOAT32_MAX, 1e300)


@functools.cache
def contacts() -> tuple[np.ndarray, np.ndarray]:
    surface = load_scene(resolve_scene('uneven_texture')).surface
    return probe_like_pathway(surface, 0.085, 0.22, 0.01, np.random.default_rng(0))


@functools.cache
def good_plan():
    return plan_sweep(*contacts(), None, START_JOINTS)


@st.composite
def spoilt_contacts(draw):
    """The probed contacts, some cut away and one coordinate of one made extreme."""
    points, normals = (a.copy() for a in contacts())
    count = draw(st.integers(0, len(points)))
    points, normals = points[:count], normals[:count]
    ok = np.ones(count, dtype=bool)
    if count and draw(st.booleans()):
        index, axis = draw(st.integers(0, count - 1)), draw(st.integers(0, 2))
        target = draw(st.sampled_from(['point', 'normal', 'ok']))
        if target == 'ok':
            ok[index] = False
        else:
            (points if target == 'point' else normals)[index, axis] = draw(anything())
    return points, normals, ok


def assert_valid_path(path):
    for vectors_ in (path.points, path.normals, path.tangents):
        assert np.all(np.isfinite(vectors_))
    np.testing.assert_allclose(np.linalg.norm(path.normals, axis=1), 1.0, atol=1e-9)
    np.testing.assert_allclose(np.linalg.norm(path.tangents, axis=1), 1.0, atol=1e-9)
    np.testing.assert_allclose(np.sum(path.normals * path.tangents, axis=1), 0.0, atol=1e-6)
    assert path.arclength_m[0] == 0.0 and np.all(np.diff(path.arclength_m) > 0)
    assert np.all(np.isfinite(path.contact_arclength_m))


def assert_valid_trajectory(trajectory):
    assert np.all(np.diff(trajectory.times_s) > 0) and trajectory.times_s[0] == 0.0
    for values in (trajectory.times_s, trajectory.positions, trajectory.velocities,
                   trajectory.accelerations):
        assert np.all(np.isfinite(values))
    assert np.all(trajectory.positions >= LIMITS.lower[:4])
    assert np.all(trajectory.positions <= LIMITS.upper[:4])


@example((np.array([[FLOAT32_MAX, 0.0, 0.026], [0.095, 0.0, 0.024]]),
          np.array([[0.06, 0.03, 1.0], [0.28, -0.01, 0.96]]), np.ones(2, dtype=bool)))
@example((np.array([[1e300, 0.0, 0.026], [0.095, 0.0, 0.024]]),
          np.array([[0.06, 0.03, 1.0], [0.28, -0.01, 0.96]]), np.ones(2, dtype=bool)))
@example((np.array([[3.94604064e153, -1.32104863e-4, 2.63678293e-2],
                    [9.51049001e-2, -5.35669373e-4, 2.40184493e-2],
                    [1.06304e-1, 9.47080963e-4, 1.93668171e-2]]),
          np.array([[0.06098615, 0.02723276, 0.99776704], [0.27511718, -0.01095685, 0.96134826],
                    [0.32670375, 0.06817846, 0.9426645]]),
          np.ones(3, dtype=bool)))  # a far contact among three (make hunt)
@example((np.array([[0.085, 0.0, 0.026], [0.095, 0.0, 0.024]]),
          np.array([[1.34e154, 0.03, 1.0], [0.28, -0.01, 0.96]]), np.ones(2, dtype=bool)))
@settings(max_examples=40, deadline=None)
@given(spoilt_contacts())
def test_any_contacts_give_a_path_of_unit_normals_or_a_path_error(spoilt):
    try:
        path = path_from_contacts(*spoilt)
    except PathError as err:
        assert 'contact' in str(err) or 'shape' in str(err)
        return
    assert_valid_path(path)
    assert set(path.kept.tolist()) <= set(range(len(spoilt[0])))


@pytest.mark.parametrize('points, normals', [
    ([], []), (np.zeros((0, 3)), np.zeros((0, 3))), ([[0.15, 0.0, 0.02]], [[0.0, 0.0, 1.0]]),
    ([[0.15, 0.0, 0.02]] * 5, [[0.0, 0.0, 1.0]] * 5), ([1.0, 2.0, 3.0], [0.0, 0.0, 1.0]),
    ([['a', 'b', 'c']] * 2, [[0.0, 0.0, 1.0]] * 2)])
def test_empty_single_repeated_and_malformed_contacts_are_a_path_error(points, normals):
    with pytest.raises(PathError):
        path_from_contacts(points, normals)


def made_or_refused(settings_class, name, value):
    """Settings with `name` set to `value`, or None when refused with a message naming it."""
    try:
        return settings_class(**{name: value})
    except ValueError as err:
        assert name in str(err)
        return None


@example('spacing_m', 5e-324)
@example('position_noise_m', 5e-324)
@settings(max_examples=30, deadline=None)
@given(st.sampled_from(['spacing_m', 'merge_within_m', 'position_noise_m',
                        'normal_noise_rad', 'position_tolerance_m', 'normal_tolerance_rad']),
       st.one_of(st.sampled_from(EXTREME_POSITIVE), anything()))
def test_any_path_setting_gives_a_valid_path_or_a_clear_error(name, value):
    path_settings = made_or_refused(PathSettings, name, value)
    if path_settings is None:
        return
    try:
        path = path_from_contacts(*contacts(), None, path_settings)
    except PathError:
        return
    assert_valid_path(path)


@example('sliding_speed_m_s', 1e300)
@example('descent_speed_m_s', 1e-300)
@example('sliding_speed_m_s', FLOAT64_MAX)  # make hunt
@example('approach_height_m', 1e300)
@settings(max_examples=20, deadline=None)
@given(st.sampled_from(['sliding_speed_m_s', 'approach_height_m', 'descent_speed_m_s',
                        'ramp_acceleration_m_s2', 'settle_s']),
       st.one_of(st.sampled_from(EXTREME_POSITIVE), anything()))
def test_any_sweep_setting_gives_a_plan_within_the_limits_or_a_clear_error(name, value):
    sweep_settings = made_or_refused(SweepSettings, name, value)
    if sweep_settings is None:
        return
    try:
        plan = plan_sweep(*contacts(), None, START_JOINTS, sweep_settings)
    except TrajectoryError as err:
        assert str(err)
        return
    assert_valid_trajectory(plan.trajectory)
    assert 0 <= plan.contact_start_s < plan.contact_end_s <= plan.trajectory.duration_s


@example((0.0, 0.0, 0.0, FLOAT64_MAX, 0.0))
@settings(max_examples=20, deadline=None)
@given(st.one_of(vectors(anything(), 5), vectors(st.floats(-3.0, 3.0), 4)))
def test_any_start_gives_a_plan_from_it_or_a_clear_error(start):
    try:
        plan = plan_sweep(*contacts(), None, start)
    except ValueError as err:
        assert 'start_joints' in str(err)
        assert not all(math.isfinite(v) for v in start)
        return
    except TrajectoryError as err:
        assert str(err)
        return
    assert_valid_trajectory(plan.trajectory)
    np.testing.assert_allclose(plan.trajectory.positions[0], start[:4], atol=1e-9)


@settings(max_examples=100)
@given(anything())
def test_a_plan_reports_a_travel_within_the_path_at_any_time(t):
    plan = good_plan()
    if math.isnan(t):
        return
    travel = plan.travel_at(t)
    assert 0.0 <= travel <= plan.path.length_m
    assert plan.phase_at(t) in {'', *(p.name for p in plan.phases)}


@settings(max_examples=100)
@given(st.lists(vectors(finite()), min_size=1, max_size=4))
def test_the_travel_of_any_finite_position_lies_on_the_path(positions):
    path = good_plan().path
    travel = path.travel_of(np.array(positions))
    assert np.all(np.isfinite(travel))
    assert np.all(travel >= 0.0) and np.all(travel <= path.length_m)


@settings(max_examples=60, deadline=None)
@given(vectors(anything()))
def test_solving_a_pose_anywhere_gives_joints_within_the_limits_or_a_clear_error(position):
    rotation = good_plan().poses.rotations[0]
    if not all(math.isfinite(v) for v in position):
        with pytest.raises(ValueError, match='finite'):
            solve_poses(np.array([position]), rotation[None], START_JOINTS[:4], 0.05)
        return
    try:
        poses = solve_poses(np.array([position]), rotation[None], START_JOINTS[:4], 0.05)
    except SweepRefused as err:
        assert str(err)
        return
    assert np.all(np.isfinite(poses.joints))
    assert np.all(poses.joints >= LIMITS.lower[:4]) and np.all(poses.joints <= LIMITS.upper[:4])


@settings(max_examples=60)
@given(st.floats(0.0, 1.0), st.sampled_from([(0, 1), (0, 2), (1, 3), (2, 3)]),
       st.one_of(st.sampled_from(EXTREME_POSITIVE), st.floats(1e-3, 3.0)))
def test_a_move_between_any_poses_in_reach_keeps_the_limits_or_is_refused_as_too_slow(
        fraction, pair, peak):
    joints = good_plan().poses.joints
    goal = joints[pair[0]] + fraction * (joints[-1 - pair[1]] - joints[pair[0]])
    path = JointPath(np.array([0.0, 1.0]), np.stack([START_JOINTS[:4], goal]))
    duration = move_duration(path, peak_speed=peak, minimum_s=0.5)
    assert duration >= 0.5
    if duration > MAX_PART_S:
        with pytest.raises(SweepRefused, match='raise its speed'):
            timed_move(path, duration)
        return
    assert_valid_trajectory(timed_move(path, duration))


@example(1.0, 5.5, 1.7e-276)
@example(1.0, 0.5, FLOAT64_MAX)  # t / T overflowed (make hunt)
@settings(max_examples=100)
@given(st.floats(1e-6, 10.0), st.floats(0.01, MAX_PART_S), anything())
def test_the_time_laws_stay_on_the_path_at_any_time(length, duration, t):
    if math.isnan(t):
        return
    for law in (min_jerk_law(length, duration), ramped_law(length, length / duration,
                                                           duration / 4)):
        s = float(law.position(np.array(t)))
        assert math.isfinite(s) and 0.0 <= s <= length * (1 + 1e-12)
        assert math.isfinite(float(law.speed(np.array(t))))
