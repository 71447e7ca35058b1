# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The sweep planner: one trajectory from the present joints, at the sliding speed."""

import math

from conftest import START_JOINTS, wave_pathway
import numpy as np
import pytest

from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_driver.playback import JointLimits, plan
from tactex_trajectory.errors import PathError, SweepRefused
from tactex_trajectory.planner import MIN_CONTACT_S, plan_sweep, retract, SweepSettings
from tactex_trajectory.poses import ARM, PoseSettings
from tactex_trajectory.timing import ACCELERATION_LIMITS, VELOCITY_LIMITS


@pytest.fixture(scope='module')
def sweep():
    return plan_sweep(*wave_pathway(), None, START_JOINTS)


def edges(joints):
    return np.array([ARM.tool_pose(q)[0] for q in joints])


def test_trajectory_starts_at_the_present_joints_and_the_driver_accepts_it(sweep):
    trajectory = sweep.trajectory
    np.testing.assert_allclose(trajectory.positions[0], START_JOINTS[:4])
    np.testing.assert_allclose(trajectory.velocities[[0, -1]], 0.0, atol=1e-12)
    accepted = plan(list(trajectory.joint_names), trajectory.times_s.tolist(),
                    trajectory.positions.tolist(), trajectory.velocities.tolist(), START_JOINTS,
                    JointLimits.of_robot())
    assert accepted.duration_s == pytest.approx(trajectory.duration_s)


def test_phases_follow_each_other_and_the_contact_segment_is_in_the_slide(sweep):
    assert [p.name for p in sweep.phases] == ['move', 'descend', 'settle', 'slide', 'lift']
    for before, after in zip(sweep.phases[:-1], sweep.phases[1:], strict=True):
        assert before.end_s == pytest.approx(after.start_s)
    slide = sweep.phase('slide')
    assert slide.start_s < sweep.contact_start_s < sweep.contact_end_s < slide.end_s
    assert sweep.phases[-1].end_s == pytest.approx(sweep.trajectory.duration_s)
    assert sweep.phase_at(sweep.contact_start_s) == 'slide'


def test_edge_slides_at_the_set_speed_over_the_contact_segment(sweep):
    t = np.arange(sweep.contact_start_s, sweep.contact_end_s, 0.25)
    travel = sweep.path.travel_of(edges(sweep.trajectory.interpolant()(t)))
    speed = np.diff(travel) / np.diff(t)
    np.testing.assert_allclose(speed, 0.015, rtol=0.005)
    assert sweep.travel_at(sweep.contact_start_s) == pytest.approx(travel[0], abs=2e-4)


def test_joint_velocities_and_accelerations_stay_within_the_limits(sweep):
    curve = sweep.trajectory.interpolant()
    t = np.linspace(0.0, sweep.trajectory.duration_s, 20000)
    assert np.all(np.abs(curve.derivative(1)(t)) <= VELOCITY_LIMITS)
    assert np.all(np.abs(sweep.trajectory.accelerations) <= ACCELERATION_LIMITS)


def test_descent_and_lift_run_along_the_normal_at_the_path_ends(sweep):
    trajectory = sweep.trajectory
    at = {name: edges(trajectory.interpolant()([sweep.phase(name).start_s,
                                               sweep.phase(name).end_s]))
          for name in ('descend', 'lift')}
    height = sweep.settings.approach_height_m
    for name, index, sign in (('descend', 0, -1.0), ('lift', -1, 1.0)):
        moved = at[name][1] - at[name][0]
        np.testing.assert_allclose(moved, sign * height * sweep.path.normals[index], atol=1e-6)


def test_a_sweep_that_starts_above_the_first_sample_has_no_move():
    points, normals = wave_pathway()
    first = plan_sweep(points, normals, None, START_JOINTS)
    again = plan_sweep(points, normals, None, first.trajectory.positions[
        np.searchsorted(first.trajectory.times_s, first.phase('descend').start_s)])
    assert [p.name for p in again.phases][0] == 'descend'


def test_a_start_close_to_the_surface_moves_via_a_lift():
    points, normals = wave_pathway()
    low = plan_sweep(points, normals, None, START_JOINTS).poses.joints[40]  # pressed in
    sweep = plan_sweep(points, normals, None, low)
    start = edges(sweep.trajectory.positions[:1])[0]
    move = sweep.phase('move')
    t = np.linspace(move.start_s, move.end_s, 50)
    heights = edges(sweep.trajectory.interpolant()(t))[:, 2] - start[2]
    assert np.max(heights) > 0.02  # rose before travelling


