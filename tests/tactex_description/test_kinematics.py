# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Forward and inverse kinematics of the arm: exact round trips and the hard cases."""

import dataclasses
import math

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from transforms3d.euler import euler2mat

from tactex_description.geometry import ARM_JOINT_NAMES, OPEN_MANIPULATOR_X
from tactex_description.kinematics import (
    forward_kinematics,
    inverse_kinematics,
    PlanarArm,
    tool_pose,
    Unreachable,
)

ARM = PlanarArm.from_geometry()
LIMITS = [(OPEN_MANIPULATOR_X.joint(n).lower, OPEN_MANIPULATOR_X.joint(n).upper)
          for n in ARM_JOINT_NAMES]
joint_vectors = st.tuples(*(st.floats(lo, hi) for lo, hi in LIMITS))


def assert_all_solutions_reach(result, position, pitch, tool_frame='sensor_edge'):
    assert result.reachable, result.detail
    for q in result.solutions:
        reached, reached_pitch = tool_pose(q, tool_frame=tool_frame)
        np.testing.assert_allclose(reached, position, atol=1e-9, rtol=0)
        assert abs(math.remainder(reached_pitch - pitch, 2 * math.pi)) < 1e-9
        assert all(lo - 1e-12 <= v <= hi + 1e-12 for v, (lo, hi) in zip(q, LIMITS, strict=True))


def test_planar_tool_pose_matches_chain_forward_kinematics():
    rng = np.random.default_rng(1)
    for _ in range(200):
        q = np.array([rng.uniform(lo, hi) for lo, hi in LIMITS])
        position, pitch = tool_pose(q)
        pose = forward_kinematics(q, 'sensor_edge')
        np.testing.assert_allclose(position, pose[:3, 3], atol=1e-12)
        link5 = forward_kinematics(q, 'link5')[:3, :3]
        expected = euler2mat(0.0, pitch, q[0], axes='sxyz')  # Rz(joint1) Ry(pitch)
        np.testing.assert_allclose(link5, expected, atol=1e-12)


def test_zero_configuration_matches_robotis_dimensions():
    end_effector = forward_kinematics(np.zeros(4), 'end_effector_link')[:3, 3]
    np.testing.assert_allclose(end_effector, [0.012 + 0.024 + 0.124 + 0.126, 0.0,
                                              0.017 + 0.0595 + 0.128], atol=1e-12)


@settings(max_examples=400, deadline=None)
@given(joint_vectors)
def test_fk_of_ik_reproduces_target_everywhere_in_the_workspace(q):
    position, pitch = tool_pose(q)
    result = inverse_kinematics(position, pitch)
    assert_all_solutions_reach(result, position, pitch)
    assert any(np.allclose(np.remainder(s - np.array(q) + np.pi, 2 * np.pi) - np.pi, 0,
                           atol=1e-6) for s in result.solutions)


@settings(max_examples=100, deadline=None)
@given(joint_vectors)
def test_ik_for_end_effector_tool_frame(q):
    position, pitch = tool_pose(q, tool_frame='end_effector_link')
    assert_all_solutions_reach(inverse_kinematics(position, pitch,
                                                  tool_frame='end_effector_link'),
                               position, pitch, 'end_effector_link')


UNLIMITED_ARM = dataclasses.replace(ARM, lower=np.full(4, -math.pi),
                                    upper_limit=np.full(4, math.pi))


@pytest.mark.parametrize('q2', [-1.0, 0.2, 1.3])
def test_fully_stretched_arm_is_solved_exactly(q2):
    upper_angle = math.atan2(*reversed(ARM.upper))
    q = np.array([0.3, q2, -upper_angle, 0.1])  # forearm in line with the upper arm
    position, pitch = UNLIMITED_ARM.tool_pose(q)
    result = UNLIMITED_ARM.inverse(position, pitch)
    assert len(result.solutions) == 2  # facing the target, or turned away and folded back
    for solution in result.solutions:
        reached, reached_pitch = UNLIMITED_ARM.tool_pose(solution)
        np.testing.assert_allclose(reached, position, atol=1e-9, rtol=0)
    np.testing.assert_allclose(result.solutions[0], q, atol=1e-6)


def test_fully_stretched_real_arm_reports_joint3_limit():
    upper_angle = math.atan2(*reversed(ARM.upper))
    position, pitch = tool_pose([0.3, 0.2, -upper_angle, 0.1])
    result = inverse_kinematics(position, pitch)
    assert result.reason is Unreachable.JOINT_LIMIT
    assert 'joint3' in result.detail


