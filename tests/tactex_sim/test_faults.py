# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Simulated faults: which topics each silences, and the NaN samples of a CRC burst."""

import math

import numpy as np
import pytest

from tactex_common import topics
from tactex_sim.faults import faulty_sample, muted_topics
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
