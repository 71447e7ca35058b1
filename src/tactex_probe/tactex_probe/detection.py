# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Contact detection from the barometer and accelerometer stream.

Pressing the compliant body compresses the air cast inside it, so the barometer is the
contact channel: a baseline (median and robust spread) is learnt in free air before each
approach, and contact is declared when the median of the last three valid readings stays
above the baseline by `max(min_rise_pa, sigmas * spread)` for `debounce` consecutive
samples; it ends when it stays below `release_fraction` of that rise for as many
samples (hysteresis). The median drops single spikes and most of a burst whose signs
flip; an acceleration bump cannot trigger it, and a NaN neither counts nor resets a run.
Where the barometer gives no valid samples at all (a missing chip sends NaN), the
accelerometer stands in: a persistent turn of the measured gravity direction away from
its free-air baseline (the body bending on contact) over `accel_debounce` samples, which
a short bump does not sustain. Such a contact carries a lower confidence.

The contact instant is not the detection instant: the pressure ramps up linearly while the
arm presses on, so the instant is the ramp (fitted over the samples above threshold)
extrapolated back to the baseline, which takes out the debounce latency.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
import enum
import math
import sys

import numpy as np

from tactex_common import chips
from tactex_description.geometry import OPEN_MANIPULATOR_X
from tactex_sensor.orientation import unit_direction

# Pressure per newton of contact force: the barometer model's 1.5e6 Pa per metre of
# compression over the body's press stiffness (calibrate a real module by pressing it
# on a scale).
DEFAULT_PA_PER_NEWTON = 1.5e6 / OPEN_MANIPULATOR_X.joint('sensor_press').stiffness
# The onset is never put further back than this before the sample that confirmed contact.
MAX_ONSET_BACKTRACK_S = 0.5
# Latest samples kept for the onset's fit (0.5 s at up to 1 kHz), and the largest rise
# the fit takes at its value (a wilder one counts as this much).
ONSET_SAMPLES = 512
MAX_FITTED_RISE_PA = 1e9
# Contact is judged on the median of this many of the latest valid pressure readings.
MEDIAN_OF = 3


@dataclass(frozen=True)
class DetectorConfig:
    """Tuning of the contact detector.

    Attributes:
        baseline_samples: valid free-air samples needed before detection is armed.
        sigmas: contact threshold in baseline standard deviations of the pressure.
        min_rise_pa: smallest contact threshold (Pa), whatever the spread.
        resolution_pa: the barometer's step (Pa): no spread is taken as finer. A quantised
            reading that mostly repeats one code has a median absolute deviation of 0,
            which would put the threshold within a code of the noise. Default: the
            MPL115A2's 10-bit code (`chips.PRESSURE_LSB_PA`, 63.5 Pa), as the real module
            and the simulated one (scenes declaring `sensor`) report; 0 for an ideal
            barometer.
        release_fraction: contact ends below this fraction of the threshold.
        debounce: consecutive samples beyond a threshold to change state.
        pa_per_newton: barometer rise per newton of contact force (force proxy).
        accel_threshold_rad: accelerometer fallback: gravity direction turn for contact.
        accel_debounce: accelerometer fallback: consecutive samples beyond it.
    """

    baseline_samples: int = 12
    sigmas: float = 8.0
    min_rise_pa: float = 25.0
    resolution_pa: float = chips.PRESSURE_LSB_PA
    release_fraction: float = 0.5
    debounce: int = 3
    pa_per_newton: float = DEFAULT_PA_PER_NEWTON
    accel_threshold_rad: float = math.radians(1.5)
    accel_debounce: int = 12

    def __post_init__(self) -> None:
        """Reject settings the detector cannot use."""
        for name in ('baseline_samples', 'debounce', 'accel_debounce'):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                raise ValueError(f'{name} must be an integer >= 1, got {value!r}')
        if not (math.isfinite(self.resolution_pa) and self.resolution_pa >= 0):
            raise ValueError(f'resolution_pa must be finite and >= 0, got '
                             f'{self.resolution_pa!r}')
        for name in ('sigmas', 'min_rise_pa', 'pa_per_newton', 'accel_threshold_rad'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f'{name} must be finite and > 0, got {value!r}')
        if not 0.0 < self.release_fraction < 1.0:
            raise ValueError(f'release_fraction must be in (0, 1), got '
                             f'{self.release_fraction!r}')


