# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Faults the simulator can play while running, for soak tests: what each does to a sample.

`sensor_unplug` silences the tactile topics (a USB cable pulled), `crc_burst` replaces
every tactile value with NaN (frames the decoder could not trust), `servo_silence`
silences joint_states (the servo bus stops answering). '' is no fault.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from tactex_common import topics
from tactex_sensor.messages import TACTILE_TOPICS
from tactex_sim.world import Sample

FAULTS = ('', 'sensor_unplug', 'crc_burst', 'servo_silence')
_MUTED = {'sensor_unplug': frozenset(topic for topic, _ in TACTILE_TOPICS),
          'servo_silence': frozenset({topics.JOINT_STATES})}


def muted_topics(fault: str) -> frozenset[str]:
    """The topics `fault` silences.

    Raises:
        ValueError: an unknown fault, naming the known ones.
    """
    if fault not in FAULTS:
        raise ValueError(f'fault must be one of {", ".join(map(repr, FAULTS))}, got {fault!r}')
    return _MUTED.get(fault, frozenset())


def faulty_sample(fault: str, sample: Sample) -> Sample:
    """`sample` as the tactile topics carry it under `fault` (NaN values for crc_burst)."""
    if fault != 'crc_burst':
        return sample
    nan3 = np.full(3, np.nan)
    return replace(sample, accel=nan3, gyro=nan3, mag=nan3, pressure=float('nan'),
                   temperature=float('nan'))
