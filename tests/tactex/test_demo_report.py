# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The demo's figures: pathway errors, live decisions, accuracy against time, thresholds."""

import math

import numpy as np
import pytest

from tactex.demo.figures import (
    accuracy_against_contact_time,
    Check,
    checks,
    confusion,
    Estimate,
    live_figures,
    LiveSweep,
    path_length,
    pathway_errors,
    plot_accuracy_against_time,
    plot_confusion,
    plot_pathway,
    plot_sweeps,
)
from tactex_probe.closed_loop import true_normal
from tactex_sim.scene import load_scene, resolve_scene

SURFACE = load_scene(resolve_scene('uneven_texture')).surface


def test_contacts_on_the_true_surface_have_no_error_and_a_tilted_normal_its_angle():
    xs = np.array([0.10, 0.13, 0.17])
    positions = np.array([[x, 0.0, float(SURFACE.height(x))] for x in xs])
    normals = np.array([true_normal(SURFACE, x) for x in xs])
    normal_deg, position_mm = pathway_errors(positions, normals, SURFACE)
    assert normal_deg == pytest.approx(0.0, abs=0.05)
    assert position_mm == pytest.approx(0.0, abs=0.02)
    lifted = positions + [0.0, 0.0, 0.001]
    tilt = math.radians(10.0)
    rotation = np.array([[math.cos(tilt), 0, math.sin(tilt)], [0, 1, 0],
                         [-math.sin(tilt), 0, math.cos(tilt)]])
    normal_deg, position_mm = pathway_errors(lifted, normals @ rotation.T, SURFACE)
    assert normal_deg == pytest.approx(10.0, abs=1.0)  # measured at the nearest point
    assert np.all((position_mm > 0.5) & (position_mm <= 1.0))


def test_the_decision_is_the_first_decided_estimate_else_the_last():
    early = Estimate('wood', True, 1.0)
    sweep = LiveSweep('wood', (Estimate('carpet wool', False, 0.5), early,
                               Estimate('carpet wool', True, 2.0)))
    assert sweep.decision() is early
    undecided = LiveSweep('wood', (Estimate('wood', False, 0.5), Estimate('mesh', False, 1.5)))
    assert undecided.decision().label == 'mesh'
    assert LiveSweep('wood', ()).decision() is None


def test_live_figures_count_a_silent_sweep_as_wrong_and_time_forced_decisions():
    sweeps = [LiveSweep('wood', (Estimate('wood', True, 1.0),)),
              LiveSweep('mesh', (Estimate('wood', True, 3.0),)),
              LiveSweep('mesh', (Estimate('mesh', False, 4.0),)),
              LiveSweep('wood', ())]
    figures = live_figures(sweeps)
    assert figures['live_accuracy'] == 0.5
    assert figures['time_to_decision_s'] == 3.0  # median of 1, 3 and 4 (decided at its end)
    assert figures['live_decided'] == 2 and figures['live_sweeps'] == 4
    assert math.isnan(live_figures([])['live_accuracy'])
    assert math.isnan(live_figures(sweeps[3:])['time_to_decision_s'])


def test_accuracy_against_contact_time_follows_the_latest_estimate():
    sweeps = [LiveSweep('wood', (Estimate('mesh', False, 0.5), Estimate('wood', False, 1.5))),
              LiveSweep('mesh', (Estimate('mesh', False, 1.0),))]
    accuracy = accuracy_against_contact_time(sweeps, np.array([0.0, 0.6, 1.0, 2.0]))
    assert accuracy.tolist() == [0.0, 0.0, 0.5, 1.0]


def test_confusion_counts_true_against_decided_and_sweeps_never_estimated():
    classes = ['mesh', 'wood']
    sweeps = [LiveSweep('wood', (Estimate('mesh', True, 1.0),)),
              LiveSweep('wood', (Estimate('wood', True, 1.0),)), LiveSweep('mesh', ())]
    assert confusion(sweeps, classes).tolist() == [[0, 0, 1], [1, 1, 0]]  # last: none


def test_nan_never_passes_and_the_contact_limit_is_a_share_of_the_probe_points():
    assert not Check('x', math.nan, 1.0).passed
    assert not Check('x', math.nan, 1.0, at_least=True).passed
    summary = {'contacts': 8, 'normal_error_deg_mean': 1.0, 'position_error_mm_mean': 0.2,
               'contact_fraction': 0.95, 'sliding_speed_error': 0.03,
               'cv_accuracy_grouped': 0.8, 'live_accuracy': 0.7, 'time_to_decision_s': 2.0,
               'madgwick_rejected': 0.0}
    results = {c.key: c for c in checks(summary, probe_points=11, textures=12, contact_s=7.6)}
    assert results['contacts'].limit == 9 and not results['contacts'].passed
    assert all(c.passed for key, c in results.items() if key != 'contacts')
    assert results['contacts'].line() == 'contacts 8 (threshold >= 9): FAIL'
    # A sample the Madgwick filter refused (beyond the chip's full scale), or a filter
    # whose diagnostics were never heard (NaN), fails the demo.
    for rejected in (1.0, math.nan):
        refused = {c.key: c for c in checks(dict(summary, madgwick_rejected=rejected), 11,
                                            12, 7.6)}
        assert not refused['madgwick_rejected'].passed


def test_accuracy_must_reach_twice_chance_and_every_sweep_a_decision_within_its_contact():
    summary = {'contacts': 11, 'normal_error_deg_mean': 1.0, 'position_error_mm_mean': 0.2,
               'contact_fraction': 0.95, 'sliding_speed_error': 0.03,
               'cv_accuracy_grouped': 0.2, 'live_accuracy': 0.15, 'time_to_decision_s': 7.0,
               'madgwick_rejected': 0.0}
    twelve = {c.key: c for c in checks(summary, 11, textures=12, contact_s=7.6)}
    assert twelve['cv_accuracy_grouped'].passed and not twelve['live_accuracy'].passed
    assert twelve['live_accuracy'].line() == 'live_accuracy 0.15 (threshold >= 0.167): FAIL'
    assert twelve['time_to_decision_s'].passed
    four = {c.key: c for c in checks(summary, 11, textures=4, contact_s=6.0)}
    assert not four['cv_accuracy_grouped'].passed and not four['time_to_decision_s'].passed


def test_plots_are_written_even_from_empty_input(tmp_path):
    plot_pathway(tmp_path / 'a.png', np.zeros((0, 3)), np.zeros((0, 3)), SURFACE)
    plot_sweeps(tmp_path / 'b.png', [], 0.0, 0.015)
    plot_confusion(tmp_path / 'c.png', np.zeros((2, 3), dtype=int), ['a', 'b'])
    plot_accuracy_against_time(tmp_path / 'd.png', np.array([0.0]), np.array([math.nan]), 0.5)
    assert all((tmp_path / f'{n}.png').stat().st_size > 0 for n in 'abcd')


def test_the_sweep_plot_reads_every_sweep_against_the_position_on_the_path(tmp_path):
    positions = np.array([[0.10, 0.0, 0.01], [0.13, 0.0, 0.05], [0.16, 0.0, 0.01]])
    assert path_length(positions) == pytest.approx(0.1)  # two 50 mm segments
    sweeps = [(f'texture {k}', [(0.1 * i, i / 20, 5 <= i <= 15 + k, 0.015) for i in range(21)])
              for k in range(3)]
    plot_sweeps(tmp_path / 'sweeps.png', sweeps, path_length(positions), 0.015)
    assert (tmp_path / 'sweeps.png').stat().st_size > 0
