# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What goes wrong with a live stream, judged without ROS: clock jumps, an off rate, bad windows.

- `Timeline`: the leading stream's header stamps (the IMU's, which the others are joined
  onto) either continue, jump once (a single stamp far from the others: held back and
  dropped) or restart (`CONFIRM_SAMPLES` consecutive stamps agree on a new timeline: the
  simulator restarted, a clock was set). The other streams' stamps are kept only near
  the leader's, so a few late samples of an old timeline cannot switch it back.
- `RateJudge`: whether the stream runs at the model's rate. The recording's stated
  rate judges until enough stamps are measured; from then on the measured rate does,
  over a sliding span, with hysteresis: off beyond the tolerance, back within half of it.
- `window_fault`: a window no decision may come from: frozen (the motion channels repeat
  one sample) or saturated (a channel held at a chip's rail for half the window).
- `stated_metadata`: recording/metadata as the live classifier reads it (the stated rate).
"""

from __future__ import annotations

from collections.abc import Sequence
import json
import math

import numpy as np

from tactex_classify.models.checkpoint import StreamSpec
from tactex_common import chips
from tactex_common.channels import ACCEL, BARO, GYRO, MAG
from tactex_common.constants import FLOAT32_MAX
from tactex_common.numbers import is_finite_number

CONFIRM_SAMPLES = 3  # consecutive stamps on a new timeline that make it the stream's
SATURATED_FRACTION = 0.5  # of a window's samples at a rail
CONTINUES, HELD, RESTARTED = 'continues', 'held', 'restarted'


def _smallest_rail(ranges: dict) -> float:
    """The lowest positive rail of a chip's ranges, less one count of that range."""
    finest = min(ranges.values(), key=lambda r: r.lsb_si)
    return finest.rails_si[1] - finest.lsb_si


# A value at or beyond the rail of the chip's finest range is at a rail of some range.
_RAILS = {**dict.fromkeys(ACCEL, (-_smallest_rail(chips.ACCEL_RANGES),
                                  _smallest_rail(chips.ACCEL_RANGES))),
          **dict.fromkeys(GYRO, (-_smallest_rail(chips.GYRO_RANGES),
                                 _smallest_rail(chips.GYRO_RANGES))),
          **dict.fromkeys(MAG, (-_smallest_rail(chips.MAG_RANGES),
                                _smallest_rail(chips.MAG_RANGES))),
          BARO[0]: (chips.PRESSURE_MIN_PA + chips.PRESSURE_LSB_PA,
                    chips.PRESSURE_MAX_PA - chips.PRESSURE_LSB_PA)}


def fits_float32(values: Sequence[float]) -> bool:
    """Every value finite and within float32's range (the models' input type)."""
    # A plain loop: a handful of values per sample, on the live path; abs(NaN) <= x is False.
    for value in values:
        if not abs(float(value)) <= FLOAT32_MAX:
            return False
    return True


class Timeline:
    """Whether each stamp continues the streams' timeline (see the module docstring).

    Args:
        jump_ns: a stamp further than this from the leader's newest is off the timeline.
    """

    def __init__(self, jump_ns: int) -> None:
        self.jump_ns = int(jump_ns)
        self.latest_ns: int | None = None
        self._candidate_ns: int | None = None  # newest stamp of a possible new timeline
        self._candidate_count = 0

    def near(self, stamp_ns: int) -> bool:
        """Whether a following stream's stamp lies on the timeline (any, before the first)."""
        return self.latest_ns is None or abs(int(stamp_ns) - self.latest_ns) <= self.jump_ns

    def judge(self, stamp_ns: int) -> str:
        """Judge a leader's stamp: CONTINUES, HELD (drop it) or RESTARTED (a new timeline)."""
        stamp_ns = int(stamp_ns)
        if self.near(stamp_ns):
            self.latest_ns = stamp_ns if self.latest_ns is None else max(self.latest_ns,
                                                                          stamp_ns)
            self._candidate_ns, self._candidate_count = None, 0
            return CONTINUES
        if self._candidate_ns is not None and 0 < stamp_ns - self._candidate_ns <= self.jump_ns:
            self._candidate_count += 1
        else:
            self._candidate_count = 1
        self._candidate_ns = stamp_ns
        if self._candidate_count < CONFIRM_SAMPLES:
            return HELD
        self.latest_ns, self._candidate_ns, self._candidate_count = stamp_ns, None, 0
        return RESTARTED


def stated_metadata(text: str) -> dict:
    """A recording/metadata message's JSON object ({} for anything else: the stream goes on)."""
    try:
        stated = json.loads(text)
    except ValueError:
        return {}
    return stated if isinstance(stated, dict) else {}


class RateJudge:
    """Whether the stream runs at the model's rate (see the module docstring).

    Args:
        stream: the checkpoint's stream (its rate).
        tolerance: relative difference accepted.
    """

    def __init__(self, stream: StreamSpec, tolerance: float) -> None:
        self.stream, self.tolerance = stream, tolerance
        self._stated = ''  # refusal from the recording's stated rate
        self._measured: str | None = None  # refusal from the stamps (None: not measured)

    def stated(self, rate) -> str:
        """Take a recording's stated rate (metadata `sensor_rate_hz`); '' or why it is no rate."""
        if not (is_finite_number(rate) and rate > 0):
            return (f'sensor_rate_hz {rate!r} is not a rate (a finite number of Hz > 0); '
                    'judging the stream by its stamps')
        lines = self.stream.mismatches(sampling_rate_hz=float(rate),
                                       rate_tolerance=self.tolerance)
        self._stated = f'{lines[0]} (recording/metadata)' if lines else ''
        return ''

    def measured(self, rate_hz: float | None) -> None:
        """The rate measured from the stamps (None: too few yet)."""
        if rate_hz is None:
            return
        allowed = self.tolerance if not self._measured else self.tolerance / 2
        lines = self.stream.mismatches(sampling_rate_hz=rate_hz, rate_tolerance=allowed)
        self._measured = f'{lines[0]} (median step of the header stamps)' if lines else ''

    def forget(self) -> None:
        """Start measuring again (the timeline restarted)."""
        self._measured = None

    @property
    def refusal(self) -> str:
        """Why the stream is not classified now ('' when it fits)."""
        return self._stated if self._measured is None else self._measured


def window_fault(values: np.ndarray, channels: Sequence[str]) -> str:
    """'' for a window a decision may come from, else what is wrong with it.

    Args:
        values: (window, channels) samples in SI units.
        channels: their names.

    Returns:
        'frozen' when the IMU's channels (accelerometer and gyro; without them, the
        magnetometer's) each hold one value over the window: a live chip always shows
        noise. A window of only the barometer is never called frozen. Else 'saturated
        NAME' for the first channel held at a rail in SATURATED_FRACTION of its samples.
    """
    for group in (ACCEL + GYRO, MAG):
        columns = [i for i, name in enumerate(channels) if name in group]
        if columns:
            with np.errstate(invalid='ignore', over='ignore'):  # inf - inf: not frozen
                spread = np.ptp(values[:, columns], axis=0)
            if np.all(spread == 0):
                return 'frozen'
            break
    for i, name in enumerate(channels):
        low, high = _RAILS.get(name, (-math.inf, math.inf))
        column = values[:, i]
        for extreme, beyond in ((column.max(), column.max() >= high),
                                (column.min(), column.min() <= low)):
            if beyond and np.mean(column == extreme) >= SATURATED_FRACTION:
                return f'saturated {name}'
    return ''
