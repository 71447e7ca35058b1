# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Sweep poses: the rim pressed into the path, tilted by the offset, one IK branch."""

import math

from conftest import START_JOINTS, wave_pathway
import numpy as np
import pytest

from tactex_description.kinematics import forward_kinematics
from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_trajectory.errors import SweepRefused
from tactex_trajectory.path import path_from_contacts
from tactex_trajectory.poses import (
    Branch,
    branch_of,
    edge_positions,
    PoseSettings,
    reached_rotation,
    solve_poses,
    sweep_poses,
)

SEED = START_JOINTS[:4]


@pytest.fixture(scope='module')
def path():
    return path_from_contacts(*wave_pathway(position_sd=0.0, normal_sd=0.0))


@pytest.fixture(scope='module')
def poses(path):
    return sweep_poses(path, PoseSettings(edge_offset_rad=0.5, press_depth_m=0.0015), SEED)


def test_the_rim_is_pressed_into_the_path_by_the_depth(path, poses):
    frames = [forward_kinematics(q, 'sensor_edge') for q in poses.joints]
    edges = np.array([frame[:3, 3] for frame in frames])
    np.testing.assert_allclose(edges, poses.edge_positions, atol=1e-9)
    depth = EDGE_TIP_RADIUS_M - np.sum((edges - path.points) * path.normals, axis=1)
    np.testing.assert_allclose(depth, 0.0015, atol=1e-9)


def test_sensor_axis_leans_by_the_offset_from_the_inward_normal_in_the_plane_of_motion(
        path, poses):
    axes = np.array([forward_kinematics(q, 'sensor_edge')[:3, 2] for q in poses.joints])
    angles = np.arccos(np.clip(np.sum(axes * -path.normals, axis=1), -1.0, 1.0))
    np.testing.assert_allclose(angles, 0.5, atol=1e-6)
    assert np.all(np.sum(axes * path.tangents, axis=1) > 0)  # leaning along the travel
    assert np.max(np.abs(axes[:, 1])) < 1e-9  # in the plane of motion (y = 0 here)
    assert np.max(poses.residual_rad) < 1e-6


def test_the_rim_point_is_the_lowest_part_of_the_face(path, poses):
    rotations = np.array([forward_kinematics(q, 'sensor_edge')[:3, :3] for q in poses.joints])
    towards_rim = rotations[:, :, 0]  # +x of sensor_edge: from the face centre to the rim
    assert np.all(np.sum(towards_rim * path.normals, axis=1) < -0.4)  # sin(0.5) = 0.48
    np.testing.assert_allclose(rotations, [reached_rotation(q) for q in poses.joints],
                               atol=1e-12)


def test_zero_offset_puts_the_face_parallel_to_the_surface():
    path = path_from_contacts(*wave_pathway(position_sd=0.0, normal_sd=0.0, end=0.18))
    flat = sweep_poses(path, PoseSettings(edge_offset_rad=0.0), SEED)
    axes = np.array([forward_kinematics(q, 'sensor_edge')[:3, 2] for q in flat.joints])
    np.testing.assert_allclose(np.sum(axes * -path.normals, axis=1), 1.0, atol=1e-9)


def test_a_pathway_in_reverse_order_is_swept_with_the_same_poses_backwards(path, poses):
    points, normals = wave_pathway(position_sd=0.0, normal_sd=0.0)
    backward = sweep_poses(path_from_contacts(points[::-1], normals[::-1]),
                           PoseSettings(edge_offset_rad=0.5, press_depth_m=0.0015), SEED)
    np.testing.assert_allclose(backward.joints[::-1], poses.joints, atol=1e-5)


def test_one_branch_and_no_jumps_over_the_whole_sweep(poses):
    assert poses.branch == Branch(facing=True, elbow_up=True)
    assert {branch_of(q, p) for q, p in zip(poses.joints, poses.edge_positions,
                                            strict=True)} == {poses.branch}
    assert np.max(np.abs(np.diff(poses.joints, axis=0))) < 0.2  # 2 mm apart


