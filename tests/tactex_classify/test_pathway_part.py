# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The part of a probed pathway a movement slides along: its contact and both speed ramps.

Forward parts start at the pathway's first contact, backward parts at its last and run
towards the first; a part ending between two contacts ends on the segment joining them;
a pathway shorter than the part cannot hold the movement (both lengths named).
"""

import math

import numpy as np
import pytest

from tactex_classify.identification.pathway_part import holds, movement_part, pathway_length
from tactex_description.movements import Movement
from tactex_description.speed_ramp import ramp_length_m

ACCELERATION = 0.05
# A pathway of 11 contacts 10 mm apart along x, on a gentle wave, normals tilting with it.
X = np.linspace(0.10, 0.20, 11)
POINTS = np.column_stack([X, np.zeros(11), 0.004 * np.sin(60 * X)])
NORMALS = np.column_stack([-0.24 * np.cos(60 * X), np.zeros(11), np.ones(11)])
NORMALS /= np.linalg.norm(NORMALS, axis=1, keepdims=True)


def movement(contact_m: float, direction: str = 'forward', speed: float = 0.02) -> Movement:
    return Movement('m', speed, 0.002, 0.5, direction, contact_m)


def test_a_cosine_ramp_covers_pi_v_squared_over_4a():
    assert ramp_length_m(0.02, 0.05) == pytest.approx(math.pi * 0.0004 / 0.2)
    assert movement(0.03).part_length_m(ACCELERATION) == pytest.approx(
        0.03 + 2 * ramp_length_m(0.02, ACCELERATION))


def test_a_forward_part_starts_at_the_first_contact_and_is_as_long_as_contact_and_ramps():
    wanted = movement(0.03)
    points, normals = movement_part(POINTS, NORMALS, wanted, ACCELERATION)
    assert points[0] == pytest.approx(POINTS[0])
    assert pathway_length(points) == pytest.approx(wanted.part_length_m(ACCELERATION))
    assert np.linalg.norm(normals, axis=1) == pytest.approx(np.ones(len(normals)))
    inner = len(points) - 1
    assert points[:inner] == pytest.approx(POINTS[:inner])  # the probed contacts themselves


def test_a_part_ending_between_contacts_ends_on_the_segment_joining_them():
    points, normals = movement_part(POINTS, NORMALS, movement(0.03), ACCELERATION)
    end, before, after = points[-1], POINTS[len(points) - 2], POINTS[len(points) - 1]
    along = np.dot(end - before, after - before) / np.dot(after - before, after - before)
    assert 0 < along < 1
    assert end == pytest.approx(before + along * (after - before))
    assert np.dot(normals[-1], NORMALS[len(points) - 2]) > 0.99


def test_a_backward_part_starts_at_the_last_contact_and_runs_towards_the_first():
    points, _ = movement_part(POINTS, NORMALS, movement(0.03, 'backward'), ACCELERATION)
    assert points[0] == pytest.approx(POINTS[-1])
    assert np.all(np.diff(points[:, 0]) < 0)


def test_a_movement_longer_than_the_pathway_is_refused_with_both_lengths():
    too_long = movement(0.09)  # 90 mm + 2 x 6.3 mm of ramps > 100.4 mm
    assert not holds(POINTS, too_long, ACCELERATION)
    with pytest.raises(ValueError, match=r'needs 102.6 mm .*the pathway is 10\d.\d mm long'):
        movement_part(POINTS, NORMALS, too_long, ACCELERATION)
    assert holds(POINTS, movement(0.08), ACCELERATION)


def test_a_part_within_a_millimetre_of_the_pathway_takes_all_of_it():
    length = pathway_length(POINTS)
    almost = movement(length - 2 * ramp_length_m(0.02, ACCELERATION) + 5e-4)
    points, _ = movement_part(POINTS, NORMALS, almost, ACCELERATION)
    assert points == pytest.approx(POINTS)


@pytest.mark.parametrize('points, normals, acceleration, match', [
    (POINTS[:1], NORMALS[:1], ACCELERATION, 'the pathway is 0.0 mm long'),
    (POINTS, NORMALS[:5], ACCELERATION, 'must both be N x 3'),
    (np.where(np.arange(33).reshape(11, 3) == 4, np.nan, POINTS), NORMALS, ACCELERATION,
     'non-finite'),
    (POINTS, NORMALS, 0.0, 'ramp acceleration must be finite and > 0'),
])
def test_what_cannot_be_a_pathway_is_refused(points, normals, acceleration, match):
    with pytest.raises(ValueError, match=match):
        movement_part(points, normals, movement(0.01), acceleration)
