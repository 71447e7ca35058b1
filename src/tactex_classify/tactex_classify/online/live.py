# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The online classifier's core: tactile samples in, windows and texture estimates out.

No ROS and no clock: the caller passes every sample with its header stamp and its
arrival time. `LiveWindows` keeps a ring buffer per stream (IMU, magnetometer,
pressure) and cuts windows exactly as the converter does (`tactex_classify.data.dataset`):
streams joined on the IMU stamps by `alignment.align`, runs of kept samples split at
gaps (`tactex_common.stamps.gaps`), a window every hop from each run's start. A sample
is final once every stream has reached its stamp (minus `reorder_s`); a stream silent
while the IMU delivered `max_lag_s` worth of samples is not waited for (its missing
samples drop the IMU samples as unaligned, as the converter drops them). A sample
arriving after later ones were final is late: dropped and counted.

Faults are survived, never latched (`stream_health`): a sample that does not fit float32
is dropped and counted; a stamp far off its stream's timeline is held back and dropped,
and when a few consecutive stamps agree on a new timeline (the simulator restarted, a
clock was set) every buffer is dropped, counted as a resync, and the evidence restarts.

Kept samples are those in contact: inside `sweep/active` (the converter's segment rule,
on the receive stamps of its messages, as the recorder logs them), or, by the pressure
rule, pressure `contact_pa` above a baseline that follows the barometer while out of
contact (hysteresis: released below half of that). `auto` uses sweep/active once it has
been seen, the pressure rule before. Leaving contact resets the evidence.

`OnlineClassifier` adds the model and `evidence.Evidence`: each window's probabilities,
skipping (and counting) all but the newest windows when they queue up. It classifies no
window while the stream's rate is off the model's, and none that is frozen or saturated;
a window whose model call raises is skipped; each is counted in `faults`.

Longer than 500 lines: the ring buffers, the contact rules and the window cutting are
one pass over each sample that must cut exactly the converter's windows; the evidence
and the stream-health rules live in `evidence` and `stream_health`.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
import math

import numpy as np

from tactex_classify.data.bags import inside, ROLE_CHANNELS, segments
from tactex_classify.data.dataset import FilterRule
from tactex_classify.data.stream_alignment import align, Stream
from tactex_classify.models.checkpoint import StreamSpec
from tactex_classify.online.evidence import Estimate, Evidence, EvidenceSettings
from tactex_classify.online.stream_health import (
    CONTINUES,
    fits_float32,
    HELD,
    RateJudge,
    RESTARTED,
    Timeline,
    window_fault,
)
from tactex_common.channels import CHANNELS
from tactex_common.stamps import gaps

CONTACT_SOURCES = ('auto', 'sweep_active', 'pressure', 'always')
REFERENCE = 'imu'  # the stream every other is joined onto, as in the converter
LOOKBACK = 64  # finalised reference samples re-aligned each poll (medians, duplicates)
RECENT_STAMPS = 256  # aligned stamps behind the gap rule's median
RATE_STAMPS = 64  # IMU stamps before the stream's rate is judged
RATE_SPAN = 256  # the rate is judged over the newest this many IMU stamps
RATE_STEP = 8  # the rate is judged on steps over this many samples (jitter averages out)
RATE_EVERY = 16  # IMU samples between judgements of the rate while no window is cut
WARMUP = 8  # IMU samples before the first is made final (periods need a few steps)
RESYNC = 'stamps jumped'  # why the evidence restarts when the timeline restarts
MEDIAN_OF = 3  # the pressure rule reads the median of this many latest readings


