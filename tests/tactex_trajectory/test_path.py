# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Path from contacts: a smooth curve by arc length; bad contacts dropped with a reason."""

import math

from conftest import SURFACE, truth_normals, wave_pathway
import numpy as np
import pytest

from tactex_trajectory.errors import PathError
from tactex_trajectory.path import path_from_contacts, PathSettings


def height_error(path):
    return path.points[:, 2] - SURFACE.height(path.points[:, 0])


def normal_error_deg(path):
    cosine = np.sum(path.normals * truth_normals(path.points[:, 0]), axis=1)
    return np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))


def test_path_follows_clean_contacts_closely(clean_pathway):
    path = path_from_contacts(*clean_pathway)
    assert np.sqrt(np.mean(height_error(path) ** 2)) < 0.0004
    assert np.max(normal_error_deg(path)) < 3.0
    assert not path.dropped
    np.testing.assert_allclose(path.points[[0, -1], 0], [0.085, 0.215], atol=5e-4)


@pytest.mark.parametrize('seed', range(5))
def test_noisy_contacts_are_smoothed_below_their_noise_and_none_is_dropped(seed):
    path = path_from_contacts(*wave_pathway(seed))
    assert np.sqrt(np.mean(height_error(path) ** 2)) < 0.0008  # contacts: 1 mm
    assert np.mean(normal_error_deg(path)) < 2.5  # contacts: about 2.8 deg
    assert not path.dropped


def test_samples_are_even_in_arc_length_with_unit_normals_across_the_curve(clean_pathway):
    path = path_from_contacts(*clean_pathway, settings=PathSettings(spacing_m=0.002))
    chords = np.linalg.norm(np.diff(path.points, axis=0), axis=1)
    np.testing.assert_allclose(chords, np.diff(path.arclength_m), rtol=2e-3)
    assert np.ptp(np.diff(path.arclength_m)) < 1e-9
    assert np.diff(path.arclength_m)[0] <= 0.002
    np.testing.assert_allclose(np.linalg.norm(path.normals, axis=1), 1.0)
    np.testing.assert_allclose(np.linalg.norm(path.tangents, axis=1), 1.0)
    assert np.max(np.abs(np.sum(path.normals * path.tangents, axis=1))) < 1e-9
    assert np.all(path.tangents[:, 0] > 0)  # in the order given


def test_sample_count_can_be_set_exactly(clean_pathway):
    assert len(path_from_contacts(*clean_pathway, settings=PathSettings(samples=17))
               .arclength_m) == 17


def test_pathway_in_reverse_order_gives_the_same_curve_reversed(clean_pathway):
    points, normals = clean_pathway
    forward = path_from_contacts(points, normals)
    backward = path_from_contacts(points[::-1], normals[::-1])
    np.testing.assert_allclose(backward.points[::-1], forward.points, atol=1e-6)
    np.testing.assert_allclose(backward.normals[::-1], forward.normals, atol=1e-6)
    np.testing.assert_allclose(backward.tangents[::-1], -forward.tangents, atol=1e-6)
    assert backward.length_m == pytest.approx(forward.length_m)


@pytest.mark.parametrize('offset', [0.0, 0.0004])
def test_points_closer_than_a_millimetre_are_merged_and_reported(clean_pathway, offset):
    points, normals = clean_pathway
    points = np.insert(points, 4, points[3] + [offset, 0.0, 0.0], axis=0)
    normals = np.insert(normals, 4, normals[3], axis=0)
    path = path_from_contacts(points, normals)
    assert [d.index for d in path.dropped] == [4]
    assert 'merged into it' in path.dropped[0].reason and 'contact 3' in path.dropped[0].reason
    assert 4 not in path.kept
    assert np.all(np.isfinite(path.points))


def test_flipped_normal_is_dropped_and_reported(clean_pathway):
    points, normals = clean_pathway
    normals = normals.copy()
    normals[6] = -normals[6]
    path = path_from_contacts(points, normals)
    assert [d.index for d in path.dropped] == [6]
    assert 'flipped' in path.dropped[0].reason
    assert np.max(normal_error_deg(path)) < 3.0


def test_normal_disagreeing_with_its_neighbours_and_the_curve_is_dropped(clean_pathway):
    points, normals = clean_pathway
    normals = normals.copy()
    tilt = math.radians(40.0)
    normals[5] = [math.sin(tilt), 0.0, math.cos(tilt)]
    path = path_from_contacts(points, normals)
    assert [d.index for d in path.dropped] == [5]
    assert 'deg from its neighbours' in path.dropped[0].reason


