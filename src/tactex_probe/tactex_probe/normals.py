# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Surface normal at a contact from the compliant body's deformation, in base_link.

Pressed on a surface, the compliant body turns its face towards it. The deformation E
(rotation of `sensor_link` relative to where an undeformed body would hold it) is
measured two ways from two windows of samples, one in free air just before the touch
(undeformed) and one pressed and settled (deformed):

* Madgwick (the estimate): the filter's attitudes q_u and q_d. The free-air window fixes
  the filter's world in base_link, Y = R(q_u) R_u^T with R_u the forward kinematics (FK)
  of the undeformed sensor at that window; then the deformed sensor is R_d = Y^T R(q_d).
  Heading drift and the accelerometer's bias cancel in the relative rotation.
* Gravity alignment (the cross-check, the original's eqs. 3.1-3.6): the rotation R_ag
  that aligns a measured accel with a gravity direction, built from the axis a x g and
  the angle between them with Rodrigues' formula (eqs. 3.1-3.4). In free air it gives
  the mismatch M between the measured and the FK-predicted gravity (bias, mounting); when
  pressed, E = R_ag(M a_d -> g_d) with g_d the gravity an undeformed sensor would feel
  there. Eq. 3.6's R_z(alpha) R_ag becomes R_d = R_FK E: the FK rotation holds the base
  rotation alpha (joint1) and the tool pitch. Gravity cannot see a turn about the
  vertical, which is why it is only the cross-check. When the two disagree by more than
  `MAX_DISAGREEMENT_RAD` the filter was fooled (vibration aliased into the gyro while
  pressing, say), and the gravity estimate is used instead (`source` says which).

The outward normal is minus the deformed face axis, n = -R_d a (`motion.FACE_AXIS`). The
deformed face follows from the FK of the arm joints plus the body's joints: E split into
roll, pitch and yaw (the body's three hinges share one origin) and the compression.

Where on the face the surface bears follows from the body acting as a force sensor: its
hinges' stiffness times their angles is the torque of the contact force about their
common origin, the compression times the press stiffness is that force. The line of
action of a force -F a giving that torque crosses the bearing plane at the contact
(friction, which adds a torque of its own, is neglected; refining the tool until the face
no longer turns makes that point the face centre whatever the stiffness and friction).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
import math
import sys

import numpy as np
from transforms3d.euler import mat2euler
from transforms3d.quaternions import mat2quat, quat2mat

from tactex_description.geometry import (
    ARM_JOINT_NAMES,
    COMPLIANT_JOINT_NAMES,
    OPEN_MANIPULATOR_X,
)
from tactex_description.kinematics import forward_kinematics
from tactex_probe.errors import ParameterError
from tactex_probe.motion import FACE_AXIS, FACE_CENTRE, face_tilt, TOOL_FRAME, ToolPose
from tactex_sensor.orientation import unit_direction

# Stiffness of the roll, pitch and yaw hinges (N m/rad) and the press (N/m).
HINGE_STIFFNESS = np.array([OPEN_MANIPULATOR_X.joint(name).stiffness
                            for name in COMPLIANT_JOINT_NAMES[:3]])
PRESS_STIFFNESS_N_M = OPEN_MANIPULATOR_X.joint(COMPLIANT_JOINT_NAMES[3]).stiffness
# sensor_link's origin above the hinges' common origin, along z, at rest (m).
_PRESS_ORIGIN_M = OPEN_MANIPULATOR_X.joint(COMPLIANT_JOINT_NAMES[3]).origin_xyz[2]
# Beyond this disagreement with gravity the Madgwick deformation is not trusted.
MAX_DISAGREEMENT_RAD = math.radians(2.0)
# Direction within the bearing plane, in the arm plane (sensor_link coordinates).
_ALONG_FACE = np.cross([0.0, 1.0, 0.0], FACE_AXIS)
RIM_LIMIT_M = OPEN_MANIPULATOR_X.joint('sensor_edge_fixed').origin_xyz[0]


def skew(vector) -> np.ndarray:
    """Skew-symmetric matrix K of a vector: K x = vector x x (eqs. 3.2 and 3.4)."""
    x, y, z = (float(v) for v in vector)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def axis_angle_matrix(axis, angle_rad: float) -> np.ndarray:
    """Rotation by `angle_rad` about the unit `axis`: R = I + sin K + (1 - cos) K^2 (eq. 3.1)."""
    k = skew(axis)
    return np.eye(3) + math.sin(angle_rad) * k + (1.0 - math.cos(angle_rad)) * (k @ k)


def align(measured, target) -> np.ndarray:
    """R_ag of eq. 3.3: the shortest rotation turning the direction `measured` onto `target`.

    Raises:
        ParameterError: either vector is zero or not finite.
    """
    a, g = (_direction(v) for v in (measured, target))
    if a is None or g is None:
        raise ParameterError(f'cannot align {measured!r} with {target!r}: need finite, '
                             'non-zero vectors')
    cross = np.cross(a, g)
    sine = float(np.linalg.norm(cross))
    angle = math.atan2(sine, float(np.dot(a, g)))
    if sine < 1e-12:
        if angle < 1.0:
            return np.eye(3)
        # Opposite directions: any axis across them is shortest.
        helper = np.eye(3)[int(np.argmin(np.abs(a)))]
        cross = np.cross(a, helper)
        sine = float(np.linalg.norm(cross))
    return axis_angle_matrix(cross / sine, angle)


def _direction(vector) -> np.ndarray | None:
    """Unit direction of a 3-vector (extremes and subnormals too); None if zero or not finite."""
    valid, *direction = unit_direction(*(float(v) for v in vector), sys.float_info.max)
    return np.array(direction) if valid else None


def quaternion_z_to(normal) -> np.ndarray:
    """Quaternion (w, x, y, z) of the shortest rotation turning +z onto `normal`."""
    return mat2quat(align([0.0, 0.0, 1.0], normal))


def mean_quaternion(quaternions) -> np.ndarray:
    """Average attitude of (n, 4) quaternions (w, x, y, z): the principal eigenvector.

    q and -q are the same attitude; the eigenvector of sum q q^T ignores the sign.
    """
    q = np.asarray(quaternions, dtype=float)
    # Each row scaled to its largest value first: extreme ones neither overflow nor weigh more.
    largest = np.max(np.abs(q), axis=1, keepdims=True)
    q = q / np.where(largest > 0, largest, 1.0)
    q /= np.maximum(np.linalg.norm(q, axis=1, keepdims=True), 1.0)
    _, vectors = np.linalg.eigh(q.T @ q)
    mean = vectors[:, -1]
    return mean if mean[0] >= 0 else -mean


@dataclass(frozen=True)
class SensorWindow:
    """One window of samples, averaged: what the sensor and arm showed at one instant.

    Attributes:
        quaternion: Madgwick attitude (w, x, y, z), sensor -> filter world.
        accel: mean accelerometer reading (m/s^2, sensor frame).
        joints: arm joints joint1..joint4 (rad), interpolated to the samples' stamps.
        compression_m: compression of the body along its axis (m, 0 in free air).
    """

    quaternion: np.ndarray
    accel: np.ndarray
    joints: np.ndarray
    compression_m: float = 0.0


def hinge_angles(deformation: np.ndarray) -> np.ndarray:
    """Roll, pitch and yaw hinge angles (rad) of a body deformation E (x, then y, then z)."""
    return np.array(mat2euler(deformation, axes='rxyz'))


def sensor_pose(joints: Sequence[float], deformation: np.ndarray | None = None,
                compression_m: float = 0.0) -> np.ndarray:
    """4x4 pose of `sensor_link` in base_link: arm FK plus the body's deformation."""
    positions = dict(zip(ARM_JOINT_NAMES, (float(q) for q in joints), strict=True))
    if deformation is not None:
        positions.update(zip(COMPLIANT_JOINT_NAMES, (*hinge_angles(deformation),
                                                     -compression_m), strict=True))
    return forward_kinematics(positions, TOOL_FRAME)


@dataclass(frozen=True)
class NormalEstimate:
    """The measured normal and what it rests on (base_link, SI units).

    Attributes:
        normal: outward unit normal from the Madgwick deformation.
        gravity_normal: the same from gravity alignment (eqs. 3.1-3.6), the cross-check.
        deformation: E, rotation of the body relative to its undeformed pose.
        deflection_rad: how far the face axis turned.
        turn_rad: the part of that turn within the arm plane, signed like a tool tilt
            (the face leaned further away from the base: positive).
        agreement_rad: angle between `normal` and `gravity_normal`.
        face_centre: centre of the deformed face (m).
        face_rotation: rotation base_link <- deformed sensor_link.
        compression_m: the body's compression.
        source: 'madgwick', or 'gravity' when the filter disagreed with gravity.
    """

    normal: np.ndarray
    gravity_normal: np.ndarray
    deformation: np.ndarray
    deflection_rad: float
    turn_rad: float
    agreement_rad: float
    face_centre: np.ndarray
    face_rotation: np.ndarray
    compression_m: float
    source: str = 'madgwick'


def angle_between(u, v) -> float:
    """Angle (rad) between two vectors, accurate near 0 and pi."""
    u, v = np.asarray(u, dtype=float), np.asarray(v, dtype=float)
    return math.atan2(float(np.linalg.norm(np.cross(u, v))), float(np.dot(u, v)))


def scaled(quaternion) -> np.ndarray:
    """A quaternion divided by its largest component (the same rotation; no overflow in it)."""
    quaternion = np.asarray(quaternion, dtype=float)
    largest = np.max(np.abs(quaternion))
    return quaternion / largest if largest > 0 else quaternion


def estimate_normal(free: SensorWindow, pressed: SensorWindow) -> NormalEstimate:
    """Normal and deformed face from a free-air window and a pressed, settled window.

    Raises:
        ParameterError: a window holds non-finite values or a zero accel.
    """
    for name, window in (('free', free), ('pressed', pressed)):
        values = np.concatenate([window.quaternion, window.accel, window.joints,
                                 [window.compression_m]])
        if not np.all(np.isfinite(values)) or not np.any(np.asarray(window.accel) != 0):
            raise ParameterError(f'the {name} window holds non-finite or zero readings')
    undeformed_free = sensor_pose(free.joints)[:3, :3]
    pressed_pose = sensor_pose(pressed.joints)
    undeformed = pressed_pose[:3, :3]
    filter_world = quat2mat(scaled(free.quaternion)) @ undeformed_free.T
    deformed = filter_world.T @ quat2mat(scaled(pressed.quaternion))
    up = np.array([0.0, 0.0, 1.0])
    mismatch = align(free.accel, undeformed_free.T @ up)
    # Only the direction of the pressed accel matters: scaled first, a huge one cannot
    # overflow in the rotation.
    pressed_accel = pressed.accel / np.max(np.abs(pressed.accel))
    gravity_deformed = undeformed @ align(mismatch @ pressed_accel, undeformed.T @ up)
    normal = -deformed @ FACE_AXIS
    gravity_normal = -gravity_deformed @ FACE_AXIS
    agreement = angle_between(normal, gravity_normal)
    source = 'madgwick'
    if agreement > MAX_DISAGREEMENT_RAD:
        deformed, normal, source = gravity_deformed, gravity_normal, 'gravity'
    deformation = undeformed.T @ deformed
    pose = sensor_pose(pressed.joints, deformation, pressed.compression_m)
    centre = pose[:3, :3] @ FACE_CENTRE + pose[:3, 3]
    heading = ToolPose(centre, 0.0).heading
    return NormalEstimate(
        normal=normal / np.linalg.norm(normal),
        gravity_normal=gravity_normal / np.linalg.norm(gravity_normal),
        deformation=deformation,
        deflection_rad=angle_between(deformation @ FACE_AXIS, FACE_AXIS),
        turn_rad=face_tilt(deformed, heading) - face_tilt(undeformed, heading),
        agreement_rad=agreement, face_centre=centre, face_rotation=pose[:3, :3],
        compression_m=pressed.compression_m, source=source)


def bearing_point(estimate: NormalEstimate) -> np.ndarray:
    """Where the surface bears on the face (m, base_link), from the body's torque balance.

    The hinge torques (stiffness times angle) equal the moment of the contact force
    -F a (F = compression times the press stiffness) about the hinges' origin; the point
    of the bearing plane on that force's line of action is returned. Without a force
    (or a degenerate one) it is the face centre.
    """
    force = PRESS_STIFFNESS_N_M * estimate.compression_m
    if not (math.isfinite(force) and force > 1e-3):
        return estimate.face_centre
    torque = HINGE_STIFFNESS * hinge_angles(estimate.deformation)
    pivot = np.array([0.0, 0.0, -(_PRESS_ORIGIN_M - estimate.compression_m)])
    # Moment about the pivot of -F a applied at centre + u * along + v * y (linear in u, v).
    force_vector = -force * FACE_AXIS
    with np.errstate(over='ignore', invalid='ignore'):  # an absurd one is caught below
        base = np.cross(FACE_CENTRE - pivot, force_vector)
        du = np.cross(_ALONG_FACE, force_vector)
        dv = np.cross([0.0, 1.0, 0.0], force_vector)
        # The hinges feel the moment about their own axes: use the pitch (y) and roll (x).
        matrix = np.array([[du[1], dv[1]], [du[0], dv[0]]])
        target = np.array([torque[1] - base[1], torque[0] - base[0]])
        try:
            u, v = np.linalg.solve(matrix, target)
        except np.linalg.LinAlgError:
            return estimate.face_centre
    if not (math.isfinite(u) and math.isfinite(v)):  # an absurd compression overflowed
        return estimate.face_centre
    # Never beyond the face: the contact is on it.
    u, v = (float(np.clip(w, -RIM_LIMIT_M, RIM_LIMIT_M)) for w in (u, v))
    offset = u * _ALONG_FACE + v * np.array([0.0, 1.0, 0.0])
    return estimate.face_centre + estimate.face_rotation @ offset
