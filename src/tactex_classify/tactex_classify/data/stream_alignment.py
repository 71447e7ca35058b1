# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Streams sampled on their own clocks joined onto one: the converter's and the live rule.

`align` is pure and channel-agnostic: stamps and values of a reference stream (the IMU
for this system's recordings) and of any other streams in, one array of aligned samples
out, with every dropped sample counted by reason. The bag converter, the CSV and MUN
importers and a live ring buffer call the same function, so samples line up the same
way offline and online.

Rules: each stream is sorted by stamp and a repeated stamp keeps its first sample. Each
reference sample takes, from every other stream, the sample nearest in time if it lies
within half the coarser of the two sampling periods; otherwise the reference sample is
dropped as unaligned. Samples with NaN or inf in any channel are dropped.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np


@dataclass(frozen=True)
class Stream:
    """One sampled stream.

    Attributes:
        name: what it is called in drop counts (`imu`, `mag`, `pressure`, ...).
        channels: names of its value columns.
        stamps_ns: (n,) int64 sample stamps.
        values: (n, len(channels)) float64 samples.
    """

    name: str
    channels: tuple[str, ...]
    stamps_ns: np.ndarray
    values: np.ndarray

    def __post_init__(self) -> None:
        """Check that stamps, values and channel names agree."""
        stamps, values = np.asarray(self.stamps_ns), np.asarray(self.values)
        if stamps.ndim != 1 or values.ndim != 2 or values.shape != (stamps.size,
                                                                     len(self.channels)):
            raise ValueError(f'stream {self.name!r}: stamps {stamps.shape} and values '
                             f'{values.shape} do not fit {len(self.channels)} channel(s)')


@dataclass(frozen=True)
class Aligned:
    """Samples of every stream on the reference's stamps, finite only."""

    channels: tuple[str, ...]
    stamps_ns: np.ndarray  # (n,) int64, increasing
    values: np.ndarray  # (n, len(channels)) float64
    dropped: dict[str, int] = field(default_factory=dict)
    reordered: dict[str, int] = field(default_factory=dict)  # per stream, samples sorted


def median_period_ns(stamps_ns: np.ndarray) -> float:
    """Median step of sorted stamps (nan for fewer than two)."""
    steps = np.diff(np.asarray(stamps_ns, dtype=np.int64))
    return float(np.median(steps)) if steps.size else float('nan')


def sorted_unique(stream: Stream, dropped: dict[str, int], reordered: dict[str, int]
                  ) -> Stream:
    """The stream sorted by stamp, a repeated stamp's later samples dropped; both counted.

    `reordered[name]` counts the samples that came after a later-stamped one (sorted into
    place and kept), and `dropped[name_duplicates]` the repeats.
    """
    stamps = np.asarray(stream.stamps_ns, dtype=np.int64)
    values = np.asarray(stream.values, dtype=np.float64)
    reordered[stream.name] = int(np.sum(stamps[1:] < np.maximum.accumulate(stamps)[:-1]))
    order = np.argsort(stamps, kind='stable')
    stamps, values = stamps[order], values[order]
    keep = np.concatenate([[True], np.diff(stamps) > 0]) if stamps.size else \
        np.zeros(0, dtype=bool)
    dropped[f'{stream.name}_duplicates'] = int(np.sum(~keep))
    return Stream(stream.name, stream.channels, stamps[keep], values[keep])


def nearest(stamps_ns: np.ndarray, other_ns: np.ndarray, tolerance_ns: float) -> np.ndarray:
    """Index into sorted `other_ns` of the stamp nearest each stamp; -1 beyond the tolerance."""
    stamps_ns = np.asarray(stamps_ns, dtype=np.int64)
    other_ns = np.asarray(other_ns, dtype=np.int64)
    if other_ns.size == 0:
        return np.full(stamps_ns.size, -1)
    index = np.clip(np.searchsorted(other_ns, stamps_ns), 0, other_ns.size - 1)
    previous = np.maximum(index - 1, 0)
    nearer = np.abs(stamps_ns - other_ns[previous]) <= np.abs(other_ns[index] - stamps_ns)
    index = np.where(nearer, previous, index)
    return np.where(np.abs(other_ns[index] - stamps_ns) <= tolerance_ns, index, -1)


def align(reference: Stream, others: Sequence[Stream] = ()) -> Aligned:
    """Join `others` onto the stamps of `reference` (see the module's rules).

    Returns:
        The aligned samples, channels in the order reference, then each other stream;
        `dropped` counts `<name>_duplicates`, `unaligned_samples` (reference samples some
        stream had nothing near) and `nan_samples`; `reordered` the samples of each stream
        that arrived out of time order and were sorted into it.
    """
    dropped: dict[str, int] = {}
    reordered: dict[str, int] = {}
    base = sorted_unique(reference, dropped, reordered)
    stamps = base.stamps_ns
    period = median_period_ns(stamps)
    columns = [base.values]
    joined = np.ones(stamps.size, dtype=bool)
    for other in others:
        other = sorted_unique(other, dropped, reordered)
        values = np.full((stamps.size, len(other.channels)), np.nan)
        columns.append(values)
        tolerance = 0.5 * np.nanmax([period, median_period_ns(other.stamps_ns), 0.0])
        index = nearest(stamps, other.stamps_ns, tolerance)
        close = index >= 0
        values[close] = other.values[index[close]]
        joined &= close
    values = np.concatenate(columns, axis=1)
    finite = np.all(np.isfinite(values), axis=1)
    dropped['nan_samples'] = int(np.sum(joined & ~finite))
    dropped['unaligned_samples'] = int(np.sum(~joined))
    keep = finite & joined
    channels = tuple(base.channels) + tuple(c for s in others for c in s.channels)
    return Aligned(channels, stamps[keep], values[keep], dropped, reordered)