def test_a_pathway_leaving_the_workspace_midway_is_refused_naming_where():
    path = path_from_contacts(*wave_pathway(position_sd=0.0, normal_sd=0.0, start=0.12,
                                            end=0.42))
    with pytest.raises(SweepRefused, match=r'path sample \d+ \(\d+\.\d mm along the path\)'
                                           r'.*out of the arm\'s reach'):
        sweep_poses(path, PoseSettings(), SEED)


def test_a_path_across_the_arm_is_refused_for_its_residual():
    ys = np.linspace(-0.06, 0.06, 13)
    points = np.stack([np.full_like(ys, 0.15), ys, np.full_like(ys, 0.02)], axis=1)
    path = path_from_contacts(points, np.tile([0.0, 0.0, 1.0], (13, 1)))
    with pytest.raises(SweepRefused, match=r'deg from the asked one.*has no roll'):
        sweep_poses(path, PoseSettings(edge_offset_rad=0.5), SEED)
    across = sweep_poses(path, PoseSettings(edge_offset_rad=0.5, max_residual_rad=3.0), SEED)
    assert np.all(across.residual_rad > 0.3)  # reported per sample when tolerated


def test_a_small_roll_is_projected_and_its_residual_reported():
    points, normals = wave_pathway(position_sd=0.0, normal_sd=0.0)
    tilt = math.radians(4.0)
    normals = normals @ np.array([[1, 0, 0], [0, math.cos(tilt), -math.sin(tilt)],
                                  [0, math.sin(tilt), math.cos(tilt)]]).T
    tilted = sweep_poses(path_from_contacts(points, normals), PoseSettings(), SEED)
    np.testing.assert_allclose(tilted.residual_rad, tilt, atol=0.01)


def test_a_path_past_joint1s_limit_is_refused_instead_of_turning_joint1_around():
    # An arc around the base at 160 mm: beyond 0.9 pi only joint1 turned away would face
    # it, which the sweep's branch never becomes.
    headings = np.radians(np.linspace(150.0, 175.0, 26))
    points = np.stack([0.012 + 0.16 * np.cos(headings), 0.16 * np.sin(headings),
                       np.full_like(headings, 0.02)], axis=1)
    path = path_from_contacts(points, np.tile([0.0, 0.0, 1.0], (26, 1)))
    seed = np.array([2.6, -0.3, 0.3, 1.2])
    with pytest.raises(SweepRefused, match=r"out of the arm's reach on the sweep's IK branch "
                                           r'\(joint1 facing the path, elbow up\).*joint1=.*'
                                           r'branch switch is never made'):
        sweep_poses(path, PoseSettings(edge_offset_rad=0.3, max_residual_rad=3.0), seed)


def test_a_pose_off_the_sweeps_branch_is_refused_not_switched(poses):
    turned = Branch(facing=False, elbow_up=True)
    with pytest.raises(SweepRefused, match='branch switch is never made'):
        solve_poses(poses.edge_positions[:3], poses.rotations[:3], SEED, 0.2, branch=turned)


def test_lifted_edge_positions_move_along_the_normal():
    lifted = edge_positions(np.zeros((2, 3)), np.array([[0, 0, 1.0], [0, 0, 1.0]]), 0.001,
                            np.array([0.0, 0.01]))
    np.testing.assert_allclose(lifted[:, 2], [EDGE_TIP_RADIUS_M - 0.001,
                                              EDGE_TIP_RADIUS_M + 0.009])


@pytest.mark.parametrize('name, value', [('edge_offset_rad', -0.1),
                                         ('edge_offset_rad', math.pi / 2),
                                         ('press_depth_m', 0.01), ('press_depth_m', math.nan),
                                         ('max_residual_rad', 0.0)])
def test_pose_settings_out_of_range_are_refused(name, value):
    with pytest.raises(ValueError, match=name):
        PoseSettings(**{name: value})
