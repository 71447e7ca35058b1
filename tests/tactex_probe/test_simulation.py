# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The explorer closed-loop against the simulator: accuracy, and every hard case."""

import dataclasses
import math

import numpy as np
import pytest

from tactex_probe.closed_loop import Faults, run_probe, score_run, summary
from tactex_probe.explorer_interface import ExplorerConfig, Outcome, Phase
from tactex_probe.motion import pose_of
from tactex_probe.pathway import ContactStatus, ProbeParameters
from tactex_sim.scene import load_scene, parse_scene, resolve_scene

PROBE = load_scene(resolve_scene('probe'))  # the uneven plate, sensor noise and barometer on


def line(start_x, span, step=0.01, **changes):
    values = dict(start=(start_x, 0.0, 0.018), direction=(1.0, 0.0, 0.0), span=span, step=step,
                  approach_height=0.02, descent_speed=0.005, max_descent_depth=0.025,
                  force_limit=3.0)
    values.update(changes)
    return ProbeParameters(**values)


@pytest.mark.slow
def test_pathway_on_the_uneven_plate_is_within_the_accuracy_thresholds():
    run = run_probe(PROBE, line(0.10, 0.10))
    assert run.finished.outcome is Outcome.SUCCEEDED and not run.rejected
    result = summary(score_run(run))
    assert result['contacts'] >= 10
    assert result['normal_mean_deg'] < 3.0
    assert result['position_mean_mm'] < 2.0


@pytest.mark.parametrize('centre_x, feature', [(0.14, 'valley'), (0.20, 'ridge top')])
def test_contact_exactly_in_a_valley_and_on_a_ridge_top(centre_x, feature):
    run = run_probe(PROBE, line(centre_x - 0.01, 0.02))
    errors = {e.index: e for e in score_run(run)}
    assert 1 in errors, f'no contact at the {feature}: {run.pathway.probes}'
    assert errors[1].normal_deg < 3.0 and errors[1].position_mm < 2.0
    assert abs(run.pathway.probes[1].normal[0]) < math.sin(math.radians(3.0))  # level there


def bursts(every_s, length, scale, seed=5):
    rng = np.random.default_rng(seed)

    def perturb(sample):
        if (sample.time_s % every_s) * 120.0 >= length:
            return sample
        sign = rng.choice([-1.0, 1.0])
        return dataclasses.replace(
            sample, accel=sample.accel + sign * scale * rng.normal(0.0, 5.0, 3),
            gyro=sample.gyro + sign * scale * rng.normal(0.0, 3.0, 3),
            pressure=sample.pressure + sign * scale * 300.0)
    return perturb


def test_sensor_noise_bursts_neither_fake_contacts_nor_spoil_the_pathway():
    run = run_probe(PROBE, line(0.17, 0.01), faults=Faults(perturb=bursts(1.3, 4, 1.0)))
    result = summary(score_run(run))
    assert [p.status for p in run.pathway.probes] == [ContactStatus.OK] * 2
    assert result['normal_mean_deg'] < 3.0 and result['position_max_mm'] < 2.0


def test_nan_samples_mid_descent_are_skipped():
    def nan_bursts(sample):
        if (sample.time_s % 0.9) * 120.0 >= 6:
            return sample
        return dataclasses.replace(sample, accel=np.full(3, np.nan), gyro=np.full(3, np.nan),
                                   pressure=math.nan)
    run = run_probe(PROBE, line(0.17, 0.01), faults=Faults(perturb=nan_bursts))
    assert run.finished.outcome is Outcome.SUCCEEDED
    assert [p.status for p in run.pathway.probes] == [ContactStatus.OK] * 2
    assert summary(score_run(run))['normal_mean_deg'] < 3.0


def test_surface_below_the_descent_depth_is_no_contact():
    high = line(0.13, 0.01, start=(0.13, 0.0, 0.045), approach_height=0.015,
                max_descent_depth=0.01)
    run = run_probe(PROBE, high)
    assert [p.status for p in run.pathway.probes] == [ContactStatus.NO_CONTACT] * 2
    assert all('no contact within 10.0 mm' in p.detail for p in run.pathway.probes)
    assert all(p.force_proxy < 0.1 for p in run.pathway.probes)
    assert run.finished.outcome is Outcome.SUCCEEDED