def test_edge_of_real_workspace_at_joint3_lower_limit():
    q = np.array([0.3, 0.2, LIMITS[2][0], 0.1])
    position, pitch = tool_pose(q)
    assert_all_solutions_reach(inverse_kinematics(position, pitch), position, pitch)


def test_target_a_hair_outside_reach_is_unreachable_with_distance():
    upper_angle = math.atan2(*reversed(ARM.upper))
    position, pitch = UNLIMITED_ARM.tool_pose([0.0, 0.2, -upper_angle, 0.1])
    direction = position - UNLIMITED_ARM.tool_pose([0.0, 0.2, -upper_angle, 0.1 - 1e-3])[0]
    result = UNLIMITED_ARM.inverse(position, pitch)
    assert result.reachable
    # Push the target straight away from joint2, a tenth of a micrometre.
    wrist = UNLIMITED_ARM.tool_pose([0.0, 0.2, -upper_angle, 0.1])[0]
    away = wrist - [ARM.base_x, 0.0, ARM.shoulder_z]
    away /= np.linalg.norm(away)
    del direction
    result = UNLIMITED_ARM.inverse(position + 1e-7 * away, pitch)
    assert not result.reachable
    assert result.reason is Unreachable.OUT_OF_REACH
    assert 'out of reach by' in result.detail
    assert 'nan' not in result.detail


def test_far_target_is_out_of_reach_not_nan():
    result = inverse_kinematics([2.0, 0.0, 0.1], 0.0)
    assert result.reason is Unreachable.OUT_OF_REACH
    assert result.solutions == ()


def test_wrist_on_joint1_axis_uses_seed_heading():
    # The wrist (link5 origin) right above the joint1 axis: joint1 is undefined.
    q2 = -0.5
    q3 = -math.acos(-(ARM.upper[0] * math.cos(q2) + ARM.upper[1] * math.sin(q2))
                    / ARM.forearm) - q2
    height = tool_pose([0.0, q2, q3, 0.0], tool_frame='link5')[0][2]
    target = [ARM.base_x, 0.0, height]
    for heading in (0.0, 0.7, -1.2):
        seed = [heading, q2, q3, 0.0]
        result = inverse_kinematics(target, 0.0, seed=seed, tool_frame='link5')
        assert_all_solutions_reach(result, target, 0.0, 'link5')
        assert math.isclose(result.solutions[0][0], heading, abs_tol=1e-12)


@pytest.mark.parametrize('pitch', [math.pi / 2, -math.pi / 2])
def test_pitch_at_plus_minus_half_pi(pitch):
    found = 0
    for radius in np.linspace(0.05, 0.35, 13):
        for height in np.linspace(-0.05, 0.45, 11):
            target = [ARM.base_x + radius, 0.02, height]
            result = inverse_kinematics(target, pitch)
            if result.reachable:
                found += 1
                assert_all_solutions_reach(result, target, pitch)
            else:
                assert result.reason in (Unreachable.OUT_OF_REACH, Unreachable.JOINT_LIMIT)
                assert result.detail
    assert found > 10


def test_joint_limit_reason_names_the_joint():
    # Behind the base and low: geometry reaches it, joint limits do not.
    result = inverse_kinematics([-0.15, 0.0, -0.05], 0.0)
    assert not result.reachable
    assert result.reason is Unreachable.JOINT_LIMIT
    assert 'joint' in result.detail and 'outside' in result.detail


def test_solutions_sorted_by_closeness_to_seed():
    q = np.array([0.4, 0.3, 0.2, 0.6])
    position, pitch = tool_pose(q)
    result = inverse_kinematics(position, pitch, seed=q + 0.01)
    np.testing.assert_allclose(result.solutions[0], q, atol=1e-9)


def test_non_finite_target_is_rejected():
    with pytest.raises(ValueError, match='finite'):
        inverse_kinematics([float('nan'), 0.0, 0.2], 0.0)


def test_forward_kinematics_rejects_wrong_joint_count():
    with pytest.raises(ValueError, match='4 arm joint positions'):
        forward_kinematics([0.0, 0.0, 0.0])


def test_unknown_frame_lists_known_links():
    with pytest.raises(KeyError, match='known links'):
        forward_kinematics(np.zeros(4), 'gripper_tip')


def test_compliant_press_moves_sensor_link_towards_mount():
    rest = forward_kinematics({}, 'sensor_link')[:3, 3]
    pressed = forward_kinematics({'sensor_press': -0.004}, 'sensor_link')[:3, 3]
    # At zero joints the tool axis is +x of the base: pressing pulls the sensor back.
    np.testing.assert_allclose(pressed - rest, [-0.004, 0.0, 0.0], atol=1e-12)
