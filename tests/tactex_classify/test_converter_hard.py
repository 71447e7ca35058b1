# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Bag -> dataset conversion: aligning the streams and cutting windows, under any stamps."""

import warnings

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from support.hard_values import anything

from tactex_classify.data.dataset import window_starts
from tactex_classify.data.stream_alignment import align, Stream
from tactex_common.stamps import after_clock_resets, gaps, mean_rate_hz

pytestmark = pytest.mark.hard_case

# Header stamps: sec int32, nanosec uint32.
STAMP_LOW, STAMP_HIGH = -2**31 * 10**9, 2**31 * 10**9 + 2**32 - 1
stamps = st.one_of(st.integers(STAMP_LOW, STAMP_HIGH), st.sampled_from([STAMP_LOW, STAMP_HIGH, 0]),
                   st.integers(10**12, 10**12 + 10**9))


CHANNELS = {'imu': ('ax', 'ay', 'az', 'gx', 'gy', 'gz'), 'mag': ('mx', 'my', 'mz'),
            'pressure': ('baro',)}


@st.composite
def streams(draw, name):
    width = len(CHANNELS[name])
    count = draw(st.integers(0, 12))
    return Stream(name, CHANNELS[name],
                  np.array(draw(st.lists(stamps, min_size=count, max_size=count)),
                           dtype=np.int64),
                  np.array(draw(st.lists(st.lists(anything(), min_size=width, max_size=width),
                                         min_size=count, max_size=count)),
                           dtype=float).reshape(count, width))


@settings(max_examples=150)
@given(streams('imu'), streams('mag'), streams('pressure'))
def test_aligning_any_streams_keeps_sorted_finite_samples_and_accounts_for_the_rest(
        imu, mag, pressure):
    aligned = align(imu, [mag, pressure])
    dropped = aligned.dropped
    assert aligned.values.shape == (aligned.stamps_ns.size, 10)
    assert np.all(np.isfinite(aligned.values))
    assert np.all(np.diff(aligned.stamps_ns) > 0)
    assert set(aligned.stamps_ns.tolist()) <= set(imu.stamps_ns.tolist())
    assert all(count >= 0 for count in dropped.values())
    assert aligned.stamps_ns.size + dropped['nan_samples'] + dropped['unaligned_samples'] + \
        dropped['imu_duplicates'] == imu.stamps_ns.size


@settings(max_examples=60)
@given(st.integers(0, 30), st.integers(10**6, 10**8), st.integers(STAMP_LOW, 10**18))
def test_aligned_streams_keep_each_channel_where_it_belongs(count, period_ns, start_ns):
    stamps_ns = start_ns + period_ns * np.arange(count, dtype=np.int64)
    values = np.arange(count * 10, dtype=float).reshape(count, 10)  # every channel distinct
    aligned = align(Stream('imu', CHANNELS['imu'], stamps_ns, values[:, :6]),
                    [Stream('mag', CHANNELS['mag'], stamps_ns, values[:, 6:9]),
                     Stream('pressure', CHANNELS['pressure'], stamps_ns, values[:, 9:])])
    np.testing.assert_array_equal(aligned.stamps_ns, stamps_ns)
    np.testing.assert_array_equal(aligned.values, values)


@settings(max_examples=150)
@given(st.lists(st.booleans(), max_size=60), st.integers(1, 9), st.integers(1, 9),
       st.data())
def test_every_window_lies_in_one_kept_gap_free_run(keep, window, hop, data):
    count = len(keep)
    steps = data.draw(st.lists(st.sampled_from([1000, 1000, 1000, 1001, 5000, 0]),
                               min_size=max(count - 1, 0), max_size=max(count - 1, 0)))
    stamps_ns = np.concatenate([[0], np.cumsum(steps)]).astype(np.int64)[:count]
    keep = np.array(keep, dtype=bool)
    starts = window_starts(keep, stamps_ns, window, hop)
    gap = gaps(stamps_ns)
    for start in starts:
        assert 0 <= start and start + window <= count
        assert keep[start:start + window].all()
        assert not gap[start:start + window - 1].any()
    assert starts == sorted(set(starts))


@pytest.mark.parametrize('window, hop', [(0, 1), (4, 0), (-1, 2), (4, -1)])
def test_a_window_or_hop_below_one_is_a_clear_error(window, hop):
    with pytest.raises(ValueError, match='window and hop must be >= 1'):
        window_starts(np.ones(10, dtype=bool), np.arange(10) * 1000, window, hop)


@given(st.integers(0, 1), st.integers(1, 4))
def test_empty_and_single_sample_recordings_have_no_window(count, window):
    assert window_starts(np.ones(count, dtype=bool), np.arange(count, dtype=np.int64),
                         window, 1) == []


@given(st.lists(stamps, min_size=0, max_size=50), st.booleans())
def test_the_mean_rate_of_any_stamps_is_nan_or_positive_and_never_warns(values, repeat):
    sorted_ns = np.sort(np.array(values * (2 if repeat else 1), dtype=np.int64))
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        rate = mean_rate_hz(sorted_ns)  # repeated stamps too: [5, 5, 5] has no rate
    assert np.isnan(rate) or rate > 0
    assert np.isnan(mean_rate_hz(np.array([5, 5, 5])))


