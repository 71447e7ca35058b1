# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The profile traced by located points: slopes, extrapolation, normals."""

import math

import numpy as np
import pytest

from tactex_probe.profile import coordinate, normal_from_slope, slope_at


def parabola(xs):
    return [np.array([x, 0.0, 0.02 + 0.3 * (x - 0.15) ** 2 * 10]) for x in xs]


def test_slope_between_points_is_the_parabola_slope():
    points = parabola([0.13, 0.14, 0.15, 0.16, 0.17])
    assert slope_at(points, 0.14, (1.0, 0.0, 0.0)) == pytest.approx(6.0 * (0.14 - 0.15))


def test_slope_beyond_the_last_point_is_the_line_through_the_last_two():
    points = parabola([0.13, 0.14, 0.15])
    assert slope_at(points, 0.17, (1.0, 0.0, 0.0)) == pytest.approx(
        (points[2][2] - points[1][2]) / 0.01)


def test_no_or_one_point_means_level():
    assert slope_at([], 0.1, (1.0, 0.0, 0.0)) == 0.0
    assert slope_at(parabola([0.1]), 0.2, (1.0, 0.0, 0.0)) == 0.0


def test_profile_along_a_diagonal_uses_horizontal_distance():
    direction = np.array([1.0, 1.0, 0.0]) / math.sqrt(2.0)
    points = [np.array([s, s, 0.01 * s * math.sqrt(2.0)]) / 1.0 for s in (0.1, 0.11, 0.12)]
    assert coordinate(points[1], direction) == pytest.approx(0.11 * math.sqrt(2.0))
    assert slope_at(points, coordinate(points[1], direction), direction) == pytest.approx(0.01)


def test_normal_leans_against_the_rise():
    normal = normal_from_slope(1.0, (1.0, 0.0, 0.0))
    assert normal == pytest.approx([-math.sqrt(0.5), 0.0, math.sqrt(0.5)])
