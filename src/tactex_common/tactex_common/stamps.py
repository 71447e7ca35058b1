# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Stamps as int nanoseconds, and the one rule for a gap in a sampled stream."""

from __future__ import annotations

import numpy as np

# A step longer than this many median periods is a gap: windows never cross one.
GAP_FACTOR = 2.5
# Samples either side of a clock reset whose lead over the log times places the part after.
RESET_CONTEXT = 50


def stamp_ns(stamp) -> int:
    """Nanoseconds of a builtin_interfaces/Time (rclpy or rosbags; anything with sec, nanosec)."""
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


def stamp_or_log_ns(header_ns: int, log_ns: int) -> int:
    """A logged message's header stamp, or its log time where a driver left the stamp 0.

    A simulation's first sample is at 0 on both clocks: it stays 0.
    """
    return log_ns if header_ns == 0 else header_ns


def gaps(stamps_ns: np.ndarray) -> np.ndarray:
    """True at step i when stamps i -> i+1 are more than GAP_FACTOR median periods apart.

    Returns a bool array one shorter than `stamps_ns` (empty for fewer than 2 stamps).
    """
    steps = np.diff(np.asarray(stamps_ns, dtype=np.int64))
    if steps.size == 0:
        return np.zeros(0, dtype=bool)
    return steps > GAP_FACTOR * float(np.median(steps))


def mean_rate_hz(stamps_ns: np.ndarray) -> float:
    """Samples per second of sorted stamps over their gap-free runs (nan: none to measure).

    NaN for fewer than two stamps, or for stamps that never advance. The mean step with
    gaps left out: (samples - 1) / duration within each run. Stamps
    rounded to a clock's tick average out (350 Hz with whole milliseconds stays 350 Hz),
    where a median step would read the tick (333.3 Hz).
    """
    stamps_ns = np.asarray(stamps_ns, dtype=np.int64)
    if stamps_ns.size < 2:
        return float('nan')
    steady = np.diff(stamps_ns)[~gaps(stamps_ns)]
    mean_step = float(np.mean(steady))
    return 1e9 / mean_step if mean_step > 0 else float('nan')  # repeated stamps: no rate


def after_clock_resets(stamps_ns: np.ndarray, log_ns: np.ndarray | None = None
                       ) -> tuple[np.ndarray, int]:
    """One clock's stamps with each part after a reset moved past the parts before it.

    A step back by more than GAP_FACTOR median (forward) periods is either late samples
    (a buffer flushed late: the stamps after them jump forward again, back to where the
    stream was) or the clock restarting (the stamps go on from there, with no such jump
    back). Late samples are left to sorting. After a restart sorting would interleave the
    parts, so each later part is moved past the parts before it: the parts keep their
    order and no window spans a reset. Without log times a part is moved to begin two
    gaps after the latest stamp before it. With `log_ns` (when each sample reached a
    recorder, on a clock that did not restart) it is moved by the change across the reset
    in how far the stamps lead the log times (medians of RESET_CONTEXT samples either
    side): streams of one device clock move alike and the time the device was away is
    kept, at least a gap. With log times a step back that stays within the stream's span
    so far is late or re-sent samples even at the end (a restarted clock goes back below
    where the recording began; a CSV's time column, without log times, may restart at the
    0 it began with).

    Returns:
        The stamps (int64; the input when nothing reset) and the number of resets.

    Raises:
        OverflowError: moving a part would carry a stamp past int64 nanoseconds.
    """
    stamps_ns = np.asarray(stamps_ns, dtype=np.int64)
    steps = np.diff(stamps_ns)
    forward = steps[steps > 0]
    if forward.size == 0:
        return stamps_ns, 0
    allowed = GAP_FACTOR * float(np.median(forward))
    starts = (np.flatnonzero(steps < -allowed) + 1).tolist()
    log_ns = None if log_ns is None else np.asarray(log_ns, dtype=np.int64)
    moved, resets = stamps_ns.copy(), 0
    for number, start in enumerate(starts):
        latest = int(moved[:start].max())
        back = np.flatnonzero(moved[start:] >= latest - allowed)  # where it rejoins
        if back.size and moved[start + back[0]] - moved[start + back[0] - 1] > allowed:
            continue  # late samples: the stream jumps back to where it was
        shift = latest + int(2 * allowed) - int(moved[start])
        if log_ns is not None:
            end = starts[number + 1] if number + 1 < len(starts) else moved.size
            if moved[start:end].min() >= moved[:start].min():
                continue  # within the stream's span: samples sent again or late, at its end
            logged = _logged_shift(moved, log_ns, start, end)
            # where the log times went back too, or the device was away too briefly for a
            # gap, the part begins past a gap all the same: no window spans the restart
            shift = max(logged, latest + int(allowed) + 1 - int(moved[start]))
        if int(moved[start:].max()) + shift > np.iinfo(np.int64).max:
            raise OverflowError('stamps past int64 nanoseconds after a clock reset')
        moved[start:] += shift
        resets += 1
    return moved, resets


def _logged_shift(stamps_ns: np.ndarray, log_ns: np.ndarray, start: int, end: int) -> int:
    """How far stamps[start:end] must move to lead the log times as the stamps before did."""
    lead = stamps_ns - log_ns  # int64: both are stamps of at least 0
    before = np.median(lead[max(0, start - RESET_CONTEXT):start])
    after = np.median(lead[start:min(end, start + RESET_CONTEXT)])
    return int(round(float(before) - float(after)))