@dataclass(frozen=True)
class LiveSettings:
    """How the live stream is cut and gated (see the module docstring).

    Attributes:
        hop: samples between windows (0: the checkpoint's hop).
        contact: 'auto', 'sweep_active', 'pressure' or 'always'.
        contact_pa: pressure rise over the baseline that means contact (Pa).
        baseline_tau_s: time constant of the pressure baseline out of contact (s).
        reorder_s: how long a sample may wait for an earlier one that arrives late (s).
        max_lag_s: a stream silent while the IMU delivers this many seconds of samples is
            not waited for (s).
        capacity: samples held per stream.
        jump_s: a stamp further than this from its stream's newest is off the timeline (s).
    """

    hop: int = 0
    contact: str = 'auto'
    contact_pa: float = FilterRule.contact_pa
    baseline_tau_s: float = 2.0
    reorder_s: float = 0.0
    max_lag_s: float = 0.25
    capacity: int = 4096
    jump_s: float = 0.5

    def __post_init__(self) -> None:
        """Check the ranges.

        Raises:
            ValueError: naming the setting and its range.
        """
        if self.contact not in CONTACT_SOURCES:
            raise ValueError(f'contact must be one of {", ".join(CONTACT_SOURCES)}, got '
                             f'{self.contact!r}')
        if not isinstance(self.hop, int) or self.hop < 0:
            raise ValueError(f'hop must be an integer >= 0, got {self.hop!r}')
        for name in ('contact_pa', 'baseline_tau_s', 'max_lag_s', 'jump_s'):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f'{name} must be finite and > 0, got {value!r}')
        if not (math.isfinite(self.reorder_s) and 0 <= self.reorder_s < self.max_lag_s):
            raise ValueError(f'reorder_s must be in [0, max_lag_s), got {self.reorder_s!r}')
        if not isinstance(self.capacity, int) or self.capacity < 2 * LOOKBACK:
            raise ValueError(f'capacity must be an integer >= {2 * LOOKBACK}, got '
                             f'{self.capacity!r}')


@dataclass(frozen=True)
class Window:
    """One window ready for the model.

    Attributes:
        values: (window, channels) samples in the checkpoint's channel order, SI units.
        start_ns: stamp of its first sample.
        end_ns: stamp of its last sample.
        completed_ns: arrival time of the message that completed its last sample.
    """

    values: np.ndarray
    start_ns: int
    end_ns: int
    completed_ns: int


@dataclass(frozen=True)
class ContactLost:
    """The sensor left contact (the sweep ended, or the stamps jumped) at `stamp_ns`."""

    stamp_ns: int
    reason: str


