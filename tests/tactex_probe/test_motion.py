# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Tool poses of the face and the tip, and straight joint paths between them."""

import math

import numpy as np
import pytest

from tactex_description.geometry import ARM_VELOCITY_LIMIT
from tactex_description.kinematics import forward_kinematics
from tactex_probe.motion import (
    chain,
    concatenate,
    FACE_AXIS,
    FACE_TILT_RAD,
    PathUnreachable,
    pose_of,
    pose_with_tip_at,
    reachable_part,
    sensor_rotation,
    solve,
    straight_path,
    tilt_towards,
    TIP_CENTRE,
    tip_position,
    ToolPose,
    transfer,
)

SEED = [0.0, 0.0, 0.0, 1.5]


def test_face_bears_on_the_tip_and_the_opposite_rim():
    # The bearing plane is perpendicular to FACE_AXIS through both bearing points.
    assert math.degrees(FACE_TILT_RAD) == pytest.approx(3.82, abs=0.01)
    assert np.linalg.norm(FACE_AXIS) == pytest.approx(1.0)


@pytest.mark.parametrize('point, tilt', [([0.15, 0.0, 0.03], 0.0), ([0.12, 0.05, 0.02], 0.3),
                                         ([0.18, -0.04, 0.025], -0.1)])
def test_solve_and_pose_of_are_inverse(point, tilt):
    pose = ToolPose(point, tilt)
    joints = solve(pose, SEED)
    back = pose_of(joints)
    assert back.point == pytest.approx(pose.point, abs=1e-9)
    assert back.tilt == pytest.approx(tilt, abs=1e-9)
    assert forward_kinematics(joints, 'sensor_link')[:3, :3] == pytest.approx(
        sensor_rotation(pose.heading, tilt))


def test_tip_pose_places_the_tip():
    pose = pose_with_tip_at(np.array([0.14, 0.02, 0.03]), 0.4)
    assert tip_position(pose) == pytest.approx([0.14, 0.02, 0.03])
    joints = solve(pose, SEED)
    link = forward_kinematics(joints, 'sensor_link')
    assert link[:3, :3] @ TIP_CENTRE + link[:3, 3] == pytest.approx([0.14, 0.02, 0.03])


def test_tilt_towards_faces_the_normal():
    for direction in (0.0, 0.5):
        for tilt in (-0.3, 0.0, 0.4):
            pose = ToolPose([0.2 * math.cos(direction), 0.2 * math.sin(direction), 0.0], tilt)
            assert tilt_towards(-pose.axis, pose.heading) == pytest.approx(tilt)


def test_unreachable_pose_names_the_reason():
    with pytest.raises(PathUnreachable, match='out of reach'):
        solve(ToolPose([0.6, 0.0, 0.0], 0.0), SEED)


def test_straight_path_ends_on_target_within_the_speed_limits():
    start, end = ToolPose([0.12, 0.0, 0.04], 0.0), ToolPose([0.20, 0.0, 0.03], 0.3)
    path = straight_path(start, end, 0.05, solve(start, SEED))
    assert pose_of(path.joints[-1]).point == pytest.approx(end.point, abs=1e-9)
    speeds = np.abs(np.diff(path.joints, axis=0)) / np.diff(path.times_s)[:, None]
    assert speeds.max() < 0.7 * ARM_VELOCITY_LIMIT
    halfway = path.pose_at(path.duration_s / 2)
    assert halfway.point == pytest.approx((start.point + end.point) / 2)


def test_paths_concatenate_in_time_and_space():
    a, b, c = (ToolPose(p, 0.0) for p in ([0.12, 0.0, 0.04], [0.12, 0.0, 0.06],
                                          [0.16, 0.0, 0.06]))
    first = straight_path(a, b, 0.02, solve(a, SEED))
    second = straight_path(b, c, 0.02, first.joints[-1])
    both = concatenate([first, second])
    assert both.duration_s == pytest.approx(first.duration_s + second.duration_s)
    assert both.pose_at(first.duration_s).point == pytest.approx(b.point)
    assert both.end.point == pytest.approx(c.point)
    assert np.all(np.diff(both.times_s) > 0)


def test_path_through_the_unreachable_is_refused():
    start = ToolPose([0.15, 0.0, 0.03], 0.0)
    with pytest.raises(PathUnreachable):
        straight_path(start, ToolPose([0.45, 0.0, 0.03], 0.0), 0.05, solve(start, SEED))


@pytest.mark.parametrize('far', [[1e150, 0.0, 0.0], [1e300, 0.0, 0.0], [0.0, 0.0, 1e7]])
def test_a_target_far_beyond_reach_is_refused_before_a_path_to_it_is_sized(far):
    # a probe goal's start of 1e150 m sized arrays of 1e150 points (MemoryError, ValueError)
    start = ToolPose([0.15, 0.0, 0.03], 0.0)
    with pytest.raises(PathUnreachable):
        transfer(start, ToolPose(far, 0.0), 0.05, solve(start, SEED))


def test_a_chain_passes_every_pose_in_turn():
    poses = [ToolPose(p, 0.0) for p in ([0.12, 0.0, 0.04], [0.12, 0.0, 0.06],
                                         [0.16, 0.0, 0.06])]
    path = chain(poses, 0.02, solve(poses[0], SEED))
    assert np.array([knot.point for knot in path.knots]) == pytest.approx(
        np.array([pose.point for pose in poses]))


def test_a_transfer_rises_first_and_never_dips_below_its_ends():
    start, target = ToolPose([0.12, 0.0, 0.02], 0.0), ToolPose([0.18, 0.0, 0.05], 0.2)
    path = transfer(start, target, 0.05, solve(start, SEED))
    heights = [pose_of(joints).point[2] for joints in path.joints]
    assert min(heights) >= start.point[2] - 1e-9
    assert path.knots[1].point == pytest.approx([0.12, 0.0, 0.05])  # up first
    assert path.end.point == pytest.approx(target.point)


def test_a_transfer_to_where_the_arm_cannot_reach_is_refused():
    start = ToolPose([0.15, 0.0, 0.03], 0.0)
    with pytest.raises(PathUnreachable):
        transfer(start, ToolPose([0.45, 0.0, 0.03], 0.0), 0.05, solve(start, SEED))


def test_the_reachable_part_stops_where_the_arm_does():
    start = ToolPose([0.20, 0.0, 0.03], 0.0)
    path = reachable_part(start, ToolPose([0.60, 0.0, 0.03], 0.0), 0.05, solve(start, SEED))
    end = path.end.point[0]
    assert 0.20 < end < 0.60
    with pytest.raises(PathUnreachable):
        solve(ToolPose([end + 0.002, 0.0, 0.03], 0.0), path.joints[-1])
