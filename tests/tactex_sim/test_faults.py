# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Simulated faults: which topics each silences, and what each does to the tactile samples."""

import math

import numpy as np
import pytest

from tactex_common import chips, topics
from tactex_sim.faults import (
    BURST_STEP_NS,
    CLOCK_JUMP_NS,
    FaultPlayer,
    faulty_sample,
    JITTER_NS,
    muted_topics,
)
from tactex_sim.scene import load_scene, resolve_scene
from tactex_sim.world import World


@pytest.fixture(scope='module')
def sample():
    return World(load_scene(resolve_scene('probe')), seed=0).next_sample()


def test_unplug_silences_the_tactile_topics_and_servo_silence_joint_states():
    assert topics.IMU_RAW in muted_topics('sensor_unplug')
    assert topics.JOINT_STATES not in muted_topics('sensor_unplug')
    assert muted_topics('servo_silence') == {topics.JOINT_STATES}
    assert muted_topics('') == muted_topics('crc_burst') == frozenset()


def test_an_unknown_fault_is_refused_naming_the_known_ones():
    with pytest.raises(ValueError, match="'sensor_unplug'"):
        muted_topics('unplug')


def test_a_crc_burst_makes_every_tactile_value_nan_and_keeps_the_truth(sample):
    bad = faulty_sample('crc_burst', sample)
    assert np.isnan(np.concatenate([bad.accel, bad.gyro, bad.mag])).all()
    assert math.isnan(bad.pressure) and bad.truth is sample.truth
    assert faulty_sample('sensor_unplug', sample) is sample


PERIOD_NS = 8_333_333


def played(player, samples, start_ns=10**12):
    """What the tactile topics carry for each of `samples`, one period apart."""
    return [player.tactile(sample, start_ns + i * PERIOD_NS) for i, sample in enumerate(samples)]


def test_no_fault_lets_each_sample_out_once_with_its_stamp(sample):
    assert played(FaultPlayer(), [sample]) == [[(sample, 10**12)]]


def test_overflow_and_saturated_change_one_channel_beyond_what_float32_or_the_chip_holds(
        sample):
    over = faulty_sample('overflow', sample)
    assert over.accel[0] == 1e300 and np.array_equal(over.accel[1:], sample.accel[1:])
    saturated = faulty_sample('saturated', sample)
    assert saturated.gyro[1] == chips.gyro_range(245).rails_si[1]


def test_clock_jump_and_jitter_move_only_the_stamps(sample):
    player = FaultPlayer()
    player.play('clock_jump')
    assert played(player, [sample]) == [[(sample, 10**12 + CLOCK_JUMP_NS)]]
    player.play('stamp_jitter')
    stamps = [out[0][1] - 10**12 - i * PERIOD_NS
              for i, out in enumerate(played(player, [sample] * 200))]
    assert max(map(abs, stamps)) <= JITTER_NS and len(set(stamps)) > 100


def test_a_burst_withholds_then_sends_every_sample_stamped_as_it_arrives(sample):
    player = FaultPlayer()
    player.play('burst')
    assert played(player, [sample] * 5) == [[]] * 5
    player.play('')
    out = player.tactile(sample, 10**12)
    assert [stamp - 10**12 for _, stamp in out] == [k * BURST_STEP_NS for k in range(6)]


def test_frozen_repeats_the_imu_sample_the_fault_began_with_and_the_barometer_goes_on(sample):
    world = World(load_scene(resolve_scene('probe')), seed=0)
    samples = [world.next_sample() for _ in range(4)]
    player = FaultPlayer()
    player.play('frozen')
    out = [o[0][0] for o in played(player, samples)]
    first = samples[0]
    assert all(np.array_equal(o.gyro, first.gyro)
               and np.array_equal(o.mag, first.mag, equal_nan=True) for o in out)
    assert [o.pressure for o in out] == [s.pressure for s in samples]
    assert out[3].truth is samples[3].truth
