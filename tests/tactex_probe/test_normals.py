# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Normal estimation: the Madgwick deformation, the gravity cross-check, the bearing point."""

import math

import numpy as np
import pytest
from transforms3d.axangles import axangle2mat
from transforms3d.quaternions import mat2quat

from tactex_probe.motion import FACE_AXIS, FACE_CENTRE, solve, ToolPose
from tactex_probe.normals import (
    align,
    angle_between,
    axis_angle_matrix,
    bearing_point,
    estimate_normal,
    hinge_angles,
    HINGE_STIFFNESS,
    mean_quaternion,
    PRESS_STIFFNESS_N_M,
    sensor_pose,
    SensorWindow,
)

UP = np.array([0.0, 0.0, 1.0])


def test_axis_angle_matrix_is_rodrigues():
    axis = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
    assert axis_angle_matrix(axis, 0.7) == pytest.approx(axangle2mat(axis, 0.7))


@pytest.mark.parametrize('measured, target', [
    ((0.1, -0.3, -9.7), (0.0, 0.0, 1.0)), ((0.0, 0.0, -1.0), (0.0, 0.0, 1.0)),
    ((1.0, 1e-14, 0.0), (1.0, 0.0, 0.0))])
def test_align_turns_the_measured_direction_onto_the_target(measured, target):
    rotation = align(measured, target)
    unit = np.asarray(measured) / np.linalg.norm(measured)
    assert rotation @ unit == pytest.approx(np.asarray(target) / np.linalg.norm(target))
    assert rotation @ rotation.T == pytest.approx(np.eye(3))


def test_align_refuses_zero_or_non_finite_vectors():
    with pytest.raises(ValueError, match='finite, non-zero'):
        align((0.0, 0.0, 0.0), UP)
    with pytest.raises(ValueError, match='finite, non-zero'):
        align((math.nan, 0.0, 1.0), UP)


def test_mean_quaternion_ignores_the_sign():
    q = mat2quat(axangle2mat((0.0, 1.0, 0.0), 0.3))
    assert mean_quaternion([q, -q, q]) == pytest.approx(q)


def windows(joints, deformation, *, filter_yaw=0.4, compression=0.002, fool_filter=False):
    """What the sensor would read: the filter's world turned by `filter_yaw` from base."""
    undeformed = sensor_pose(joints)[:3, :3]
    deformed = undeformed @ deformation
    yaw = axangle2mat(UP, filter_yaw)
    pressed_attitude = yaw @ deformed
    if fool_filter:
        pressed_attitude = axangle2mat((1.0, 0.0, 0.0), 0.3) @ pressed_attitude
    free = SensorWindow(mat2quat(yaw @ undeformed), undeformed.T @ UP * 9.81,
                        np.asarray(joints))
    pressed = SensorWindow(mat2quat(pressed_attitude), deformed.T @ UP * 9.81,
                           np.asarray(joints), compression)
    return free, pressed


JOINTS = solve(ToolPose([0.15, 0.0, 0.02], 0.2), [0.0, 0.0, 0.0, 1.5])


def test_estimate_recovers_a_known_deformation():
    deformation = axangle2mat((0.2, 1.0, 0.0), math.radians(4.0))
    free, pressed = windows(JOINTS, deformation)
    estimate = estimate_normal(free, pressed)
    truth = -(sensor_pose(JOINTS)[:3, :3] @ deformation) @ FACE_AXIS
    assert angle_between(estimate.normal, truth) < 1e-9
    assert math.degrees(estimate.agreement_rad) < 0.5  # gravity misses only the yaw part
    assert estimate.source == 'madgwick'
    assert estimate.deflection_rad == pytest.approx(angle_between(deformation @ FACE_AXIS,
                                                                  FACE_AXIS))
    assert estimate.turn_rad == pytest.approx(-math.radians(4.0) / math.hypot(0.2, 1.0)
                                              * 1.0, rel=0.05)


def test_estimate_falls_back_to_gravity_when_the_filter_is_fooled():
    deformation = axangle2mat((0.0, 1.0, 0.0), math.radians(3.0))
    free, pressed = windows(JOINTS, deformation, fool_filter=True)
    estimate = estimate_normal(free, pressed)
    truth = -(sensor_pose(JOINTS)[:3, :3] @ deformation) @ FACE_AXIS
    assert estimate.source == 'gravity'
    assert math.degrees(angle_between(estimate.normal, truth)) < 0.01


def test_estimate_cancels_an_accelerometer_bias():
    deformation = axangle2mat((0.0, 1.0, 0.0), math.radians(3.0))
    free, pressed = windows(JOINTS, deformation)
    bias = np.array([0.05, -0.04, 0.03])
    free = SensorWindow(free.quaternion, free.accel + bias, free.joints)
    pressed = SensorWindow(pressed.quaternion, pressed.accel + bias, pressed.joints,
                           pressed.compression_m)
    truth = -(sensor_pose(JOINTS)[:3, :3] @ deformation) @ FACE_AXIS
    assert math.degrees(angle_between(estimate_normal(free, pressed).gravity_normal,
                                      truth)) < 0.05


def test_estimate_refuses_non_finite_windows():
    free, pressed = windows(JOINTS, np.eye(3))
    broken = SensorWindow(pressed.quaternion, np.array([math.nan, 0.0, 9.8]), pressed.joints)
    with pytest.raises(ValueError, match='pressed window'):
        estimate_normal(free, broken)


def test_bearing_point_follows_the_torque_of_an_off_centre_force():
    # A 1.5 N push on the face 6 mm from its centre (along the face, in the arm plane):
    # the hinges take its moment; the bearing point must come out where it was applied.
    compression = 1.5 / PRESS_STIFFNESS_N_M
    pivot = np.array([0.0, 0.0, -(0.012 - compression)])
    along = np.cross([0.0, 1.0, 0.0], FACE_AXIS)
    contact = FACE_CENTRE + 0.006 * along
    moment = np.cross(contact - pivot, -1.5 * FACE_AXIS)
    angles = np.array([moment[0], moment[1], 0.0]) / HINGE_STIFFNESS
    deformation = axangle2mat((1.0, 0.0, 0.0), angles[0]) @ axangle2mat((0.0, 1.0, 0.0),
                                                                       angles[1])
    assert hinge_angles(deformation)[:2] == pytest.approx(angles[:2])
    free, pressed = windows(JOINTS, deformation, compression=compression)
    estimate = estimate_normal(free, pressed)
    expected = estimate.face_centre + estimate.face_rotation @ (contact - FACE_CENTRE)
    assert np.linalg.norm(bearing_point(estimate) - expected) < 2e-4


def test_bearing_point_without_force_is_the_face_centre():
    free, pressed = windows(JOINTS, np.eye(3), compression=0.0)
    estimate = estimate_normal(free, pressed)
    assert bearing_point(estimate) == pytest.approx(estimate.face_centre)

