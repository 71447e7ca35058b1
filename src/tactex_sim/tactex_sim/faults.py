# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Faults the simulator can play while running, for soak tests: what each does to a sample.

The system's faults: `sensor_unplug` silences the tactile topics (a USB cable pulled),
`crc_burst` replaces every tactile value with NaN (frames the decoder could not trust),
`servo_silence` silences joint_states (the servo bus stops answering).

The live stream's faults, played on the tactile topics only: `overflow` puts 1e300 on
ax (beyond float32), `clock_jump` stamps the samples 30 s back (a sensor clock set back;
clearing it jumps forward again), `burst` withholds the samples and, when cleared, sends
them all at once stamped 0.1 ms apart (a driver stamping a buffered burst on arrival),
`stamp_jitter` moves each stamp up to 10 ms either way, `frozen` repeats the LSM9DS0's
sample the fault began with (accelerometer, gyro and magnetometer: a chip that stopped
converting; the barometer, another chip, goes on), `saturated` holds the gyro's y axis at
the rail of its finest range. '' is no fault.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from tactex_common import chips, topics
from tactex_sensor.messages import TACTILE_TOPICS
from tactex_sim.world import Sample

FAULTS = ('', 'sensor_unplug', 'crc_burst', 'servo_silence', 'overflow', 'clock_jump',
          'burst', 'stamp_jitter', 'frozen', 'saturated')
_MUTED = {'sensor_unplug': frozenset(topic for topic, _ in TACTILE_TOPICS),
          'servo_silence': frozenset({topics.JOINT_STATES})}
OVERFLOW = 1e300
CLOCK_JUMP_NS = -30 * 10**9
BURST_STEP_NS = 100_000
JITTER_NS = 10_000_000


def muted_topics(fault: str) -> frozenset[str]:
    """The topics `fault` silences.

    Raises:
        ValueError: an unknown fault, naming the known ones.
    """
    if fault not in FAULTS:
        raise ValueError(f'fault must be one of {", ".join(map(repr, FAULTS))}, got {fault!r}')
    return _MUTED.get(fault, frozenset())


def faulty_sample(fault: str, sample: Sample) -> Sample:
    """`sample` as the tactile topics carry it under `fault` (the stateless faults)."""
    if fault == 'crc_burst':
        nan3 = np.full(3, np.nan)
        return replace(sample, accel=nan3, gyro=nan3, mag=nan3, pressure=float('nan'),
                       temperature=float('nan'))
    if fault == 'overflow':
        return replace(sample, accel=np.array([OVERFLOW, *sample.accel[1:]]))
    if fault == 'saturated':
        rail = chips.gyro_range(min(chips.GYRO_RANGES)).rails_si[1]
        return replace(sample, gyro=np.array([sample.gyro[0], rail, sample.gyro[2]]))
    return sample


class FaultPlayer:
    """The fault being played, and the tactile samples (with their stamps) it lets out.

    Args:
        seed: of the stamp jitter.
    """

    def __init__(self, seed: int = 0) -> None:
        self.fault = ''
        self.muted: frozenset[str] = frozenset()
        self._rng = np.random.default_rng(seed)
        self._held: list[Sample] = []  # withheld by `burst`
        self._frozen: Sample | None = None

    def play(self, fault: str) -> None:
        """Play `fault` from the next sample on ('' stops it).

        Raises:
            ValueError: an unknown fault, naming the known ones.
        """
        self.muted = muted_topics(fault)
        self.fault, self._frozen = fault, None

    def tactile(self, sample: Sample, time_ns: int) -> list[tuple[Sample, int]]:
        """What the tactile topics carry for the sample stamped `time_ns`: (sample, stamp)s."""
        if self.fault == 'burst':
            self._held.append(sample)
            return []
        out = [(held, time_ns + k * BURST_STEP_NS) for k, held in enumerate(self._held)]
        self._held = []
        stamp = time_ns + len(out) * BURST_STEP_NS
        if self.fault == 'clock_jump':
            stamp += CLOCK_JUMP_NS
        elif self.fault == 'stamp_jitter':
            stamp += int(self._rng.integers(-JITTER_NS, JITTER_NS + 1))
        if self.fault == 'frozen':
            self._frozen = self._frozen or sample
            frozen = self._frozen
            sample = replace(sample, accel=frozen.accel, gyro=frozen.gyro, mag=frozen.mag)
        return out + [(faulty_sample(self.fault, sample), stamp)]
