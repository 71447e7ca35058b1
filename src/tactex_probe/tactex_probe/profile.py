# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The surface's profile along the probing line, from the points where the tip touched it.

Points are placed by their horizontal distance s along the probing direction; the slope
dz/ds at a point comes from the parabola through it and its nearest neighbours (the
line through two, level with one), and the normal is that slope turned up: it lies in
the vertical plane of the probing direction (the profile says nothing across it).
"""

from __future__ import annotations

from collections.abc import Sequence
import math

import numpy as np

from tactex_probe.errors import ParameterError


def horizontal(direction) -> np.ndarray:
    """Unit horizontal part of the probing direction (x when it has none).

    Raises:
        ParameterError: the direction is not finite.
    """
    x, y = float(direction[0]), float(direction[1])
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ParameterError(f'the probing direction must be finite, got {direction!r}')
    if math.hypot(x, y) <= 1e-9:
        return np.array([1.0, 0.0, 0.0])
    largest = max(abs(x), abs(y))  # scaled first: no overflow at float64's max
    x, y = x / largest, y / largest
    length = math.hypot(x, y)
    return np.array([x / length, y / length, 0.0])


def slope_at(points: Sequence[np.ndarray], s: float, direction) -> float:
    """dz/ds of the profile at distance `s`, from the (up to) three points nearest to it.

    Between points (or on one) a parabola through the three nearest; beyond the last
    point the line through the last two (a parabola extrapolates wildly).

    Args:
        points: located points (m, base_link), any order.
        s: where along the line (m, measured like the points' own s from the origin).
        direction: the probing direction.
    """
    if not points:
        return 0.0
    along = horizontal(direction)
    coordinates = np.array([float(np.dot(p, along)) for p in points])
    heights = np.array([float(p[2]) for p in points])
    nearest = np.argsort(np.abs(coordinates - s))[:3]
    if nearest.size == 1:
        return 0.0
    outside = s > coordinates.max() + 1e-6 or s < coordinates.min() - 1e-6
    if outside:
        nearest = nearest[:2]
    degree = min(2, nearest.size - 1)
    centred = coordinates[nearest] - s
    if np.ptp(centred) < 1e-6:
        return 0.0
    if degree == 2 and np.min(np.diff(np.sort(centred))) < 1e-6:
        degree = 1  # two points at one place: a parabola through them is not determined
    coefficients = np.polyfit(centred, heights[nearest], degree)
    return float(coefficients[-2])


def normal_from_slope(slope: float, direction) -> np.ndarray:
    """Outward unit normal of a profile rising by `slope` along the direction.

    Raises:
        ParameterError: the slope or the direction is not finite.
    """
    if not math.isfinite(slope):
        raise ParameterError(f'the profile slope must be finite, got {slope!r}')
    along = horizontal(direction)
    normal = np.array([0.0, 0.0, 1.0]) - slope * along
    return normal / math.hypot(1.0, slope)  # no overflow for steep slopes


def coordinate(point, direction) -> float:
    """Horizontal distance of `point` along the probing direction (from the origin)."""
    return float(np.dot(np.asarray(point, dtype=float), horizontal(direction)))
