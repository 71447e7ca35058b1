# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The part of a probed pathway one movement slides along: never off the pathway.

A movement slides `contact_length_m` at its speed. The sweep ramps its speed up before
and down after that contact on the same surface (`tactex_description.speed_ramp`), so
its part of the pathway is the contact plus both ramps (`Movement.part_length_m`): from
the pathway's first contact onwards (forward) or from its last contact back towards the
first (backward). The part follows the pathway's polyline through its
contacts; where it ends between two contacts, its last point is interpolated on that
segment (its normal too, renormalised), so the edge stays on the probed surface. A
pathway shorter than the part cannot hold the movement.
"""

from __future__ import annotations

import math

import numpy as np

from tactex_description.movements import Movement

# A pathway this much shorter than a movement's contact still holds it (the probe's
# points are 10 mm apart; a millimetre less contact is well within one window's travel).
LENGTH_TOLERANCE_M = 1e-3


def pathway_length(points: np.ndarray) -> float:
    """Length of the polyline through `points` (N x 3, m); 0 for fewer than two."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    with np.errstate(over='ignore'):  # too long for a float: inf, which callers refuse
        return float(np.sum(np.linalg.norm(np.diff(points, axis=0), axis=1)))


def holds(points: np.ndarray, movement: Movement, acceleration_m_s2: float) -> bool:
    """Whether the pathway through `points` is long enough for `movement` and its ramps."""
    return pathway_length(points) >= movement.part_length_m(acceleration_m_s2) \
        - LENGTH_TOLERANCE_M


def movement_part(points: np.ndarray, normals: np.ndarray, movement: Movement,
                  acceleration_m_s2: float) -> tuple[np.ndarray, np.ndarray]:
    """(points, normals) of the part of the pathway `movement` slides along, in its order.

    Args:
        points: the pathway's contact positions in order (N x 3, m, finite).
        normals: their unit surface normals (N x 3).
        movement: its direction, speed and contact length.
        acceleration_m_s2: the sweep's ramp acceleration (> 0).

    Raises:
        ValueError: shapes that differ, non-finite values, or a pathway too short for the
            movement (both lengths named).
    """
    points = np.asarray(points, dtype=float)
    normals = np.asarray(normals, dtype=float)
    if points.ndim != 2 or points.shape[1:] != (3,) or normals.shape != points.shape:
        raise ValueError(f'points and normals must both be N x 3, got {points.shape} and '
                         f'{normals.shape}')
    if not (np.all(np.isfinite(points)) and np.all(np.isfinite(normals))):
        raise ValueError('the pathway holds a non-finite position or normal')
    if not (math.isfinite(acceleration_m_s2) and acceleration_m_s2 > 0):
        raise ValueError(f'the ramp acceleration must be finite and > 0, got '
                         f'{acceleration_m_s2!r}')
    length = pathway_length(points)
    if not math.isfinite(length):
        raise ValueError('the pathway is longer than a float can hold: its positions are not '
                         'in metres')
    needed = movement.part_length_m(acceleration_m_s2)
    if points.shape[0] < 2 or not holds(points, movement, acceleration_m_s2):
        raise ValueError(f'movement {movement.name} needs {1e3 * needed:.1f} mm (its contact '
                         f'and speed ramps); the pathway is {1e3 * length:.1f} mm long')
    if movement.direction == 'backward':
        points, normals = points[::-1], normals[::-1]
    travelled = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0),
                                                                 axis=1))])
    wanted = min(needed, length)
    inside = int(np.searchsorted(travelled, wanted, side='right'))  # contacts up to `wanted`
    if inside >= points.shape[0] or travelled[inside - 1] >= wanted:
        return points[:inside].copy(), normals[:inside].copy()
    fraction = (wanted - travelled[inside - 1]) / (travelled[inside] - travelled[inside - 1])
    end = points[inside - 1] + fraction * (points[inside] - points[inside - 1])
    normal = normals[inside - 1] + fraction * (normals[inside] - normals[inside - 1])
    with np.errstate(over='ignore'):  # normals far from unit: an infinite size gives 0
        size = np.linalg.norm(normal)
    normal = normal / size if size > 1e-9 else normals[inside - 1]  # opposite normals
    return (np.vstack([points[:inside], end]), np.vstack([normals[:inside], normal]))
