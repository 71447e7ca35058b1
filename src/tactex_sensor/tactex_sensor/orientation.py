# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Orientation from gravity (the original's eqs. 3.1-3.6) and the quaternion helpers around it.

Quaternions are (w, x, y, z) and rotate body vectors into the world frame (z up).
An accelerometer at rest reads +g along the world's up axis, so the attitude that
"aligns the measured accel with gravity" is the shortest rotation taking the
normalised accel reading onto +z, composed with the arm's base rotation about z.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(cache=True)
def gravity_alignment(ax: float, ay: float, az: float) -> tuple[float, float, float, float]:
    """Shortest rotation taking the unit vector (ax, ay, az) onto +z; exact near 0 and pi.

    Compiled by numba so the Madgwick kernels can call it.

    The half-way quaternion is (1 + az, ay, -ax, 0), normalised. At 180 degrees
    (az = -1) the cross product vanishes and any horizontal axis is right: x is
    chosen. 1 + az is formed without cancellation when az is near -1.
    """
    horizontal_sq = ax * ax + ay * ay
    w = 1.0 + az if az >= 0.0 else horizontal_sq / (1.0 - az)
    norm = math.sqrt(w * w + horizontal_sq)
    if norm < 1e-150:
        return 0.0, 1.0, 0.0, 0.0
    return w / norm, ay / norm, -ax / norm, 0.0


def orientation_from_gravity(accel, base_yaw_rad: float = 0.0) -> np.ndarray:
    """Return the attitude quaternion (w, x, y, z) R_z(base_yaw) * R_ag of a static sensor.

    Args:
        accel: accelerometer reading (m/s^2, any non-zero length).
        base_yaw_rad: rotation of the arm's base about z (alpha in eq. 3.5).

    Raises:
        ValueError: the reading is zero or not finite.
    """
    a = np.asarray(accel, dtype=float)
    norm = float(np.linalg.norm(a))
    if a.shape != (3,) or not math.isfinite(norm) or norm == 0.0:
        raise ValueError(f'accel must be a finite non-zero 3-vector, got {accel!r}')
    align = gravity_alignment(*(a / norm))
    half = 0.5 * base_yaw_rad
    yaw = (math.cos(half), 0.0, 0.0, math.sin(half))
    return quaternion_multiply(yaw, align)


def quaternion_multiply(a, b) -> np.ndarray:
    """Hamilton product a * b of (w, x, y, z) quaternions."""
    a0, a1, a2, a3 = a
    b0, b1, b2, b3 = b
    return np.array([a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
                     a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
                     a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
                     a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0])


def rotate(quaternion, vector) -> np.ndarray:
    """Rotate a body `vector` into the world frame by `quaternion` (w, x, y, z)."""
    w, x, y, z = quaternion
    matrix = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])
    return matrix @ np.asarray(vector, dtype=float)


def angle_between(q_a, q_b) -> float:
    """Rotation angle (rad) between two attitudes."""
    dot = abs(float(np.dot(q_a, q_b))) / (np.linalg.norm(q_a) * np.linalg.norm(q_b))
    return 2.0 * math.acos(min(1.0, dot))


def tilt_between(q_a, q_b) -> float:
    """Angle (rad) between the up axes of two attitudes, ignoring heading."""
    up_a = rotate(_conjugate(q_a), (0.0, 0.0, 1.0))
    up_b = rotate(_conjugate(q_b), (0.0, 0.0, 1.0))
    return math.atan2(float(np.linalg.norm(np.cross(up_a, up_b))), float(np.dot(up_a, up_b)))


def _conjugate(q) -> np.ndarray:
    return np.array([q[0], -q[1], -q[2], -q[3]], dtype=float)