class Channel(enum.Enum):
    """Which sensor declared a contact."""

    PRESSURE = 'pressure'
    ACCEL = 'accel'


@dataclass(frozen=True)
class ContactEvent:
    """A detected contact.

    Attributes:
        onset_ns: estimated instant of first touch (ns).
        detected_ns: stamp of the sample that confirmed it (ns).
        channel: the sensor that saw it.
        snr: rise over the baseline spread at detection (signal-to-noise ratio).
    """

    onset_ns: int
    detected_ns: int
    channel: Channel
    snr: float


class ContactDetector:
    """Streaming detector: `learn` free-air samples, then `update` through the approach."""

    def __init__(self, config: DetectorConfig = DetectorConfig()) -> None:
        self.config = config
        self.reset()

    def reset(self) -> None:
        """Forget the baseline (call before each approach) and leave contact."""
        self._pressures: list[float] = []
        self._accels: list[np.ndarray] = []
        self.baseline_pa = math.nan
        self.spread_pa = math.nan
        self._gravity: np.ndarray | None = None
        self.in_contact = False
        self._recent: deque[float] = deque(maxlen=MEDIAN_OF)
        self._run: deque[tuple[int, float]] = deque()
        # (stamp, rise) of the latest samples: the onset is fitted through them.
        self._approach: deque[tuple[int, float]] = deque(maxlen=ONSET_SAMPLES)
        self._accel_run = 0
        self._accel_start = 0
        self._release_run = 0
        self._armed = False

    # -- baseline ---------------------------------------------------------------------
    def learn(self, pressure_pa: float, accel=None) -> None:
        """Add one free-air sample to the baseline (NaN values are ignored)."""
        if math.isfinite(pressure_pa):
            self._pressures.append(float(pressure_pa))
        direction = _direction(accel)
        if direction is not None:
            self._accels.append(direction)
        self._refresh_baseline()

    def _refresh_baseline(self) -> None:
        if self._pressures:
            values = np.asarray(self._pressures)
            self.baseline_pa = middle(values)
            # Robust spread: 1.4826 * median absolute deviation (a burst cannot inflate it),
            # never finer than the barometer resolves.
            with np.errstate(over='ignore'):  # a wild sample's deviation may be inf
                deviations = np.abs(values - self.baseline_pa)
            self.spread_pa = max(1.4826 * middle(deviations), self.config.resolution_pa)
        if self._accels:
            # Per-axis median of the directions: a few wild readings cannot turn it.
            median = np.median(self._accels, axis=0)
            length = float(np.linalg.norm(median))
            self._gravity = median / length if length > 0 else None
        self._armed = (len(self._pressures) >= self.config.baseline_samples
                       or (not self._pressures
                           and len(self._accels) >= self.config.baseline_samples))

    @property
    def armed(self) -> bool:
        """True once enough free-air samples were learnt."""
        return self._armed

    @property
    def uses_pressure(self) -> bool:
        """True when the barometer gave a baseline (else the accelerometer stands in)."""
        return bool(self._pressures)

    @property
    def threshold_pa(self) -> float:
        """Pressure rise above the baseline that counts as contact (Pa)."""
        return max(self.config.min_rise_pa, self.config.sigmas * self.spread_pa)

    def force_proxy(self, pressure_pa: float) -> float:
        """Contact force proxy (N) of a pressure reading; NaN without a baseline."""
        return (pressure_pa - self.baseline_pa) / self.config.pa_per_newton

    # -- detection --------------------------------------------------------------------
    def update(self, stamp_ns: int, pressure_pa: float, accel=None) -> ContactEvent | None:
        """Feed one sample; return the contact event when this sample confirms one.

        Before the baseline is learnt nothing is detected. NaN readings are skipped.
        """
        if not self._armed:
            return None
        if self.uses_pressure:
            return self._update_pressure(int(stamp_ns), float(pressure_pa))
        return self._update_accel(int(stamp_ns), accel)

    def _update_pressure(self, stamp_ns: int, pressure_pa: float) -> ContactEvent | None:
        if not math.isfinite(pressure_pa):
            return None
        self._recent.append(pressure_pa)
        self._approach.append((stamp_ns, pressure_pa - self.baseline_pa))
        rise = middle(self._recent) - self.baseline_pa
        config = self.config
        if self.in_contact:
            below = rise < config.release_fraction * self.threshold_pa
            self._release_run = self._release_run + 1 if below else 0
            if self._release_run >= config.debounce:
                self.in_contact = False
                self._release_run = 0
                self._run.clear()
                self._approach.clear()
            return None
        if rise < self.threshold_pa:
            self._run.clear()
            return None
        self._run.append((stamp_ns, pressure_pa - self.baseline_pa))
        if len(self._run) < config.debounce:
            return None
        self.in_contact = True
        spread = max(self.spread_pa, 1e-9)
        return ContactEvent(self._onset(), stamp_ns, Channel.PRESSURE, rise / spread)

    def _onset(self) -> int:
        """The instant the rise began: a hinge fitted through the approach's latest samples.

        Flat (no rise) before the onset, a straight rise after it; the onset is the sample
        of the last `MAX_ONSET_BACKTRACK_S` whose hinge leaves the least absolute error,
        each hinge's slope the median of the rises over the time since it (a wild sample
        moves neither much). Fitted through every sample of the rise, not only the few
        above the threshold: a barometer with a whole 10-bit code of noise (63.5 Pa) rises
        about one code per sample at 5 mm/s, so a line through three samples could put
        the onset anywhere.
        """
        stamps = np.array([s for s, _ in self._approach], dtype=np.int64)
        rises = np.clip([r for _, r in self._approach], -MAX_FITTED_RISE_PA, MAX_FITTED_RISE_PA)
        keep = stamps >= stamps[-1] - int(MAX_ONSET_BACKTRACK_S * 1e9)
        stamps, rises = stamps[keep], rises[keep]
        t = (stamps - stamps[-1]) * 1e-9
        best_error, onset = math.inf, int(self._run[0][0])
        for hinge in range(t.size):
            after = t > t[hinge]
            if np.count_nonzero(after) < 2:
                continue
            lever = t[after] - t[hinge]
            slope = max(float(np.median(rises[after] / lever)), 0.0)
            error = float(np.abs(rises[~after]).sum() + np.abs(rises[after] - slope * lever).sum())
            if error < best_error:
                best_error, onset = error, int(stamps[hinge])
        return onset

    def _update_accel(self, stamp_ns: int, accel) -> ContactEvent | None:
        direction = _direction(accel)
        if direction is None or self._gravity is None:
            return None
        turn = math.acos(min(1.0, max(-1.0, float(np.dot(direction, self._gravity)))))
        beyond = turn > self.config.accel_threshold_rad
        if self.in_contact:
            self._release_run = 0 if beyond else self._release_run + 1
            if self._release_run >= self.config.accel_debounce:
                self.in_contact = False
                self._release_run = 0
            return None
        if not beyond:
            self._accel_run = 0
            return None
        self._accel_run += 1
        if self._accel_run == 1:
            self._accel_start = stamp_ns
        if self._accel_run < self.config.accel_debounce:
            return None
        self.in_contact = True
        self._accel_run = 0
        return ContactEvent(self._accel_start, stamp_ns, Channel.ACCEL,
                            turn / self.config.accel_threshold_rad)


def _direction(accel) -> np.ndarray | None:
    """Unit direction of an accel reading (any finite size); None if absent, zero or not finite."""
    if accel is None:
        return None
    valid, *direction = unit_direction(*(float(a) for a in accel), sys.float_info.max)
    return np.array(direction) if valid else None


def middle(values) -> float:
    """The median, its two middle values halved before they are added (no overflow)."""
    ordered = sorted(values)
    half = len(ordered) // 2
    return float(ordered[half]) if len(ordered) % 2 else ordered[half - 1] / 2 + ordered[half] / 2