class RingBuffer:
    """The newest `capacity` samples of one stream: stamps, values and arrival times."""

    def __init__(self, capacity: int, width: int) -> None:
        self.capacity = capacity
        self.stamps = np.zeros(capacity, dtype=np.int64)
        self.values = np.zeros((capacity, width))
        self.arrivals = np.zeros(capacity, dtype=np.int64)
        self.count = 0  # samples ever written
        self.latest_ns: int | None = None

    def append(self, stamp_ns: int, values, arrival_ns: int) -> int | None:
        """Store a sample; return the stamp of the sample it overwrote (None if none)."""
        slot = self.count % self.capacity
        overwritten = int(self.stamps[slot]) if self.count >= self.capacity else None
        self.stamps[slot], self.values[slot], self.arrivals[slot] = stamp_ns, values, arrival_ns
        self.count += 1
        if self.latest_ns is None or stamp_ns > self.latest_ns:
            self.latest_ns = stamp_ns
        return overwritten

    def since(self, stamp_ns: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The held samples stamped after `stamp_ns`, in arrival order."""
        held = min(self.count, self.capacity)
        order = (np.arange(self.count - held, self.count) % self.capacity)
        chosen = order[self.stamps[order] > stamp_ns]
        return self.stamps[chosen], self.values[chosen], self.arrivals[chosen]


@dataclass
class PressureContact:
    """Contact by the pressure rule: transitions (stamp, touching) from barometer samples.

    Each reading is judged against the baseline, as the converter judges each sample. The
    baseline follows the median of the last MEDIAN_OF finite readings (the first is their
    median), so a single wild reading cannot move it; out of contact, a fall of that
    median more than half of `contact_pa` below the baseline is taken as the baseline at
    once (a fall is never contact).
    """

    contact_pa: float
    tau_s: float
    baseline: float | None = None
    touching: bool = False
    last_ns: int | None = None
    transitions: list[tuple[int, bool]] = field(default_factory=list)
    recent: deque[float] = field(default_factory=lambda: deque(maxlen=MEDIAN_OF))

    def update(self, stamps_ns: np.ndarray, pressure: np.ndarray) -> None:
        """Feed finite samples in stamp order (older than the last one are ignored)."""
        for stamp, reading in zip(stamps_ns.tolist(), pressure.tolist(), strict=True):
            if (self.last_ns is not None and stamp <= self.last_ns) or not math.isfinite(
                    reading):
                continue
            self.recent.append(reading)
            typical = sorted(self.recent)[len(self.recent) // 2]  # a reading: no overflow
            if self.baseline is None and len(self.recent) < MEDIAN_OF:
                self.last_ns = stamp
                continue
            if self.baseline is None or (not self.touching
                                         and typical < self.baseline - self.contact_pa / 2):
                self.baseline = typical
            elif not self.touching:
                weight = min(1.0, (stamp - self.last_ns) * 1e-9 / self.tau_s)
                # A weighted mean of two finite values: never overflows.
                self.baseline = self.baseline * (1.0 - weight) + typical * weight
            rise = reading - self.baseline
            touching = rise > self.contact_pa if not self.touching else rise > self.contact_pa / 2
            if touching != self.touching:
                self.touching = touching
                self.transitions.append((stamp, touching))
            self.last_ns = stamp


class LiveWindows:
    """Samples of the tactile streams in, windows and contact events out.

    Args:
        stream: the checkpoint's stream (channels, window, hop, rate).
        settings: how the stream is cut and gated.

    Raises:
        ValueError: a channel the tactile topics do not carry.
    """

    def __init__(self, stream: StreamSpec, settings: LiveSettings = LiveSettings()) -> None:
        unknown = [c for c in stream.channels if c not in CHANNELS]
        if unknown:
            raise ValueError(f'the model was trained on channels {", ".join(stream.channels)}; '
                             f'the tactile topics carry {", ".join(CHANNELS)} '
                             f'({", ".join(unknown)} missing)')
        self.stream, self.settings = stream, settings
        self.window = stream.window
        self.hop = settings.hop or stream.hop
        if self.hop > self.window:
            raise ValueError(f'hop {self.hop} is longer than the window {self.window}')
        # Streams joined as the converter joins them: the IMU, then the others it needs.
        self.aligned_roles = [REFERENCE] + [r for r in ('mag', 'pressure')
                                            if set(ROLE_CHANNELS[r]) & set(stream.channels)]
        self.roles = list(self.aligned_roles)
        if settings.contact in ('auto', 'pressure') and 'pressure' not in self.roles:
            self.roles.append('pressure')
        joined = [c for role in self.aligned_roles for c in ROLE_CHANNELS[role]]
        self._order = [joined.index(c) for c in stream.channels]
        self._period_ns = 1e9 / stream.sampling_rate_hz
        self._timeline = Timeline(int(settings.jump_s * 1e9))
        self._run = np.zeros((self.window, len(stream.channels)))
        self._run_stamps = np.zeros(self.window, dtype=np.int64)
        self._active: list[tuple[int, bool]] = []
        self.active_seen = False
        self._pending: list[ContactLost] = []  # resyncs, handed out by the next poll
        self.counts = {'samples': 0, 'late': 0, 'overflow': 0, 'dropped': 0, 'windows': 0,
                       'invalid': 0, 'off_timeline': 0, 'resyncs': 0}
        self._longest_ended = 0  # the longest run of samples in contact that has ended
        self._run_count = 0
        self._reset_streams()

    def _reset_streams(self) -> None:
        """Empty every buffer and forget what was final: a fresh start of the streams."""
        self._buffers = {role: RingBuffer(self.settings.capacity, len(ROLE_CHANNELS[role]))
                         for role in self.roles}
        self._final_ns: int | None = None  # stamps up to here are final
        self._reference_count = 0  # IMU samples since the start
        # _reference_count at each other stream's last sample (how far it lags).
        self._heard_at = dict.fromkeys(self.roles[1:], 0)
        self._recent = np.zeros(0, dtype=np.int64)  # newest aligned stamps
        self._rate_stamps: deque[int] = deque(maxlen=RATE_SPAN)  # newest IMU stamps, late too
        self._end_run()
        self._kept_before = False
        self._pressure = PressureContact(self.settings.contact_pa, self.settings.baseline_tau_s)
        self._pressure_done: int | None = None

    @property
    def longest_contact(self) -> int:
        """The longest run of samples in contact so far (a window needs `window` of them)."""
        return max(self._longest_ended, self._run_count)

    def _end_run(self) -> None:
        """The run of samples in contact ends: its length is kept, the next starts at 0."""
        self._longest_ended = max(self._longest_ended, self._run_count)
        self._run_count = 0

    @property
    def needed_roles(self) -> list[str]:
        """The streams this model (and the contact rule) read."""
        return list(self.roles)

    def stream_rate_hz(self) -> float | None:
        """The stream's rate from the newest IMU stamps (None: too few yet).

        The median RATE_STEP-sample step of the stamps in order, each counted once: robust
        to gaps, repeats, late samples and jitter of a few periods.
        """
        stamps = np.unique(np.fromiter(self._rate_stamps, dtype=np.int64))
        if stamps.size < RATE_STAMPS:
            return None
        steps = stamps[RATE_STEP:] - stamps[:-RATE_STEP]
        median = float(np.median(steps))
        return RATE_STEP * 1e9 / median if median > 0 else math.inf

    def latest_ns(self, role: str) -> int | None:
        """Newest stamp seen on a stream (None before its first sample)."""
        return self._buffers[role].latest_ns

    def add(self, role: str, stamp_ns: int, values: Sequence[float], arrival_ns: int) -> None:
        """One sample of a stream (ignored if the model does not read it)."""
        if role not in self._buffers:
            return
        if not fits_float32(values):
            self.counts['invalid'] += 1
            return
        verdict = (self._timeline.judge(stamp_ns) if role == REFERENCE
                   else CONTINUES if self._timeline.near(stamp_ns) else HELD)
        if verdict == HELD:
            self.counts['off_timeline'] += 1
            return
        if verdict == RESTARTED:
            self._restart(int(stamp_ns))
        if role == REFERENCE:
            self._rate_stamps.append(int(stamp_ns))
        if self._final_ns is not None and stamp_ns <= self._final_ns:
            self.counts['late'] += 1
            return
        overwritten = self._buffers[role].append(int(stamp_ns), values, int(arrival_ns))
        if role == REFERENCE:
            self.counts['samples'] += 1
            self._reference_count += 1
        else:
            self._heard_at[role] = self._reference_count
        if overwritten is not None and (self._final_ns is None or overwritten > self._final_ns):
            self.counts['overflow'] += 1

    def _restart(self, stamp_ns: int) -> None:
        """The IMU's stamps moved to a new timeline at `stamp_ns`: start again from there."""
        self.counts['resyncs'] += 1
        self._active = [t for t in self._active
                        if abs(t[0] - stamp_ns) <= self._timeline.jump_ns]
        self._reset_streams()
        self._pending.append(ContactLost(stamp_ns, RESYNC))

    def set_active(self, active: bool, stamp_ns: int) -> None:
        """A sweep/active message received at `stamp_ns` (the clock the sensor stamps use).

        As in the converter, a segment holds the samples stamped from its true message to
        its false message, both included.
        """
        self.active_seen = True
        self._active.append((int(stamp_ns), bool(active)))

    def horizon_ns(self) -> int | None:
        """Stamp up to which samples can be made final now (None: nothing yet)."""
        horizon = self._buffers[REFERENCE].latest_ns
        if self._reference_count < WARMUP:
            return None  # align's tolerance needs the streams' periods
        stalled = self.settings.max_lag_s * self.stream.sampling_rate_hz
        for role in self.roles[1:]:
            if self._reference_count - self._heard_at[role] > stalled:
                continue  # stalled (or never started): not waited for
            latest = self._buffers[role].latest_ns
            if self._buffers[role].count < 2:
                return None  # not started yet: wait for it a while
            horizon = min(horizon, latest)
        # Integer nanoseconds: a stamp since the epoch (~1.8e18) is not exact as a float64
        # (256 ns apart), and rounding it down kept the newest sample waiting for the next.
        return int(horizon) - int(round(self.settings.reorder_s * 1e9))

    def poll(self) -> list[Window | ContactLost]:
        """Make final what can be; return the windows and contact losses it completes."""
        events: list[Window | ContactLost] = self._pending
        self._pending = []
        horizon = self.horizon_ns()
        if horizon is None or (self._final_ns is not None and horizon <= self._final_ns):
            return events
        final = -np.inf if self._final_ns is None else self._final_ns
        lookback = LOOKBACK * self._period_ns
        streams = []
        for role in self.aligned_roles:
            stamps, values, _ = self._buffers[role].since(final - lookback * (
                1 if role == REFERENCE else 2))
            streams.append(Stream(role, ROLE_CHANNELS[role], stamps, values))
        aligned = align(streams[0], streams[1:])
        new = (aligned.stamps_ns > final) & (aligned.stamps_ns <= horizon)
        reference = np.unique(streams[0].stamps_ns)
        arrived = int(np.sum((reference > final) & (reference <= horizon)))
        self.counts['dropped'] += arrived - int(new.sum())
        self._final_ns = horizon
        stamps, values = aligned.stamps_ns[new], aligned.values[new][:, self._order]
        self._update_pressure(horizon)
        return events + self._cut(stamps, values)

    def _update_pressure(self, horizon: int) -> None:
        if 'pressure' not in self._buffers:
            return
        done = -np.inf if self._pressure_done is None else self._pressure_done
        stamps, values, _ = self._buffers['pressure'].since(done)
        order = np.argsort(stamps, kind='stable')
        chosen = order[stamps[order] <= horizon]
        self._pressure.update(stamps[chosen], values[chosen, 0])
        self._pressure_done = horizon

    def _keep(self, stamps: np.ndarray) -> tuple[np.ndarray, str]:
        """Which samples are in contact, and what losing it is called."""
        source = self.settings.contact
        if source == 'auto':
            source = 'sweep_active' if self.active_seen else 'pressure'
        if source == 'always':
            return np.ones(stamps.size, dtype=bool), ''
        if source == 'sweep_active':
            return inside(stamps, segments(self._active)), 'sweep/active fell'
        return inside(stamps, segments(self._pressure.transitions)), 'contact lost'

    def _cut(self, stamps: np.ndarray, values: np.ndarray) -> list[Window | ContactLost]:
        """Runs and windows as `dataset.window_starts` finds them, one sample at a time."""
        if not stamps.size:
            return []
        keep, reason = self._keep(stamps)
        recent = np.concatenate([self._recent, stamps])
        gap_before = np.concatenate([[False], gaps(recent)])[self._recent.size:]
        self._recent = recent[-RECENT_STAMPS:]
        events: list[Window | ContactLost] = []
        for i, stamp in enumerate(stamps.tolist()):
            if keep[i] != self._kept_before or gap_before[i]:
                if self._kept_before and not keep[i]:
                    events.append(ContactLost(stamp, reason))
                self._end_run()
            self._kept_before = bool(keep[i])
            if not keep[i]:
                continue
            slot = self._run_count % self.window
            self._run[slot], self._run_stamps[slot] = values[i], stamp
            self._run_count += 1
            if self._run_count >= self.window and (self._run_count - self.window) % self.hop == 0:
                order = (np.arange(self._run_count, self._run_count + self.window)
                         % self.window)
                events.append(Window(self._run[order].copy(), int(self._run_stamps[order[0]]),
                                     stamp, self._completed(stamp)))
                self.counts['windows'] += 1
        return events

    def _completed(self, stamp_ns: int) -> int:
        """Arrival of the last message needed for the sample stamped `stamp_ns`."""
        arrivals = []
        for role in self.aligned_roles:
            stamps, _, arrived = self._buffers[role].since(stamp_ns - 1)
            if arrived.size:
                arrivals.append(int(arrived[np.argmin(stamps)]))
        return max(arrivals)

    def prune_active(self) -> None:
        """Forget sweep/active spans that ended before every stamp still to come."""
        spans = segments(self._active)
        if self._final_ns is not None and len(spans) > 1:
            old = [s for s in spans[:-1] if s[1] < self._final_ns]
            if old:
                last_end = old[-1][1]
                self._active = [t for t in self._active if t[0] > last_end]


@dataclass(frozen=True)
class Classified:
    """An estimate with the window that made it and the model's own probabilities."""

    estimate: Estimate
    window: Window
    proba: np.ndarray


class OnlineClassifier:
    """LiveWindows + a model + Evidence: the whole online classifier without ROS.

    Args:
        predict: (n, window, channels) raw windows -> (n, classes) probabilities.
        stream: the checkpoint's stream.
        classes: number of classes.
        live: how the stream is cut and gated.
        evidence: the decision and change rules.
        newest_only: classify only the newest pending window (skip and count the rest).
        rate_tolerance: relative difference from the checkpoint's rate accepted.

    Attributes:
        faults: windows not classified, by cause: 'refused' (the stream's rate is off),
            'frozen', 'saturated', 'model_errors' (the model call raised or returned
            something other than finite probabilities).
        last_fault: what the newest unclassified window had ('' once one is classified).
    """

    def __init__(self, predict: Callable[[np.ndarray], np.ndarray], stream: StreamSpec,
                 classes: int, *, live: LiveSettings = LiveSettings(),
                 evidence: EvidenceSettings | None = None,
                 newest_only: bool = True, rate_tolerance: float = 0.05) -> None:
        self.predict = predict
        self.classes = classes
        self.windows = LiveWindows(stream, live)
        self.evidence = Evidence(classes, int(round(1e9 / stream.sampling_rate_hz)),
                                 evidence or EvidenceSettings())
        self.rate = RateJudge(stream, rate_tolerance)
        self.newest_only = newest_only
        self.skipped = 0
        self.resets: dict[str, int] = {}
        self._rate_judged_at = 0  # IMU samples when the rate was last judged
        self.faults = dict.fromkeys(('refused', 'frozen', 'saturated', 'model_errors'), 0)
        self.last_fault = ''

    def step(self) -> list[Classified]:
        """Classify what the samples added so far complete, in stamp order."""
        events = self.windows.poll()
        self.windows.prune_active()
        if any(isinstance(e, ContactLost) and e.reason == RESYNC for e in events):
            self.rate.forget()
        windows = [e for e in events if isinstance(e, Window)]
        samples = self.windows.counts['samples']
        if windows or samples - self._rate_judged_at >= RATE_EVERY:
            self._rate_judged_at = samples
            self.rate.measured(self.windows.stream_rate_hz())
        chosen = windows[-1:] if self.newest_only else windows
        self.skipped += len(windows) - len(chosen)
        if chosen and self.rate.refusal:
            self.faults['refused'] += len(chosen)
            self.last_fault = self.rate.refusal
            events, chosen = [ContactLost(chosen[-1].end_ns, 'rate off')], []
        faulty = {id(w): fault for w in chosen
                  if (fault := window_fault(w.values, self.windows.stream.channels))}
        probabilities = self._predict([w for w in chosen if id(w) not in faulty])
        results = []
        for event in events:
            if isinstance(event, ContactLost):
                self._reset(event.reason)
            elif id(event) in faulty:
                kind = faulty[id(event)].split()[0]  # 'frozen' or 'saturated'
                self.faults[kind] += 1
                self.last_fault = f'{faulty[id(event)]} window'
                self._reset(kind)
            elif id(event) in probabilities:
                self.last_fault = ''
                proba = probabilities[id(event)]
                estimate = self.evidence.add(proba, event.start_ns, event.end_ns)
                if estimate.restarted:
                    self.resets[estimate.restarted] = self.resets.get(estimate.restarted,
                                                                      0) + 1
                results.append(Classified(estimate, event, proba))
        return results

    def _predict(self, windows: list[Window]) -> dict[int, np.ndarray]:
        """The model's probabilities of each window by id ({} when the model fails)."""
        if not windows:
            return {}
        try:
            proba = np.asarray(self.predict(np.stack([w.values for w in windows])), dtype=float)
            if proba.shape != (len(windows), self.classes) or \
                    not np.all(np.isfinite(proba) & (proba >= 0)):
                raise ValueError(f'the model returned {proba.shape} values, not finite, '
                                 f'non-negative probabilities of {self.classes} classes per '
                                 'window')
        except Exception as err:  # noqa: BLE001 - whatever the model raises skips its windows
            self.faults['model_errors'] += len(windows)
            self.last_fault = f'model error: {type(err).__name__}: {err}'
            return {}
        return dict(zip(map(id, windows), proba, strict=True))

    def _reset(self, reason: str) -> None:
        if self.evidence.windows:
            self.resets[reason] = self.resets.get(reason, 0) + 1
        self.evidence.reset()
