# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Where the explorer aims: probe points, the profile's normal, tilts the arm can take.

Pure geometry on the probe line (`ProbeParameters`): no state, no arm, no clock. The
explorer (`tactex_probe.exploration`) asks it where the next touch goes.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_probe.motion import PathUnreachable, pose_with_tip_at, solve, tilt_towards, ToolPose
from tactex_probe.pathway import ProbeParameters, ProbeRecord
from tactex_probe.profile import coordinate, normal_from_slope, slope_at

# Tilts tried between the asked one and upright when the arm cannot take the asked one.
TILT_CANDIDATES = 9


def probe_point(parameters: ProbeParameters, index: int) -> np.ndarray:
    """Probe point `index` (-1 and the count: the points one step beyond the ends)."""
    return np.asarray(parameters.start) + index * parameters.step * np.asarray(
        parameters.direction)


def heading(parameters: ProbeParameters, index: int) -> float:
    """The arm's heading (rad about z) towards probe point `index`."""
    return ToolPose(probe_point(parameters, index), 0.0).heading


def profile_normal(tip_centres: Sequence[np.ndarray], point, direction) -> np.ndarray:
    """Normal at `point` of the profile the located tips trace (vertical without one)."""
    return normal_from_slope(slope_at(list(tip_centres), coordinate(point, direction),
                                      direction), direction)


def surface_point(tip_centre: np.ndarray, tip_centres: Sequence[np.ndarray],
                  direction) -> np.ndarray:
    """Where a tip centred at `tip_centre` touches: one tip radius along -normal."""
    return tip_centre - EDGE_TIP_RADIUS_M * profile_normal(tip_centres, tip_centre, direction)


def extrapolated_normal(records: Sequence[ProbeRecord], point, direction,
                        heading_rad: float) -> np.ndarray:
    """The normal the last two good records' normals extrapolate to at `point`.

    Vertical without a good record, the last one's with one; the tilt towards
    `heading_rad` changes linearly along the line between the last two.
    """
    found = [record for record in records if record.ok][-2:]
    if not found:
        return np.array([0.0, 0.0, 1.0])
    if len(found) < 2:
        return np.asarray(found[-1].normal)
    tilts = [tilt_towards(record.normal, heading_rad) for record in found]
    s = [coordinate(record.position, direction) for record in found]
    rate = (tilts[1] - tilts[0]) / (s[1] - s[0]) if abs(s[1] - s[0]) > 1e-6 else 0.0
    tilt = tilts[1] + rate * (coordinate(point, direction) - s[1])
    return -ToolPose(point, tilt).axis


def reachable_tilt(point, tilt: float, also: Sequence[np.ndarray] = (), *,
                   max_tilt_rad: float, seed, tip: bool = False) -> float:
    """`tilt` within +-max_tilt_rad, then towards 0 until the arm reaches every pose.

    The poses: the tool (its tip, with `tip`) at `point` and at each of `also`. 0 when
    no candidate works.
    """
    tilt = float(np.clip(tilt, -max_tilt_rad, max_tilt_rad))
    for candidate in np.linspace(tilt, 0.0, TILT_CANDIDATES):
        try:
            for where in (point, *also):
                solve(pose_with_tip_at(where, candidate) if tip
                      else ToolPose(where, candidate), seed)
        except PathUnreachable:
            continue
        return float(candidate)
    return 0.0
