# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The sweep's watch: contact from pressure, aborts, the result, latency-proof timing."""

import math

from conftest import FLANK_NORMALS, FLANK_POINTS, FLANK_REST, SAG_STEP, START_JOINTS, wave_pathway
import numpy as np
import pytest

from tactex_description.mjcf import EDGE_TIP_RADIUS_M
from tactex_trajectory.monitor import MonitorSettings, SweepMonitor
from tactex_trajectory.planner import plan_sweep
from tactex_trajectory.poses import ARM

BASELINE_PA = 101_325.0
RATE_HZ = 120.0


@pytest.fixture(scope='module')
def sweep():
    return plan_sweep(*wave_pathway(), None, START_JOINTS)


def stream(sweep, *, latency_s=0.3, pressure=None, joints_offset=0.0, step=0.0):
    """(time since sending, joints, pressure) of an arm following the plan late.

    `step` is added to the joints from the trajectory's arrival (after `latency_s`) on.
    """
    curve = sweep.trajectory.interpolant()
    path = sweep.path
    for time_s in np.arange(0.0, sweep.trajectory.duration_s + latency_s + 0.5, 1 / RATE_HZ):
        t = min(max(time_s - latency_s, 0.0), sweep.trajectory.duration_s)
        joints = curve(t) + joints_offset + (step if time_s >= latency_s else 0.0)
        edge = ARM.tool_pose(joints)[0]
        travel = path.travel_of(edge)[0]
        point, normal = (np.array([np.interp(travel, path.arclength_m, v[:, k])
                                   for k in range(3)]) for v in (path.points, path.normals))
        depth = EDGE_TIP_RADIUS_M - float((edge - point) @ (normal / np.linalg.norm(normal)))
        value = BASELINE_PA + 1.35e6 * max(0.0, depth)
        if pressure is not None:
            value = pressure(t, value)
        yield time_s, joints, value


def watch(sweep, samples):
    monitor = SweepMonitor(sweep)
    status = None
    for time_s, joints, pressure in samples:
        monitor.update_joints(time_s, joints)
        status = monitor.update_pressure(time_s, pressure)
        if status.abort_reason:
            break
    return monitor, status


def test_a_good_sweep_is_in_contact_over_its_segment_at_the_speed_and_depth(sweep):
    monitor, status = watch(sweep, stream(sweep, latency_s=0.7))
    assert status.abort_reason == ''
    assert monitor.baseline_pa == pytest.approx(BASELINE_PA)
    result = monitor.result()
    assert result.contact_fraction == 1.0
    assert result.speed_mean_m_s == pytest.approx(0.015, rel=0.01)
    assert result.speed_std_m_s < 0.0005
    assert result.press_depth_error_m < 1e-4
    (start, end), = result.active_spans_s
    # Late by the latency, as the arm was: the monitor's clock starts when the arm moves.
    assert start == pytest.approx(sweep.contact_start_s + 0.7, abs=0.05)
    assert end == pytest.approx(sweep.contact_end_s + 0.7, abs=0.05)


def test_latency_is_not_taken_for_a_tracking_error(sweep):
    monitor, status = watch(sweep, stream(sweep, latency_s=2.0))
    assert status.abort_reason == '' and monitor.started
    assert status.tracking_error_m < 1e-3


def test_contact_lost_beyond_the_tolerance_aborts(sweep):
    middle = 0.5 * (sweep.contact_start_s + sweep.contact_end_s)

    def lifted(t, value):
        return BASELINE_PA if middle < t < middle + 1.0 else value

    _, status = watch(sweep, stream(sweep, pressure=lifted))
    assert status.abort_reason.startswith('contact lost for 0.5')
    assert 'mm along the path (tolerance 0.5 s)' in status.abort_reason


def test_a_short_loss_of_contact_is_tolerated_and_counted(sweep):
    middle = 0.5 * (sweep.contact_start_s + sweep.contact_end_s)

    def lifted(t, value):
        return BASELINE_PA if middle < t < middle + 0.3 else value

    monitor, status = watch(sweep, stream(sweep, pressure=lifted))
    assert status.abort_reason == ''
    result = monitor.result()
    assert 0.9 < result.contact_fraction < 0.99
    assert len(result.active_spans_s) == 2


def test_over_force_aborts(sweep):
    def pressed(t, value):
        return value + 20_000.0 if t > sweep.contact_start_s + 1.0 else value

    _, status = watch(sweep, stream(sweep, pressure=pressed))
    assert status.abort_reason.startswith('force ') and 'over the limit 3 N' in \
        status.abort_reason


def test_the_servo_sag_step_as_the_trajectory_arrives_is_not_taken_for_the_departure():
    """The step is not the arm leaving its start: the clock starts with the plan's motion.

    Counted as the departure, it started the clock 0.37 s early, and the lift (30 mm/s)
    read as 6.5 mm from its command here, with the servo lag and the edge's drag on the
    surface over 10 mm in the simulator: 'the edge is 10.1 mm from where it is commanded
    ... (lift; tolerance 10 mm)' (test_sweep_simulation).
    """
    sweep = plan_sweep(FLANK_POINTS, FLANK_NORMALS, None, FLANK_REST)
    monitor = SweepMonitor(sweep)
    worst = 0.0
    for time_s, joints, pressure in stream(sweep, latency_s=0.3, step=SAG_STEP):
        worst = max(worst, monitor.update_joints(time_s, joints).tracking_error_m)
        status = monitor.update_pressure(time_s, pressure)
        assert status.abort_reason == ''
    assert monitor.started
    # The step itself (0.9 mm) and what its share along the plan's first motion shifts
    # the clock (0.07 s), no more: 3.0 mm at most, against 6.5 mm before.
    assert worst < 4e-3
    assert monitor.result().contact_fraction == 1.0


def test_the_edge_far_from_its_command_aborts(sweep):
    _, status = watch(sweep, stream(sweep, joints_offset=np.array([0.1, 0.0, 0.0, 0.0])))
    assert 'mm from where it is commanded' in status.abort_reason


def test_non_finite_samples_are_ignored(sweep):
    def broken(t, value):
        return math.nan if int(t * RATE_HZ) % 7 == 0 else value

    samples = ((t, q if int(t * RATE_HZ) % 11 else q * math.nan, p)
               for t, q, p in stream(sweep, pressure=broken))
    monitor, status = watch(sweep, samples)
    assert status.abort_reason == ''
    assert monitor.result().contact_fraction == 1.0


@pytest.mark.parametrize('name', ['contact_threshold_pa', 'force_limit_n',
                                  'tracking_tolerance_m'])
def test_thresholds_must_be_positive(name):
    with pytest.raises(ValueError, match=name):
        MonitorSettings(**{name: 0.0})
