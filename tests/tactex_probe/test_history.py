# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The sample history: late samples slotted in, repeats dropped, windows joined by stamp."""

import math

import numpy as np
import pytest

from tactex_probe.history import SampleHistory

UP_DOWN = (0.0, 1.0, 0.0, 0.0)  # sensor facing down


def test_late_samples_are_slotted_in_and_repeats_dropped():
    history = SampleHistory()
    for stamp in (0, 20, 10, 30):
        assert history.add_pressure(stamp, 100.0 + stamp)
    assert not history.add_pressure(20, 1.0)
    assert history.pressures(0, 30).tolist() == [100.0, 110.0, 120.0, 130.0]
    assert history.dropped == 1


def test_non_finite_samples_are_counted_not_kept():
    history = SampleHistory()
    assert not history.add_pressure(0, math.nan)
    assert not history.add_imu(0, (math.nan, 0.0, 9.8), UP_DOWN)
    assert not history.add_joints(0, (0.0, math.inf, 0.0, 0.0))
    assert history.dropped == 3 and history.window(0, 10) is None


@pytest.mark.parametrize('attitude', [(0.0, 0.0, 0.0, 0.0), (2.0, 0.0, 0.0, 0.0),
                                      (0.5, 0.5, 0.0, 0.0)])
def test_an_attitude_that_is_no_unit_quaternion_is_counted_not_kept(attitude):
    # REP-145's all-zero orientation means none: averaged, it gave a 180 degree yaw
    history = SampleHistory()
    assert not history.add_imu(0, (0.0, 0.0, 9.8), attitude)
    assert history.dropped == 1 and history.window(0, 10) is None
    assert history.add_imu(0, (0.0, 0.0, 9.8), UP_DOWN)


def test_old_samples_are_forgotten():
    history = SampleHistory(keep_s=1.0)
    for i in range(300):
        history.add_pressure(i * 10_000_000, float(i))
    assert history.pressures(0, 10**10).size <= 200
    assert history.pressures(2_980_000_000, 2_990_000_000).tolist() == [298.0, 299.0]


def test_window_joins_the_streams_by_stamp():
    history = SampleHistory()
    history.add_joints(0, (0.0, 0.0, 0.0, 0.0))
    history.add_joints(100, (1.0, 2.0, 3.0, 4.0))
    history.add_imu(25, (0.0, 0.0, -9.8), UP_DOWN)
    history.add_imu(75, (0.0, 0.0, -9.8), UP_DOWN)
    history.add_imu(80, (50.0, 0.0, -9.8), UP_DOWN)  # a wild one: the median ignores it
    window = history.window(20, 80)
    assert window.joints == pytest.approx([0.6, 1.2, 1.8, 2.4])
    assert window.accel == pytest.approx([0.0, 0.0, -9.8])
    assert np.abs(window.quaternion) == pytest.approx(UP_DOWN)


def test_caught_up_waits_for_both_sensors():
    history = SampleHistory()
    history.add_imu(100, (0.0, 0.0, -9.8), UP_DOWN)
    assert not history.caught_up(100)
    history.add_pressure(120, 101325.0)
    assert history.caught_up(100) and not history.caught_up(110)
