# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Forward and inverse kinematics under any joint values, targets and seeds."""

import math

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from support.hard_values import anything, finite, vectors

from tactex_description.geometry import ARM_JOINT_NAMES, OPEN_MANIPULATOR_X
from tactex_description.kinematics import (
    forward_kinematics,
    inverse_kinematics,
    tool_pose,
    Unreachable,
)

pytestmark = pytest.mark.hard_case

LOWER = np.array([OPEN_MANIPULATOR_X.joint(n).lower for n in ARM_JOINT_NAMES])
UPPER = np.array([OPEN_MANIPULATOR_X.joint(n).upper for n in ARM_JOINT_NAMES])
FRAMES = ('link5', 'sensor_link', 'sensor_edge', 'end_effector_link')


@settings(max_examples=150)
@given(vectors(finite(), 4), st.sampled_from(FRAMES))
def test_forward_kinematics_of_any_finite_joints_is_a_rigid_pose(joints, frame):
    pose = forward_kinematics(joints, frame)
    assert np.all(np.isfinite(pose))
    rotation = pose[:3, :3]
    np.testing.assert_allclose(rotation.T @ rotation, np.eye(3), atol=1e-9)
    assert np.linalg.det(rotation) == pytest.approx(1.0, abs=1e-9)
    np.testing.assert_array_equal(pose[3], [0.0, 0.0, 0.0, 1.0])
    assert np.linalg.norm(pose[:3, 3]) < 1.0  # the arm is shorter than a metre


@settings(max_examples=100)
@given(vectors(anything(), 4))
def test_non_finite_joints_are_refused_not_propagated(joints):
    if all(math.isfinite(q) for q in joints):
        assert np.all(np.isfinite(tool_pose(joints)[0]))
        return
    with pytest.raises(ValueError, match='finite'):
        forward_kinematics(joints)
    with pytest.raises(ValueError, match='finite'):
        tool_pose(joints)


@settings(max_examples=200)
@given(vectors(finite()), finite(), st.one_of(st.none(), vectors(finite(), 4)))
def test_inverse_kinematics_of_any_finite_target_solves_or_says_why(position, pitch, seed):
    result = inverse_kinematics(position, pitch, seed=seed)
    if not result.reachable:
        assert result.reason in set(Unreachable) and result.detail
        return
    for q in result.solutions:
        assert np.all(np.isfinite(q))
        assert np.all(q >= LOWER - 1e-12) and np.all(q <= UPPER + 1e-12)
        reached, reached_pitch = tool_pose(q)
        np.testing.assert_allclose(reached, position, atol=1e-9, rtol=0)
        assert abs(math.remainder(reached_pitch - math.remainder(pitch, 2 * math.pi),
                                  2 * math.pi)) < 1e-9


@settings(max_examples=100)
@given(vectors(anything()), anything(), st.one_of(st.none(), vectors(anything(), 4)))
def test_a_non_finite_target_or_seed_is_refused(position, pitch, seed):
    values = (*position, pitch, *(seed or ()))
    if all(math.isfinite(v) for v in values):
        inverse_kinematics(position, pitch, seed=seed)
        return
    with pytest.raises(ValueError, match='finite'):
        inverse_kinematics(position, pitch, seed=seed)


@given(st.lists(finite(), max_size=6).filter(lambda v: len(v) != 4))
def test_a_seed_of_the_wrong_length_is_refused(seed):
    with pytest.raises(ValueError, match='four finite joint positions'):
        inverse_kinematics((0.2, 0.0, 0.1), 1.0, seed=seed)