def test_the_mean_rate_of_whole_millisecond_stamps_is_the_true_rate():
    true_ns = np.arange(3500) * 1e9 / 350.0
    assert mean_rate_hz((np.floor(true_ns / 1e6) * 1e6).astype(np.int64)) == \
        pytest.approx(350.0, rel=1e-3)


@given(st.lists(stamps, min_size=0, max_size=50))
def test_after_clock_resets_any_stamps_keep_their_count_and_go_on_from_each_reset(values):
    raw = np.array(values, dtype=np.int64)
    try:
        moved, resets = after_clock_resets(raw)
    except OverflowError:
        return  # refused: a part would pass int64 nanoseconds
    assert moved.dtype == np.int64 and moved.size == raw.size and resets >= 0
    steps = np.diff(moved)
    if resets:  # each reset's step back is now a step forward
        assert np.sum(steps < 0) == np.sum(np.diff(raw) < 0) - resets
    assert np.array_equal(np.diff(moved)[np.diff(raw) >= 0], np.diff(raw)[np.diff(raw) >= 0])


@given(st.lists(st.tuples(stamps, st.integers(0, 2**63 - 1)), min_size=0, max_size=50))
def test_after_clock_resets_with_any_log_times_keeps_the_count_and_the_steps(pairs):
    raw = np.array([s for s, _ in pairs], dtype=np.int64)
    try:
        moved, resets = after_clock_resets(raw, np.array([t for _, t in pairs], dtype=np.int64))
    except OverflowError:
        return
    assert moved.size == raw.size and resets >= 0
    if resets:
        assert np.sum(np.diff(moved) < 0) == np.sum(np.diff(raw) < 0) - resets
    assert np.array_equal(np.diff(moved)[np.diff(raw) >= 0], np.diff(raw)[np.diff(raw) >= 0])


def test_log_times_place_the_part_after_a_reset_where_the_device_was_away():
    period, away = 4_000_000, 3 * 10**9  # 250 Hz; the device back after 3 s
    part = np.arange(100, dtype=np.int64) * period
    header = np.concatenate([part + 10**9, part])  # its clock restarts at 0
    logged = np.concatenate([part, part + 400_000_000 + away]) + 7 * 10**12
    logged += np.random.default_rng(0).integers(0, 2_000_000, logged.size)  # transport jitter
    moved, resets = after_clock_resets(header, logged)
    assert resets == 1 and np.array_equal(moved[:100], header[:100])
    assert moved[100] - moved[99] == pytest.approx(period + away, abs=1_000_000)
    # A second stream of the same clock at another rate moves alike.
    slow = np.arange(0, 100, 4)
    other, _ = after_clock_resets(header[np.concatenate([slow, 100 + slow])],
                                  logged[np.concatenate([slow, 100 + slow])])
    assert other[25] - moved[100] == pytest.approx(0, abs=1_000_000)
    # Where the log times went back too, or the device was away a moment, the part
    # follows past a gap all the same: no window spans the restart.
    for log_times in (np.concatenate([part, part]), np.concatenate([part, part + 4 * 10**8])):
        again, resets = after_clock_resets(header, log_times)
        assert resets == 1 and gaps(again).sum() == 1
    # Late or re-sent samples at the very end stay within the stream's span: not a restart.
    flushed = np.concatenate([part + 10**9, part[40:43] + 10**9])
    kept, resets = after_clock_resets(flushed, np.arange(flushed.size) * period)
    assert resets == 0 and np.array_equal(kept, flushed)


def test_a_clock_that_restarts_gives_parts_that_follow_each_other_with_a_gap():
    period = 4_000_000  # 250 Hz
    part = np.arange(100, dtype=np.int64) * period
    moved, resets = after_clock_resets(np.concatenate([part + 10**9, part]))  # back 1 s
    assert resets == 1 and np.all(np.diff(moved) > 0)
    assert gaps(moved).sum() == 1 and mean_rate_hz(moved) == pytest.approx(250.0)
    for late in (1, 5):  # rows out of order by one period, one row 5 periods late
        shuffled = part.copy()
        shuffled[20], shuffled[20 - late:20] = part[20 - late], part[20 - late + 1:21]
        kept, resets = after_clock_resets(shuffled)
        assert resets == 0 and np.array_equal(kept, shuffled)  # left to sorting
    flushed = np.concatenate([part[:10], part[13:30], part[10:13], part[30:]])  # 3 rows late
    kept, resets = after_clock_resets(flushed)
    assert resets == 0 and np.array_equal(kept, flushed)


def test_a_clock_reset_at_the_end_of_a_file_still_counts():
    period = 4_000_000
    stamps = np.concatenate([np.arange(50), np.arange(2)]).astype(np.int64) * period
    moved, resets = after_clock_resets(stamps)
    assert resets == 1 and np.all(np.diff(moved) > 0)
