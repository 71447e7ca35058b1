# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Joint trajectories for the driver: validated as a whole, then sampled at the control rate.

A trajectory is accepted only if all of it is safe: known joint names, finite values,
strictly increasing times, every point within the position limits, a first point near
the current state, and an interpolated profile (from the current state through every
point) that stays within the position and velocity limits. Otherwise it is refused
with the reason and nothing of it runs. Joints the trajectory does not name hold still.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
import math

import numpy as np
from scipy.interpolate import CubicHermiteSpline, PchipInterpolator

from tactex_description.geometry import JOINT_STATE_NAMES, OPEN_MANIPULATOR_X
from tactex_driver.errors import TrajectoryRejected

SAMPLES_PER_SEGMENT = 32
LIMIT_TOLERANCE = 1e-9
# Closer points make the spline's slopes overflow (a subnormal gap gives inf).
MIN_POINT_SPACING_S = 1e-6


@dataclass(frozen=True)
class JointLimits:
    """Position (rad or m) and velocity limits of the commanded joints, in `names` order."""

    names: tuple[str, ...]
    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray

    @classmethod
    def of_robot(cls) -> JointLimits:
        """The limits of joint1..joint4 and the gripper from the robot description."""
        joints = [OPEN_MANIPULATOR_X.joint(name) for name in JOINT_STATE_NAMES]
        return cls(JOINT_STATE_NAMES, np.array([j.lower for j in joints]),
                   np.array([j.upper for j in joints]), np.array([j.velocity for j in joints]))

    def clamp(self, positions: np.ndarray) -> np.ndarray:
        """Positions clamped into the limits."""
        return np.clip(positions, self.lower, self.upper)


@dataclass(frozen=True)
class TrajectoryArrays:
    """A trajectory_msgs/JointTrajectory as plain arrays (what `plan` takes)."""

    joint_names: list[str]
    times_s: list[float]
    positions: list[list[float]]
    velocities: list[list[float]]


def trajectory_arrays(message) -> TrajectoryArrays:
    """Arrays of a JointTrajectory message (rclpy or rosbags: read by attribute only)."""
    points = list(message.points)
    return TrajectoryArrays(
        [str(name) for name in message.joint_names],
        [p.time_from_start.sec + 1e-9 * p.time_from_start.nanosec for p in points],
        [[float(v) for v in p.positions] for p in points],
        [[float(v) for v in p.velocities] for p in points])


@dataclass(frozen=True)
class Trajectory:
    """An accepted trajectory: a C1 interpolant of all joints from t = 0 (the start state)."""

    duration_s: float
    _curve: object
    _limits: JointLimits

    def sample(self, t_s: float) -> np.ndarray:
        """Positions at `t_s` seconds after the start (held at the ends), within limits.

        Raises:
            ValueError: `t_s` is NaN (+-inf hold the ends).
        """
        if math.isnan(t_s):
            raise ValueError('t_s must not be NaN')
        t = min(max(t_s, 0.0), self.duration_s)
        return self._limits.clamp(np.asarray(self._curve(t), dtype=float))


