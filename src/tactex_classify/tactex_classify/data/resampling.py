# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""One sampling rate per dataset: recordings of differing rates refused, or resampled.

A dataset's windows must share one rate. `common_rate` accepts recordings whose measured
rates agree within RATE_TOLERANCE (clock jitter) and otherwise names every rate and the
recordings that have it. `resample` puts a recording onto another rate, never across a
gap (`tactex_common.stamps.gaps`): each gap-free run is interpolated linearly onto a
uniform grid at the recording's measured rate, then filtered onto the target rate by
scipy's polyphase resampler, which removes what lies above the new Nyquist frequency
before it could fold back as an alias. The up/down factors are target / measured as a
fraction with a denominator of at most MAX_DENOMINATOR; the new stamps follow that
ratio, and no run is extended past its last sample. Each channel is filtered centred and
scaled into [-1, 1]: an offset (gravity, the air's pressure) passes exactly, not with the
filter's ripple, and the largest finite values cannot overflow (ringing past the largest
float is held at it).
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction

import numpy as np

from tactex_classify.errors import DatasetError
from tactex_common.stamps import gaps

# Rates this far apart (a fraction of the higher) are one rate: clock jitter, not a choice.
RATE_TOLERANCE = 0.05
MAX_DENOMINATOR = 1000
# A rate is changed by at most this factor, up or down.
MAX_RATIO = 1000
FLOAT_MAX = float(np.finfo(np.float64).max)


def common_rate(rates: Sequence[tuple[str, float]]) -> float:
    """The median of the recordings' (name, measured rate in Hz) when all are one rate.

    Raises:
        DatasetError: the rates differ by more than RATE_TOLERANCE; names each rate, the
            recordings at it, and the ways out.
    """
    groups: list[list[tuple[str, float]]] = []
    for name, rate in sorted(rates, key=lambda item: -item[1]):
        if groups and rate >= groups[-1][0][1] * (1 - RATE_TOLERANCE):
            groups[-1].append((name, rate))
        else:
            groups.append([(name, rate)])
    if len(groups) > 1:
        listed = ', '.join(
            f'{np.median([rate for _, rate in group]):.4g} Hz ('
            f'{", ".join(name for name, _ in group[:3])}'
            f'{f", ... {len(group)} in all" if len(group) > 3 else ""})' for group in groups)
        raise DatasetError(f'recordings at different rates: {listed}; convert them '
                           'separately or give --resample HZ')
    return float(np.median([rate for _, rate in rates]))


def resampling_ratio(measured_hz: float, target_hz: float) -> Fraction:
    """Target / measured rate as up/down factors (denominator <= MAX_DENOMINATOR).

    Raises:
        ValueError: a rate is not a finite number > 0, or they differ by more than
            MAX_RATIO.
    """
    if not all(np.isfinite(rate) and rate > 0 for rate in (measured_hz, target_hz)) or \
            not 1 / MAX_RATIO <= target_hz / measured_hz <= MAX_RATIO:
        raise ValueError(f'cannot resample {measured_hz:.4g} Hz to {target_hz:g} Hz: rates '
                         f'must be > 0 and at most {MAX_RATIO} times apart')
    return Fraction(target_hz / measured_hz).limit_denominator(MAX_DENOMINATOR)


def resample(stamps_ns: np.ndarray, values: np.ndarray, measured_hz: float, target_hz: float
             ) -> list[tuple[np.ndarray, np.ndarray]]:
    """Each gap-free run of the samples at `target_hz`, as (stamps_ns, values) pairs.

    Args:
        stamps_ns: (n,) increasing int64 stamps of the samples.
        values: (n, channels) finite samples.
        measured_hz: the recording's own rate (`Recording.rate_hz`), the first grid's.
        target_hz: the rate wanted.

    Returns:
        Per run, int64 stamps spaced by 1 / (measured_hz * ratio) from the run's first
        stamp up to its last, and the float64 values at them. Runs shorter than one
        measured period (a lone sample among them) give nothing.

    Raises:
        ValueError: see `resampling_ratio` (only for two samples or more).
    """
    stamps_ns = np.asarray(stamps_ns, dtype=np.int64)
    if stamps_ns.size < 2:
        return []
    from scipy.signal import firwin  # scipy.signal takes seconds to import: only when used
    ratio = resampling_ratio(measured_hz, target_hz)
    longest = max(ratio.numerator, ratio.denominator)
    # resample_poly's filter; at the measured rate itself only the grid is made uniform
    taps = firwin(20 * longest + 1, 1 / longest, window=('kaiser', 5.0)) if longest > 1 \
        else np.ones(1)
    bounds = np.flatnonzero(gaps(stamps_ns)) + 1
    runs = [_resample_run(run_stamps, run_values, 1e9 / measured_hz, ratio, taps)
            for run_stamps, run_values in zip(np.split(stamps_ns, bounds),
                                              np.split(np.asarray(values, np.float64), bounds),
                                              strict=True)]
    return [run for run in runs if run is not None]


def _resample_run(stamps_ns: np.ndarray, values: np.ndarray, period_ns: float,
                  ratio: Fraction, taps: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """One gap-free run onto a grid of `period_ns`, then filtered by up/down `ratio`.

    None when the run spans less than one period.
    """
    offsets_ns = (stamps_ns - stamps_ns[0]).astype(np.float64)
    grid_size = int(offsets_ns[-1] // period_ns) + 1
    if grid_size < 2:
        return None
    highest, lowest = values.max(axis=0) / 2, values.min(axis=0) / 2
    varies = highest > lowest
    centre = np.where(varies, highest + lowest, values[0])
    scale = np.where(varies, highest - lowest, 1.0)
    grid_ns = np.arange(grid_size) * period_ns
    uniform = np.stack([np.interp(grid_ns, offsets_ns, channel)
                        for channel in ((values - centre) / scale).T], axis=1)
    from scipy.signal import resample_poly
    up, down = ratio.numerator, ratio.denominator
    with np.errstate(over='ignore'):  # ringing past the largest float is held at it
        filtered = np.clip(centre + scale * resample_poly(
            uniform, up, down, axis=0, window=taps, padtype='line'), -FLOAT_MAX, FLOAT_MAX)
    size = (grid_size - 1) * up // down + 1  # none past the run's last sample
    step_ns = period_ns * down / up
    return stamps_ns[0] + np.round(np.arange(size) * step_ns).astype(np.int64), filtered[:size]


def carry_mask(mask: np.ndarray, stamps_ns: np.ndarray, resampled_ns: np.ndarray
               ) -> np.ndarray:
    """`mask` of the samples at `stamps_ns`, carried to resampled stamps within their span.

    A resampled sample is True when the samples on both sides of it (or the one at its
    stamp) are: it was computed from them.
    """
    after = np.searchsorted(stamps_ns, resampled_ns, side='left')
    before = np.searchsorted(stamps_ns, resampled_ns, side='right') - 1
    return mask[before] & mask[after]
