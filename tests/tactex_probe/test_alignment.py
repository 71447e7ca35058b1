# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The root search for the tilt at which the face lies flat."""

import math
from types import SimpleNamespace

import pytest

from tactex_probe.alignment import best, next_tilt, RIM_STEP_RAD, TouchResult

DEG = math.radians(1.0)


def touch(tilt_deg, turn_deg, light_turn_deg=None):
    light = turn_deg if light_turn_deg is None else light_turn_deg
    return TouchResult(tilt_deg * DEG, SimpleNamespace(turn_rad=light * DEG),
                       SimpleNamespace(turn_rad=turn_deg * DEG))


def test_flat_needs_a_small_turn_that_pressing_harder_does_not_grow():
    assert touch(0, 0.3, 0.2).flat(0.5 * DEG)
    assert not touch(0, 0.3, -0.4).flat(0.5 * DEG)  # kept turning with the force
    assert not touch(0, 1.5).flat(0.5 * DEG)


def test_first_step_assumes_the_face_lay_flat():
    assert next_tilt([touch(10, -3)]) == pytest.approx(7 * DEG)


def test_flat_response_lands_on_the_root():
    # turn = 12 deg - tilt: a slope of -1.
    assert next_tilt([touch(5, 7), touch(9, 3)]) == pytest.approx(12 * DEG)


def test_bearing_rim_steps_towards_the_side_the_turn_shows():
    # The turn hardly changed with the tilt: only the rim bore.
    assert next_tilt([touch(20, -0.8), touch(19.2, -0.75)]) == pytest.approx(
        19.2 * DEG - RIM_STEP_RAD)


def test_bracketed_root_is_interpolated():
    assert next_tilt([touch(0, 2), touch(8, -2)]) == pytest.approx(4 * DEG)


def test_steps_on_a_bearing_rim_grow_until_bounded():
    touches = [touch(0, 1.0), touch(1, 0.9)]
    assert next_tilt(touches) == pytest.approx(1 * DEG + RIM_STEP_RAD)
    touches.append(touch(9, 0.8))
    assert next_tilt(touches) == pytest.approx(25 * DEG)
    assert next_tilt([touch(0, 40)]) == pytest.approx(20 * DEG)


def test_best_prefers_the_last_flat_touch_else_the_smallest_turn():
    flat_early, flat_late, steep = touch(0, 0.2), touch(1, -0.1), touch(2, 3)
    assert best([flat_early, flat_late, steep], 0.5 * DEG) is flat_late
    assert best([touch(0, 2), touch(1, -1.5), steep], 0.5 * DEG).tilt == pytest.approx(DEG)


def test_no_touch_no_tilt():
    with pytest.raises(ValueError, match='at least one touch'):
        next_tilt([])