def plan(joint_names: Sequence[str], times_s: Sequence[float],
         positions: Sequence[Sequence[float]], velocities: Sequence[Sequence[float]],
         current: np.ndarray, limits: JointLimits, *, start_tolerance: float = 0.1
         ) -> Trajectory:
    """Validate a trajectory and return its interpolant from the current state.

    Args:
        joint_names: joints the points refer to (a subset of `limits.names`).
        times_s: time from start of each point (s).
        positions: one row per point, one value per named joint.
        velocities: one row per point (or empty rows, or no rows): velocities at the points.
        current: present positions of all joints, in `limits.names` order.
        limits: the joint limits.
        start_tolerance: the first point may differ from the current state by this much.

    Raises:
        TrajectoryRejected: any rule is broken, or the current state is not finite (no
            safe start); the message says which and where.
        ValueError: a start tolerance that is not finite or negative.
    """
    current = np.asarray(current, dtype=float)
    if current.shape != limits.lower.shape or not np.all(np.isfinite(current)):
        raise TrajectoryRejected(f'the current state is not {limits.lower.size} finite '
                                 f'positions ({current!r}); no safe start')
    if not (math.isfinite(start_tolerance) and start_tolerance >= 0):
        raise ValueError(f'start_tolerance must be finite and >= 0, got {start_tolerance!r}')
    names = list(joint_names)
    if not names:
        raise TrajectoryRejected('trajectory names no joints')
    unknown = [n for n in names if n not in limits.names]
    if unknown:
        raise TrajectoryRejected(f'unknown joint(s) {unknown!r}; known: {list(limits.names)}')
    if len(set(names)) != len(names):
        raise TrajectoryRejected(f'joint names repeat: {names!r}')
    if len(times_s) == 0:
        raise TrajectoryRejected('trajectory has no points')
    columns = [limits.names.index(n) for n in names]
    times = np.asarray(times_s, dtype=float)
    rows = _rows(positions, len(names), 'positions', len(times))
    has_velocities = any(len(v) for v in velocities)
    speeds = _rows(velocities, len(names), 'velocities', len(times)) if has_velocities else None
    if not np.all(np.isfinite(times)) or times[0] < 0 or np.any(np.diff(times) <= 0):
        raise TrajectoryRejected(f'time_from_start must be finite, >= 0 and strictly '
                                 f'increasing, got {times.tolist()!r}')
    if 0 < times[0] < MIN_POINT_SPACING_S or np.any(np.diff(times) < MIN_POINT_SPACING_S):
        raise TrajectoryRejected(f'points must be at least {MIN_POINT_SPACING_S * 1e6:g} us '
                                 f'apart (and from the start), got {times.tolist()!r}')
    full = np.tile(current, (len(times), 1))
    full[:, columns] = rows
    for index, row in enumerate(full):
        low = row < limits.lower - LIMIT_TOLERANCE
        high = row > limits.upper + LIMIT_TOLERANCE
        if np.any(low | high):
            joint = int(np.argmax(low | high))
            raise TrajectoryRejected(
                f'point {index}: {limits.names[joint]} = {row[joint]:.4f} is outside '
                f'[{limits.lower[joint]:.4f}, {limits.upper[joint]:.4f}]')
    deviation = np.abs(full[0] - current)
    if np.any(deviation > start_tolerance):
        joint = int(np.argmax(deviation))
        raise TrajectoryRejected(
            f'first point is {deviation[joint]:.3f} from the current {limits.names[joint]} '
            f'({current[joint]:.3f}); start within {start_tolerance} of the current state')
    knots_t = times if times[0] == 0.0 else np.concatenate([[0.0], times])
    knots_q = full if times[0] == 0.0 else np.vstack([current, full])
    if speeds is not None:
        full_v = np.zeros_like(full)
        full_v[:, columns] = speeds
        knots_v = full_v if times[0] == 0.0 else np.vstack([np.zeros_like(current), full_v])
        if np.any(np.abs(knots_v) > limits.velocity + LIMIT_TOLERANCE):
            raise TrajectoryRejected('a point velocity exceeds the joint velocity limit')
        curve = CubicHermiteSpline(knots_t, knots_q, knots_v, axis=0) if len(knots_t) > 1 \
            else None
    else:
        with np.errstate(over='ignore'):  # subnormal steps: a slope's mean overflows to a
            # flat 0; what is not finite is refused by _check_profile
            curve = PchipInterpolator(knots_t, knots_q, axis=0) if len(knots_t) > 1 else None
    if curve is None:  # a single point at t = 0: hold it
        point = knots_q[0].copy()
        return Trajectory(0.0, lambda _t: point, limits)
    _check_profile(curve, knots_t, limits)
    return Trajectory(float(knots_t[-1]), curve, limits)


def _rows(values: Sequence[Sequence[float]], width: int, what: str, count: int) -> np.ndarray:
    if len(values) != count:
        raise TrajectoryRejected(f'{count} points but {len(values)} rows of {what}')
    try:
        array = np.array([list(row) for row in values], dtype=float)
    except ValueError as err:
        raise TrajectoryRejected(f'{what} are malformed: {err}') from None
    if array.shape != (count, width):
        raise TrajectoryRejected(f'each point needs {width} {what}, got shape {array.shape!r}')
    if not np.all(np.isfinite(array)):
        raise TrajectoryRejected(f'{what} contain NaN or infinity')
    return array


def _check_profile(curve, knots_t: np.ndarray, limits: JointLimits) -> None:
    """Reject an interpolant that leaves the limits between points or moves too fast."""
    t = np.concatenate([np.linspace(a, b, SAMPLES_PER_SEGMENT, endpoint=False)
                        for a, b in zip(knots_t[:-1], knots_t[1:], strict=True)]
                       + [knots_t[-1:]])
    q = curve(t)
    v = curve.derivative()(t)
    if not (np.all(np.isfinite(q)) and np.all(np.isfinite(v))):
        raise TrajectoryRejected('the interpolated path is not finite (points too close in '
                                 'time for their positions); give the points more time')
    if np.any(q < limits.lower - 1e-6) or np.any(q > limits.upper + 1e-6):
        raise TrajectoryRejected('the interpolated path leaves the position limits between '
                                 'points; add points or lower the point velocities')
    ratio = np.abs(v) / limits.velocity
    if np.any(ratio > 1.0 + 1e-6):
        row, joint = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
        raise TrajectoryRejected(
            f'{limits.names[joint]} would move at {abs(v[row, joint]):.3f} '
            f'(limit {limits.velocity[joint]:.3f}) around t = {t[row]:.3f} s; '
            f'give the points more time')


def hold(positions: np.ndarray, limits: JointLimits) -> Trajectory:
    """A trajectory that holds `positions` (clamped into the limits).

    Raises:
        ValueError: a position that is not finite.
    """
    if not np.all(np.isfinite(positions)):
        raise ValueError(f'cannot hold non-finite positions {positions!r}')
    point = limits.clamp(np.asarray(positions, dtype=float))
    return Trajectory(0.0, lambda _t: point, limits)

