# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Time parameterisation: joint trajectories at a constant sliding speed, within the limits.

A geometric joint path q(s) (s: the edge's travel in m, or the fraction of a joint-space
move) becomes timed points by a time law s(t): minimum-jerk (rest to rest) for moves,
approach, descent and lift; for the slide, a cosine ramp up to the sliding speed, the
constant speed, a cosine ramp down. Velocities q'(s) s' and accelerations
q''(s) s'^2 + q'(s) s'' come from a cubic spline of q(s), and every law is stretched
until the joint velocity and acceleration limits of the robot description hold.
"""

from __future__ import annotations

from dataclasses import dataclass
import math

import numpy as np
from scipy.interpolate import CubicHermiteSpline, CubicSpline

from tactex_description.geometry import ARM_JOINT_NAMES, OPEN_MANIPULATOR_X
from tactex_description.speed_ramp import ramp_duration_s, TimeLaw
from tactex_trajectory.errors import SweepRefused

VELOCITY_LIMITS = np.array([OPEN_MANIPULATOR_X.joint(n).velocity for n in ARM_JOINT_NAMES])
ACCELERATION_LIMITS = np.array([OPEN_MANIPULATOR_X.joint(n).acceleration
                                for n in ARM_JOINT_NAMES])
# Planned peaks stay this far below the limits (the driver's interpolant may overshoot).
LIMIT_MARGIN = 0.9
# Peak speed and acceleration of the minimum-jerk law, per unit of length and time.
MIN_JERK_PEAK_SPEED = 1.875
MIN_JERK_PEAK_ACCELERATION = 10.0 / math.sqrt(3.0)
# Points per second of a minimum-jerk move (at least MIN_MOVE_POINTS).
MOVE_POINTS_PER_S = 10.0
MIN_MOVE_POINTS = 8
# Samples per metre (and per unit fraction) used to check a geometric path's derivatives.
CHECK_SAMPLES = 400
# No part of a sweep (a move, the descent, the slide, the lift) may last longer (s): slower
# settings are refused rather than planned into an endless (and memory-hungry) trajectory.
MAX_PART_S = 3600.0


def check_duration(duration_s: float, part: str) -> None:
    """Refuse a part of a sweep that would last longer than MAX_PART_S (or not finitely).

    Raises:
        SweepRefused: naming the part and what to change.
    """
    if not duration_s <= MAX_PART_S:
        raise SweepRefused(f'{part} would take {duration_s:.3g} s, more than {MAX_PART_S:g} s: '
                           'raise its speed')


@dataclass(frozen=True)
class TimedJoints:
    """Timed joint points: what a trajectory_msgs/JointTrajectory carries.

    Attributes:
        times_s: (n,) time from start, strictly increasing.
        positions, velocities, accelerations: (n, 4) of joint1..joint4 (rad, rad/s, rad/s^2).
    """

    times_s: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    accelerations: np.ndarray
    joint_names: tuple[str, ...] = ARM_JOINT_NAMES

    @property
    def duration_s(self) -> float:
        """Time of the last point (s)."""
        return float(self.times_s[-1])

    def interpolant(self) -> CubicHermiteSpline:
        """The piecewise cubic through the points and their velocities (as the driver plays)."""
        return CubicHermiteSpline(self.times_s, self.positions, self.velocities, axis=0)

    def shifted(self, offset_s: float) -> TimedJoints:
        """The same points `offset_s` later."""
        return TimedJoints(self.times_s + offset_s, self.positions, self.velocities,
                           self.accelerations, self.joint_names)


def concatenate(parts: list[TimedJoints]) -> TimedJoints:
    """Join parts end to start; a part's first point replaces the previous part's last."""
    times, positions, velocities, accelerations = [], [], [], []
    offset = 0.0
    for index, part in enumerate(parts):
        skip = 1 if index else 0
        times.append(part.times_s[skip:] + offset)
        positions.append(part.positions[skip:])
        velocities.append(part.velocities[skip:])
        accelerations.append(part.accelerations[skip:])
        offset += part.duration_s
    return TimedJoints(np.concatenate(times), np.vstack(positions), np.vstack(velocities),
                       np.vstack(accelerations))


def min_jerk_law(length: float, duration_s: float) -> TimeLaw:
    """Rest to rest: s = L (10 r^3 - 15 r^4 + 6 r^5), r = t / T."""
    def phase(t):  # r in [0, 1]; t clipped first, so a huge t cannot overflow t / T
        return np.clip(np.asarray(t, dtype=float), 0.0, duration_s) / duration_s

    def position(t):
        r = phase(t)
        return length * (10 * r ** 3 - 15 * r ** 4 + 6 * r ** 5)

    def speed(t):
        r = phase(t)
        return length / duration_s * (30 * r ** 2 - 60 * r ** 3 + 30 * r ** 4)

    def acceleration(t):
        r = phase(t)
        return length / duration_s ** 2 * (60 * r - 180 * r ** 2 + 120 * r ** 3)

    return TimeLaw(duration_s, length, position, speed, acceleration)


@dataclass(frozen=True)
class JointPath:
    """A geometric joint path q(s) for s in [0, length], a cubic spline through samples."""

    travel: np.ndarray  # (k,) s of the samples, strictly increasing
    joints: np.ndarray  # (k, 4)

    def __post_init__(self) -> None:
        """Build the spline (straight between two samples)."""
        kind = 'not-a-knot' if len(self.travel) > 3 else 'natural'
        object.__setattr__(self, '_spline', CubicSpline(self.travel, self.joints, axis=0,
                                                        bc_type=kind))

    @property
    def length(self) -> float:
        """Travel from the first to the last sample."""
        return float(self.travel[-1] - self.travel[0])

    def derivative_bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Max |q'(s)| and max |q''(s)| per joint over the path."""
        s = np.linspace(self.travel[0], self.travel[-1],
                        max(CHECK_SAMPLES, 4 * len(self.travel)))
        spline = self._spline
        return (np.max(np.abs(spline.derivative(1)(s)), axis=0),
                np.max(np.abs(spline.derivative(2)(s)), axis=0))

    def timed(self, law: TimeLaw, times_s: np.ndarray) -> TimedJoints:
        """Points at `times_s` (law time) following the law along the path."""
        s = self.travel[0] + law.position(times_s)
        speed = law.speed(times_s)[:, None]
        first = self._spline.derivative(1)(s)
        return TimedJoints(np.asarray(times_s, dtype=float), self._spline(s), first * speed,
                           self._spline.derivative(2)(s) * speed ** 2
                           + first * law.acceleration(times_s)[:, None])


