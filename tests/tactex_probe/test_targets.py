# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Where the explorer aims: probe points, the profile's normal, reachable tilts."""

import math

import numpy as np
import pytest

from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_probe import targets
from tactex_probe.motion import PathUnreachable, solve, tilt_towards, ToolPose
from tactex_probe.pathway import ContactStatus, ProbeParameters, ProbeRecord

SEED = [0.0, 0.0, 0.0, 1.5]
LINE = ProbeParameters(start=(0.12, 0.0, 0.03), direction=(1.0, 0.0, 0.0), span=0.06,
                       step=0.01, approach_height=0.02, descent_speed=0.005,
                       max_descent_depth=0.03, force_limit=5.0)


def record(x, tilt, ok=True):
    if not ok:
        return ProbeRecord(index=0, status=ContactStatus.NO_CONTACT, stamp_ns=0,
                           position=(x, 0.0, 0.0), normal=(0.0, 0.0, 0.0), force_proxy=0.0,
                           confidence=0.0)
    normal = -ToolPose([x, 0.0, 0.0], tilt).axis
    return ProbeRecord(index=0, status=ContactStatus.OK, stamp_ns=0, position=(x, 0.0, 0.0),
                       normal=tuple(normal), force_proxy=1.0, confidence=1.0)


def test_probe_points_step_along_the_line_and_one_beyond_each_end():
    assert targets.probe_point(LINE, 0) == pytest.approx([0.12, 0.0, 0.03])
    assert targets.probe_point(LINE, 3) == pytest.approx([0.15, 0.0, 0.03])
    assert targets.probe_point(LINE, -1) == pytest.approx([0.11, 0.0, 0.03])


def test_without_located_tips_the_profile_is_flat():
    assert targets.profile_normal([], [0.15, 0.0, 0.0], (1.0, 0.0, 0.0)) == pytest.approx(
        [0.0, 0.0, 1.0])


def test_tips_on_a_slope_give_its_normal_and_a_surface_point_one_radius_below():
    slope = 0.2
    centres = [np.array([x, 0.0, slope * x]) for x in (0.12, 0.13, 0.14)]
    normal = targets.profile_normal(centres, [0.13, 0.0, 0.0], (1.0, 0.0, 0.0))
    assert normal == pytest.approx(np.array([-slope, 0.0, 1.0]) / math.hypot(slope, 1.0))
    point = targets.surface_point(centres[1], centres, (1.0, 0.0, 0.0))
    assert np.linalg.norm(point - centres[1]) == pytest.approx(EDGE_TIP_RADIUS_M)


def test_the_normal_extrapolates_the_last_two_good_records_linearly():
    heading = targets.heading(LINE, 0)
    records = [record(0.12, 0.0), record(0.13, 0.1), record(0.14, 0.9, ok=False)]
    normal = targets.extrapolated_normal(records, [0.14, 0.0, 0.0], (1.0, 0.0, 0.0), heading)
    assert tilt_towards(normal, heading) == pytest.approx(0.2)
    assert targets.extrapolated_normal([], [0.14, 0.0, 0.0], (1.0, 0.0, 0.0),
                                       heading) == pytest.approx([0.0, 0.0, 1.0])


def test_a_tilt_the_arm_cannot_take_turns_towards_upright_until_it_can():
    point = np.array([0.15, 0.0, 0.03])
    assert targets.reachable_tilt(point, 0.3, max_tilt_rad=1.0, seed=SEED) == 0.3
    assert targets.reachable_tilt(point, 2.0, max_tilt_rad=0.5, seed=SEED) == 0.5
    far = np.array([0.60, 0.0, 0.03])
    with pytest.raises(PathUnreachable):
        solve(ToolPose(far, 0.0), SEED)
    assert targets.reachable_tilt(point, 0.3, (far,), max_tilt_rad=1.0, seed=SEED) == 0.0
