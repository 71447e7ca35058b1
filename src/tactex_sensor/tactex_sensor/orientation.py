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
import sys

import numba
import numpy as np

from tactex_sensor.errors import ReadingError


@numba.njit(cache=True)
def unit_direction(x: float, y: float, z: float, limit: float
                   ) -> tuple[bool, float, float, float]:
    """(valid, unit vector) of a reading; invalid when non-finite, zero or an axis > limit.

    Divided by its largest axis before the norm is taken, so float32-max (or 1e300)
    readings do not overflow and subnormal ones keep their direction. Compiled by numba
    so the Madgwick kernels can call it.
    """
    if not (abs(x) <= limit and abs(y) <= limit and abs(z) <= limit):  # NaN fails too
        return False, 0.0, 0.0, 0.0
    largest = max(abs(x), abs(y), abs(z))
    if largest == 0.0:
        return False, 0.0, 0.0, 0.0
    x, y, z = x / largest, y / largest, z / largest
    norm = math.sqrt(x * x + y * y + z * z)
    return True, x / norm, y / norm, z / norm


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
        accel: accelerometer reading (m/s^2, any finite non-zero length, float64 max to
            subnormal).
        base_yaw_rad: rotation of the arm's base about z (alpha in eq. 3.5).

    Raises:
        ReadingError: the reading is zero, not finite or not a 3-vector, or the yaw is
            not finite (a ValueError).
    """
    a = np.asarray(accel, dtype=float)
    valid, ux, uy, uz = unit_direction(*a, sys.float_info.max) if a.shape == (3,) else (
        False, 0.0, 0.0, 0.0)
    if not valid:
        raise ReadingError(f'accel must be a finite non-zero 3-vector, got {accel!r}')
    if not math.isfinite(base_yaw_rad):
        raise ReadingError(f'base_yaw_rad must be finite, got {base_yaw_rad!r}')
    align = gravity_alignment(ux, uy, uz)
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
    """Rotation angle (rad) between two attitudes, accurate near 0; NaN for no attitude.

    A quaternion of any length stands for its direction; a zero or non-finite one is no
    attitude at all.
    """
    q_a, q_b = _unit(q_a), _unit(q_b)
    relative = quaternion_multiply(_conjugate(q_a), q_b)
    return 2.0 * math.atan2(float(np.linalg.norm(relative[1:])), abs(float(relative[0])))


def tilt_between(q_a, q_b) -> float:
    """Angle (rad) between the up axes of two attitudes, ignoring heading; NaN as above."""
    up_a = rotate(_conjugate(_unit(q_a)), (0.0, 0.0, 1.0))
    up_b = rotate(_conjugate(_unit(q_b)), (0.0, 0.0, 1.0))
    return math.atan2(float(np.linalg.norm(np.cross(up_a, up_b))), float(np.dot(up_a, up_b)))


def _unit(q) -> np.ndarray:
    """The quaternion scaled to length 1 (NaN where it has no direction: zero, not finite)."""
    q = np.asarray(q, dtype=float)
    scale = np.max(np.abs(q)) if np.all(np.isfinite(q)) else 0.0
    if not scale > 0:
        return np.full(4, np.nan)
    q = q / scale  # no overflow squaring huge components
    return q / np.linalg.norm(q)


def _conjugate(q) -> np.ndarray:
    return np.array([q[0], -q[1], -q[2], -q[3]], dtype=float)