def move_duration(path: JointPath, *, peak_speed: float = math.inf, minimum_s: float = 0.0
                  ) -> float:
    """Shortest minimum-jerk duration (s) within the joint limits and `peak_speed` of s."""
    length = path.length
    if length <= 0.0:
        return minimum_s
    first, second = path.derivative_bounds()
    velocity = VELOCITY_LIMITS * LIMIT_MARGIN
    acceleration = ACCELERATION_LIMITS * LIMIT_MARGIN
    by_speed = MIN_JERK_PEAK_SPEED * length * np.max(first / velocity)
    by_acceleration = math.sqrt(float(np.max(
        (second * (MIN_JERK_PEAK_SPEED * length) ** 2
         + first * MIN_JERK_PEAK_ACCELERATION * length) / acceleration)))
    by_cap = MIN_JERK_PEAK_SPEED * length / peak_speed
    return max(minimum_s, float(by_speed), by_acceleration, by_cap)


def timed_move(path: JointPath, duration_s: float) -> TimedJoints:
    """The path as a minimum-jerk move over `duration_s`, from rest to rest.

    Raises:
        SweepRefused: the move would last longer than MAX_PART_S.
    """
    check_duration(duration_s, 'a move')
    count = max(MIN_MOVE_POINTS, int(math.ceil(duration_s * MOVE_POINTS_PER_S)) + 1)
    law = min_jerk_law(path.length, duration_s)
    return path.timed(law, np.linspace(0.0, duration_s, count))


def ramp_duration(path: JointPath, speed_m_s: float, ramp_acceleration_m_s2: float) -> float:
    """Shortest cosine ramp (s) to `speed_m_s` within the joint limits.

    Raises:
        SweepRefused: the joints cannot follow the path at this speed at all.
    """
    first, second = path.derivative_bounds()
    velocity = VELOCITY_LIMITS * LIMIT_MARGIN
    acceleration = ACCELERATION_LIMITS * LIMIT_MARGIN
    with np.errstate(over='ignore'):  # a huge speed gives inf ratios: refused below
        ratio = first * speed_m_s / velocity
        squared = np.float64(speed_m_s) ** 2
        spare = acceleration - second * squared
    if np.any(ratio > 1.0) or np.any(spare <= 0.0):
        joint = int(np.argmax(np.maximum(ratio, second * squared / acceleration)))
        fastest = float(min(np.min(velocity / np.maximum(first, 1e-12)),
                            np.min(np.sqrt(acceleration / np.maximum(second, 1e-12)))))
        raise SweepRefused(f'{ARM_JOINT_NAMES[joint]} cannot follow the path at '
                           f'{speed_m_s * 1e3:.1f} mm/s within its velocity and acceleration '
                           f'limits; slide at most {fastest * 1e3 * 0.99:.1f} mm/s')
    by_cap = ramp_duration_s(speed_m_s, ramp_acceleration_m_s2)
    by_joints = float(np.max(math.pi * speed_m_s * first / (2.0 * spare)))
    return max(by_cap, by_joints)