def test_retract_lifts_the_edge_off_along_the_normal_from_where_the_arm_is(sweep):
    joints = sweep.trajectory.interpolant()(0.5 * (sweep.contact_start_s + sweep.contact_end_s))
    lift = retract(sweep, joints)
    np.testing.assert_allclose(lift.positions[0], joints)
    start, end = edges(lift.positions[[0, -1]])
    travel = sweep.path.travel_of(start)[0]
    normal = np.array([np.interp(travel, sweep.path.arclength_m, sweep.path.normals[:, k])
                       for k in range(3)])
    np.testing.assert_allclose(end - start, sweep.settings.approach_height_m
                               * normal / np.linalg.norm(normal), atol=2e-4)
    assert np.all(np.abs(lift.velocities) <= VELOCITY_LIMITS)


def test_retract_holds_an_arm_already_clear_of_the_surface(sweep):
    lifted = sweep.trajectory.positions[-1]
    lift = retract(sweep, lifted)
    assert len(lift.times_s) == 1
    np.testing.assert_allclose(lift.positions[0], lifted)


def test_a_path_too_short_for_the_ramps_is_refused():
    with pytest.raises(SweepRefused, match='mm long; ramping to 15 mm/s'):
        plan_sweep([[0.15, 0.0, 0.0265], [0.1525, 0.0, 0.0265]], [[0, 0, 1.0], [0, 0, 1.0]],
                   None, START_JOINTS)


def two_contacts(apart_m):
    """A pathway of two probed contacts `apart_m` apart on the uneven scene's wave."""
    points, normals = wave_pathway(start=0.10, end=0.10 + apart_m, step=apart_m,
                                   position_sd=0.0, normal_sd=0.0)
    return points[:2], normals[:2]


def test_a_two_contact_pathway_too_short_to_measure_the_speed_is_refused():
    # 10 mm: the constant-speed segment would last 0.23 s, less than one speed window,
    # so the sweep would end with no measured speed (it used to succeed with NaN).
    with pytest.raises(SweepRefused, match=f'at least {MIN_CONTACT_S:g} s .*probe a longer '
                                           'pathway or slide slower'):
        plan_sweep(*two_contacts(0.010), None, START_JOINTS)


def test_a_two_contact_pathway_long_enough_slides_at_least_the_shortest_contact():
    sweep = plan_sweep(*two_contacts(0.020), None, START_JOINTS)
    assert sweep.contact_end_s - sweep.contact_start_s >= MIN_CONTACT_S


def test_a_speed_the_joints_cannot_follow_is_refused():
    with pytest.raises(SweepRefused, match='cannot follow the path at 3000.0 mm/s'):
        plan_sweep(*wave_pathway(), None, START_JOINTS, SweepSettings(sliding_speed_m_s=3.0))


def test_one_contact_is_refused_before_anything_moves():
    with pytest.raises(PathError, match='at least 2 usable contacts'):
        plan_sweep([[0.15, 0.0, 0.02]], [[0.0, 0.0, 1.0]], None, START_JOINTS)


@pytest.mark.parametrize('joints', [[0.0, 0.0, 0.0], [0.0, math.nan, 0.0, 0.0]])
def test_bad_start_joints_are_refused(joints):
    with pytest.raises(ValueError, match='start_joints'):
        plan_sweep(*wave_pathway(), None, joints)


@pytest.mark.parametrize('name, value', [('sliding_speed_m_s', 0.0),
                                         ('approach_height_m', math.inf), ('settle_s', -1.0)])
def test_settings_out_of_range_are_refused(name, value):
    with pytest.raises(ValueError, match=name):
        SweepSettings(**{name: value})


def test_the_press_depth_and_the_rim_radius_set_where_the_edge_goes():
    points, normals = wave_pathway(position_sd=0.0, normal_sd=0.0)
    deep = plan_sweep(points, normals, None, START_JOINTS,
                      SweepSettings(pose=PoseSettings(press_depth_m=0.003)))
    depth = EDGE_TIP_RADIUS_M - np.sum((deep.poses.edge_positions - deep.path.points)
                                          * deep.path.normals, axis=1)
    np.testing.assert_allclose(depth, 0.003, atol=1e-9)