def test_contact_off_the_curve_is_dropped_and_reported(clean_pathway):
    points, normals = clean_pathway
    points = points.copy()
    points[8, 2] += 0.008
    path = path_from_contacts(points, normals)
    assert [d.index for d in path.dropped] == [8]
    assert 'mm off the curve' in path.dropped[0].reason
    assert np.max(np.abs(height_error(path))) < 0.001


@pytest.mark.parametrize('bad, reason', [
    ('normal', 'normal is not finite'), ('position', 'position is not finite'),
    ('zero', 'normal has zero length'), ('status', 'status is not ok')])
def test_unusable_contacts_are_dropped_with_their_reason(clean_pathway, bad, reason):
    points, normals = (array.copy() for array in clean_pathway)
    ok = np.ones(len(points), dtype=bool)
    if bad == 'normal':
        normals[3, 1] = math.nan
    elif bad == 'position':
        points[3, 0] = math.inf
    elif bad == 'zero':
        normals[3] = 0.0
    else:
        ok[3] = False
    path = path_from_contacts(points, normals, ok)
    assert [(d.index, d.reason.split(' (')[0]) for d in path.dropped] == [(3, reason)]
    assert np.all(np.isfinite(path.points)) and np.all(np.isfinite(path.normals))


def test_one_point_is_refused_with_the_reason():
    with pytest.raises(PathError, match=r'at least 2 usable contacts.*1 given, 1 usable'):
        path_from_contacts([[0.1, 0.0, 0.02]], [[0.0, 0.0, 1.0]])


def test_identical_points_are_refused_after_merging():
    with pytest.raises(PathError, match=r'3 given, 1 usable.*merged into it'):
        path_from_contacts([[0.1, 0.0, 0.02]] * 3, [[0.0, 0.0, 1.0]] * 3)


def test_no_usable_contact_is_refused():
    with pytest.raises(PathError, match='0 usable.*normal is not finite'):
        path_from_contacts([[0.1, 0.0, 0.02], [0.12, 0.0, 0.02]],
                           [[math.nan, 0.0, 1.0], [0.0, math.nan, 1.0]])


def test_two_contacts_with_opposite_normals_are_refused():
    with pytest.raises(PathError, match='no third contact'):
        path_from_contacts([[0.1, 0.0, 0.02], [0.12, 0.0, 0.02]],
                           [[0.0, 0.0, 1.0], [0.0, 0.0, -1.0]])


def test_two_contacts_make_a_straight_path():
    path = path_from_contacts([[0.1, 0.0, 0.02], [0.14, 0.0, 0.02]],
                              [[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]])
    assert path.length_m == pytest.approx(0.04, abs=1e-5)
    np.testing.assert_allclose(path.points[:, 2], 0.02, atol=1e-9)
    np.testing.assert_allclose(path.normals, [[0.0, 0.0, 1.0]] * len(path.normals), atol=1e-9)


@pytest.mark.parametrize('points, normals, ok, match', [
    ([[0.1, 0.0]], [[0.0, 1.0]], None, 'shape'),
    ([[0.1, 0.0, 0.0]], [[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]], None, 'shape'),
    ([[0.1, 0.0, 0.0]], [[0.0, 0.0, 1.0]], [True, False], 'ok must have shape'),
    ([['a', 0.0, 0.0]], [[0.0, 0.0, 1.0]], None, 'numeric'),
])
def test_malformed_arrays_are_refused(points, normals, ok, match):
    with pytest.raises(PathError, match=match):
        path_from_contacts(points, normals, ok)


def test_far_away_pathway_stays_finite():
    xs = np.linspace(1e5, 1e5 + 0.1, 11)
    points = np.stack([xs, np.zeros_like(xs), np.full_like(xs, 1e5)], axis=1)
    path = path_from_contacts(points, np.tile([0.0, 0.0, 1.0], (11, 1)))
    assert np.all(np.isfinite(path.points)) and path.length_m == pytest.approx(0.1, abs=1e-5)


@pytest.mark.parametrize('name, value', [('spacing_m', 0.0), ('position_noise_m', math.nan),
                                         ('normal_tolerance_rad', -1.0), ('samples', 1)])
def test_settings_out_of_range_are_refused(name, value):
    with pytest.raises(ValueError, match=name):
        PathSettings(**{name: value})