def test_surface_above_the_approach_height_stops_the_sideways_move():
    low = line(0.16, 0.02, start=(0.16, 0.0, -0.005), approach_height=0.012)
    run = run_probe(PROBE, low)
    statuses = [p.status for p in run.pathway.probes]
    assert ContactStatus.UNREACHABLE in statuses
    blocked = [p for p in run.pathway.probes if p.status is ContactStatus.UNREACHABLE]
    assert all('moving sideways' in p.detail for p in blocked)
    assert max(p.force_proxy for p in run.pathway.probes) < low.force_limit
    assert run.finished.outcome is Outcome.SUCCEEDED


def test_servo_dropout_mid_probe_aborts_with_the_reason():
    run = run_probe(PROBE, line(0.15, 0.02), faults=Faults(servo_dropout_s=4.0))
    assert run.finished.outcome is Outcome.ABORTED
    assert 'no joint state' in run.finished.message
    assert run.sim_time_s < 6.0


def test_cancel_during_a_descent_stops_at_the_approach_height():
    parameters = line(0.15, 0.02)
    run = run_probe(PROBE, parameters, faults=Faults(cancel_in_phase=Phase.DESCENDING,
                                                     cancel_delay_s=0.8))
    assert run.finished.outcome is Outcome.CANCELED
    assert run.pathway.probes == ()
    held = run.trace[-1]
    top = parameters.probe_point(0)[2] + parameters.approach_height
    assert held[3] > top - 0.02  # the tip, below the face centre by less than 2 cm
    assert run.feedback[-1].phase is Phase.RETRACTING


def test_steep_slope_gives_a_good_normal_or_says_it_failed():
    steep = parse_scene({
        'name': 'steep', 'seed': 3,
        'effects': ['contact', 'compliance', 'imu_noise', 'barometer'],
        'surface': {'kind': 'flat', 'size_m': [0.10, 0.10], 'origin_m': [0.16, 0.0, 0.0],
                    'thickness_m': 0.01, 'slope_rad': math.radians(60.0)}})
    parameters = line(0.16, 0.0, start=(0.16, 0.0, 0.01), approach_height=0.04,
                      max_descent_depth=0.03)
    config = ExplorerConfig(max_tilt_rad=math.radians(65.0), refinements=6)
    run = run_probe(steep, parameters, config)
    assert run.finished.outcome is Outcome.SUCCEEDED and len(run.pathway.probes) == 1
    assert all(error.normal_deg < 5.0 for error in score_run(run)), run.pathway.probes
    assert all(p.force_proxy < parameters.force_limit for p in run.pathway.probes)


def test_commanded_tool_ends_where_the_explorer_thinks():
    run = run_probe(PROBE, line(0.18, 0.0))
    assert run.finished.outcome is Outcome.SUCCEEDED
    final = pose_of(run.final_joints)
    top = run.pathway.parameters.probe_point(0)[2] + run.pathway.parameters.approach_height
    assert final.point[2] == pytest.approx(top, abs=0.002)


def test_an_arm_that_takes_commands_late_still_follows_every_path():
    # Commands reach the arm late by an amount that varies: the bridge took them only
    # between bursts of 50 samples (0.42 s) and the nodes lag on a loaded machine, so the
    # quick demo measured 0.2 to 1.1 s. Here every other command arrives 0.8 s late. A
    # path modelled from the late-started descent, to hold on touch, began 0.145 rad from
    # where the driver commanded joint4, outside its 0.1 rad start tolerance; it was
    # refused and so was every path after it ("the arm does not follow"). A stop on touch
    # holds where the driver commands the arm, and the next path starts where it stands.
    run = run_probe(PROBE, line(0.15, 0.0, descent_speed=0.02),
                    faults=Faults(command_delays_s=(0.8, 0.0)))
    assert run.rejected == ()
    assert run.finished.outcome is Outcome.SUCCEEDED, run.finished.message
    assert len(run.pathway.probes) == 1
