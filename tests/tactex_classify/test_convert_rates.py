# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Recordings at any sampling rate: kept as measured, refused when mixed, or resampled."""

import json
import re

from hypothesis import assume, given, settings
from hypothesis import strategies as st
import numpy as np
import pytest
from support.bagfactory import ramp, write_bag
from support.hard_values import finite

from tactex.cli import main
from tactex_classify.data.bags import Recording
from tactex_classify.data.dataset import convert, NO_CONTACT_INFORMATION
from tactex_classify.data.resampling import (
    carry_mask,
    common_rate,
    MAX_RATIO,
    resample,
    resampling_ratio,
)
from tactex_classify.errors import DatasetError
from tactex_common.stamps import gaps

QUIET = {'progress': lambda line: None}
START_NS = 10**12


def sampled(rate_hz, seconds, signal=None):
    """Ramp samples at `rate_hz` for `seconds`; channel ax is `signal(t)` when given."""
    stamps, values = ramp(round(rate_hz * seconds), START_NS, round(1e9 / rate_hz))
    if signal is not None:
        values[:, 0] = signal(seconds_of(stamps))
    return stamps, values


def seconds_of(stamps_ns):
    """Seconds since the first sample of `sampled`."""
    return (np.asarray(stamps_ns) - START_NS) * 1e-9


def record(path, stamps, values, *, trial=0, label='wood', swept=True, **options):
    """A live-order recording, one sweep segment over all of it unless not `swept`."""
    return write_bag(path, stamps, values, metadata={'label': label, 'trial': trial},
                     active=[(stamps[0], stamps[-1])] if swept else None, live_order=True,
                     **options)


def sine(frequency_hz):
    return lambda t: np.sin(2 * np.pi * frequency_hz * t)


def amplitude_at(windows, bin_index):
    """Amplitude of each window's component at one FFT bin."""
    return 2 * np.abs(np.fft.rfft(windows, axis=-1)[..., bin_index]) / windows.shape[-1]


def run_cli(capsys, *argv):
    """Exit code and the `error:` lines of `tactex convert ARGV`."""
    try:
        code = main(['convert', *map(str, argv)])
    except SystemExit as exit_:  # argparse refuses before the command runs
        code = exit_.code
    captured = capsys.readouterr()
    assert 'Traceback' not in captured.out + captured.err
    return code, [line for line in captured.err.splitlines() if line.startswith('error:')]


# -- one rate: kept as measured ------------------------------------------------------------

@pytest.mark.parametrize('rate_hz', [30, 50, 120, 350])
def test_a_recording_at_any_rate_converts_at_its_measured_rate(tmp_path, rate_hz):
    stamps, values = sampled(rate_hz, 2.0)
    record(tmp_path / 'rec', stamps, values)
    data = convert([tmp_path / 'rec'], window=16, hop=16, **QUIET)
    assert data.info['sampling_rate_hz'] == pytest.approx(rate_hz, rel=1e-4)
    (entry,) = data.info['recordings']
    assert entry['rate_hz'] == pytest.approx(rate_hz, rel=1e-4)
    assert 'resampled_from_hz' not in entry
    np.testing.assert_array_equal(data.X[1], values[16:32])  # the samples as recorded


def test_rates_within_five_percent_are_one_rate(tmp_path):
    for trial, rate_hz in enumerate((120.0, 124.0)):  # 3 % apart: clock jitter
        record(tmp_path / f'rec_{trial}', *sampled(rate_hz, 1.0), trial=trial)
    data = convert([tmp_path], window=16, hop=16, **QUIET)
    assert data.info['sampling_rate_hz'] == pytest.approx(122.0, rel=1e-3)


def test_recordings_at_different_rates_stop_with_one_error_naming_rates_and_recordings(
        tmp_path):
    for trial, (name, rate_hz) in enumerate((('wood_0000', 120), ('wood_0001', 120),
                                             ('slow_0000', 30))):
        record(tmp_path / name, *sampled(rate_hz, 2.0), trial=trial)
    expected = ('recordings at different rates: 120 Hz (wood_0000, wood_0001), 30 Hz '
                '(slow_0000); convert them separately or give --resample HZ')
    with pytest.raises(DatasetError, match=re.escape(expected)):
        convert([tmp_path], window=16, hop=16, **QUIET)


def test_a_long_list_of_recordings_at_one_rate_is_shortened_with_its_count():
    rates = [(f'fast_{i}', 350.0) for i in range(5)] + [('slow', 50.0)]
    with pytest.raises(DatasetError, match=re.escape(
            '350 Hz (fast_0, fast_1, fast_2, ... 5 in all), 50 Hz (slow);')):
        common_rate(rates)


# -- resampling: every recording onto the rate asked for -----------------------------------

def test_resampling_30_hz_to_120_hz_follows_the_recorded_sine(tmp_path):
    stamps, values = sampled(30, 4.0, sine(2.0))
    record(tmp_path / 'rec', stamps, values)
    data = convert([tmp_path / 'rec'], window=32, hop=32, resample_hz=120.0, **QUIET)
    assert data.info['sampling_rate_hz'] == 120.0
    (entry,) = data.info['recordings']
    assert entry['rate_hz'] == 120.0
    assert entry['resampled_from_hz'] == pytest.approx(30.0, rel=1e-4)
    np.testing.assert_allclose(np.diff(data.t0), 32 / 120, rtol=1e-6)
    times = seconds_of(data.t0 * 1e9)[:, None] + np.arange(32) / 120
    inner = (times > 0.5) & (times < 3.5)  # the filter's edges left out
    assert inner.sum() > 300
    np.testing.assert_allclose(data.X[:, :, 0][inner], sine(2.0)(times[inner]), atol=0.01)


def test_resampling_350_hz_to_120_hz_leaves_no_alias_of_a_100_hz_sine(tmp_path):
    stamps, values = sampled(350, 5.0, sine(100.0))
    record(tmp_path / 'rec', stamps, values)
    data = convert([tmp_path / 'rec'], window=120, hop=120, resample_hz=120.0, **QUIET)
    inner = data.X[1:-1, :, 0]  # whole seconds away from the edges
    assert len(inner) >= 2
    assert amplitude_at(inner, 20).max() < 0.01  # 100 Hz would fold onto 120 - 100 Hz
    times = data.t0[1:-1, None] + np.arange(120) / 120
    picked = np.interp(times, stamps * 1e-9, values[:, 0])  # no anti-aliasing filter
    assert amplitude_at(picked, 20).min() > 0.5


def test_values_on_both_sides_of_a_gap_never_mix():
    stamps, values = sampled(30, 4.0)
    values[:, 0] = np.where(stamps < START_NS + 2 * 10**9, 0.0, 1.0)  # steps in the gap
    present = (seconds_of(stamps) < 1.5) | (seconds_of(stamps) > 2.5)
    stamps, values = stamps[present], values[present]
    before, after = resample(stamps, values, 30.0, 120.0)
    last, first = stamps[seconds_of(stamps) < 2].max(), stamps[seconds_of(stamps) > 2].min()
    assert before[0][-1] <= last and after[0][0] == first  # nothing made inside the gap
    assert np.all(before[1][:, 0] == 0.0) and np.all(after[1][:, 0] == 1.0)


def test_no_resampled_window_spans_a_gap_shorter_than_the_new_period(tmp_path):
    stamps, values = sampled(350, 6.0)
    present = np.ones(stamps.size, dtype=bool)
    present[1000:1004] = False  # 14 ms missing: less than half a period at 30 Hz
    stamps, values = stamps[present], values[present]
    record(tmp_path / 'rec', stamps, values)
    data = convert([tmp_path / 'rec'], window=8, hop=1, resample_hz=30.0, **QUIET)
    gap_start, gap_end = stamps[999] * 1e-9, stamps[1000] * 1e-9
    ends = data.t0 + 7 / 30
    assert (ends < gap_start).any() and (data.t0 > gap_end).any()
    assert not np.any((data.t0 < gap_end) & (ends > gap_start))


def test_resampled_windows_lie_inside_the_sweep_segments(tmp_path):
    stamps, values = sampled(30, 6.0)
    write_bag(tmp_path / 'rec', stamps, values, metadata={'label': 'wood', 'trial': 0},
              active=[(stamps[30], stamps[119])], live_order=True)
    data = convert([tmp_path / 'rec'], window=16, hop=4, resample_hz=120.0, **QUIET)
    assert len(data.X) > 10
    assert data.t0.min() >= stamps[30] * 1e-9 - 1e-9
    assert (data.t0 + 15 / 120).max() <= stamps[119] * 1e-9 + 1e-9


def test_ground_truth_contact_carries_onto_upsampled_samples(tmp_path):
    stamps, values = sampled(30, 4.0)
    edge = np.zeros((stamps.size, 3))
    edge[:, 0] = 0.015 * seconds_of(stamps)  # sliding at 15 mm/s throughout
    truth = {'contact': np.ones(stamps.size, dtype=bool), 'texture': ['wood'] * stamps.size,
             'edge_m': edge}
    record(tmp_path / 'rec', stamps, values, truth=truth)
    plain = convert([tmp_path / 'rec'], window=16, hop=16, **QUIET).info['recordings'][0]
    upsampled = convert([tmp_path / 'rec'], window=16, hop=16, resample_hz=120.0,
                        **QUIET).info['recordings'][0]
    assert upsampled['kept'] / upsampled['samples'] == pytest.approx(
        plain['kept'] / plain['samples'], abs=0.05)


# -- no contact information: nothing converted unless every sample is asked for ------------

def test_a_recording_without_contact_information_is_skipped_naming_all_samples(tmp_path):
    stamps, values = sampled(120, 2.0)
    record(tmp_path / 'bags' / 'bare', stamps, values, trial=1, swept=False)
    record(tmp_path / 'bags' / 'swept', stamps, values, trial=2)
    data = convert([tmp_path / 'bags'], window=16, hop=16, **QUIET)
    assert set(data.trial) == {2}
    (skipped,) = data.info['skipped']
    assert skipped['path'].endswith('bare') and skipped['reason'] == NO_CONTACT_INFORMATION
    assert '--all-samples' in NO_CONTACT_INFORMATION
    everything = convert([tmp_path / 'bags' / 'bare'], window=16, hop=16, all_samples=True,
                         **QUIET)
    assert len(everything.X) == stamps.size // 16


def test_a_recording_too_short_for_a_window_is_called_short_not_sent_to_all_samples(tmp_path):
    stamps, values = sampled(120, 0.1)
    record(tmp_path / 'bare', stamps, values, swept=False)
    with pytest.raises(DatasetError, match='12 samples, shorter than one window of 16'):
        convert([tmp_path / 'bare'], window=16, hop=16, **QUIET)


# -- the command line ------------------------------------------------------------------------

def test_cli_resamples_and_says_the_rate(tmp_path, capsys):
    record(tmp_path / 'rec', *sampled(30, 4.0))
    code, errors = run_cli(capsys, tmp_path / 'rec', '--out', tmp_path / 'd.npz', '--window',
                           '16', '--resample', '120')
    assert code == 0 and not errors
    sidecar = json.loads((tmp_path / 'd.json').read_text())
    assert sidecar['sampling_rate_hz'] == 120.0
    assert sidecar['recordings'][0]['resampled_from_hz'] == pytest.approx(30.0, rel=1e-4)


def test_cli_mixed_rates_end_in_one_error_line_and_convert_with_resample(tmp_path, capsys):
    record(tmp_path / 'bags' / 'fast', *sampled(120, 2.0), trial=0)
    record(tmp_path / 'bags' / 'slow', *sampled(30, 2.0), trial=1)
    argv = [tmp_path / 'bags', '--out', tmp_path / 'd.npz', '--window', '16']
    code, errors = run_cli(capsys, *argv)
    assert code == 1 and errors == ['error: recordings at different rates: 120 Hz (fast), '
                                    '30 Hz (slow); convert them separately or give '
                                    '--resample HZ']
    assert not (tmp_path / 'd.npz').exists()
    assert run_cli(capsys, *argv, '--resample', '50') == (0, [])


def test_resampling_onto_a_recordings_own_rate_keeps_it(tmp_path, capsys):
    record(tmp_path / 'bags' / 'fast', *sampled(120, 2.0), trial=0)
    record(tmp_path / 'bags' / 'slow', *sampled(30, 2.0), trial=1)
    out = tmp_path / 'd.npz'
    assert run_cli(capsys, tmp_path / 'bags', '--out', out, '--window', '16', '--resample',
                   '120') == (0, [])
    rows = json.loads(out.with_suffix('.json').read_text())['recordings']
    assert len(rows) == 2 and all(row['windows'] > 0 for row in rows)  # none skipped


def test_at_the_measured_rate_resampling_only_makes_the_grid_uniform():
    stamps, values = sampled(120, 1.0)
    period = float(np.diff(stamps)[0])
    jittered = stamps + np.round(np.random.default_rng(0).uniform(-0.2, 0.2, stamps.size)
                                 * period).astype(np.int64)
    jittered[0] = stamps[0]
    [(grid, on_grid)] = resample(jittered, values, 1e9 / period, 1e9 / period)
    assert np.all(np.abs(np.diff(grid) - period) <= 1)  # uniform, at the same rate
    # a ramp interpolated onto the grid: the ramp's value at each grid stamp
    expected = np.interp(grid, jittered, values[:, 0])
    assert np.allclose(on_grid[:, 0], expected)


@pytest.mark.parametrize('rate', ['0', '-30', 'nan', 'inf', 'fast', '1e6'])
def test_cli_refuses_a_resample_rate_that_is_no_rate(tmp_path, capsys, rate):
    record(tmp_path / 'rec', *sampled(30, 1.0))
    code, errors = run_cli(capsys, tmp_path / 'rec', '--out', tmp_path / 'd.npz',
                           '--resample', rate)
    assert code == 1 and len(errors) == 1
    assert errors[0].startswith('error: argument --resample: must be a finite number > 0 and '
                                f"<= 100000, got '{rate}'")


def test_cli_recording_without_contact_information_ends_in_one_error_line(tmp_path, capsys):
    record(tmp_path / 'bare', *sampled(120, 2.0), swept=False)
    code, errors = run_cli(capsys, tmp_path / 'bare', '--out', tmp_path / 'd.npz',
                           '--window', '16')
    assert code == 1 and len(errors) == 1 and '--all-samples' in errors[0]
    assert run_cli(capsys, tmp_path / 'bare', '--out', tmp_path / 'd.npz', '--window', '16',
                   '--all-samples') == (0, [])


# -- the resampling function under any input -------------------------------------------------

@st.composite
def recordings(draw):
    """Increasing stamps around a rate of 10..900 Hz, jittered, with gaps; finite values."""
    rate_hz = draw(st.floats(10.0, 900.0))
    count = draw(st.integers(0, 40))
    steps = draw(st.lists(st.one_of(st.floats(0.9, 1.1), st.sampled_from([3.0, 50.0])),
                          min_size=max(count - 1, 0), max_size=max(count - 1, 0)))
    start = draw(st.integers(-2**62, 2**62))
    stamps = start + np.concatenate([[0], np.cumsum(np.round(np.array(steps) * 1e9 / rate_hz))
                                     ]).astype(np.int64)[:count]
    width = draw(st.integers(1, 3))
    values = np.array(draw(st.lists(finite(), min_size=count * width, max_size=count * width)),
                      dtype=np.float64).reshape(count, width)
    return stamps, values


def measured_rate(stamps_ns, target_hz):
    """What `Recording.rate_hz` says of these stamps, within MAX_RATIO of `target_hz`."""
    rate_hz = Recording(None, stamps_ns, np.zeros((stamps_ns.size, 0)), {}, None,
                        np.zeros(0, np.int64), np.zeros(0)).rate_hz
    assume(stamps_ns.size < 2 or 1 / MAX_RATIO <= target_hz / rate_hz <= MAX_RATIO)
    return rate_hz


@pytest.mark.hard_case
@settings(max_examples=60)
@given(recordings(), st.floats(1.0, 2000.0))
def test_resampling_any_finite_recording_gives_finite_samples_on_consistent_stamps(
        recording, target_hz):
    stamps, values = recording
    measured_hz = measured_rate(stamps, target_hz)
    runs = resample(stamps, values, measured_hz, target_hz)
    if stamps.size < 2:
        assert runs == []
        return
    step_ns = 1e9 / (measured_hz * resampling_ratio(measured_hz, target_hz))
    previous_end = None
    for run_stamps, run_values in runs:
        assert run_stamps.dtype == np.int64 and run_values.shape == (run_stamps.size,
                                                                     values.shape[1])
        assert np.all(np.isfinite(run_values))
        assert stamps[0] <= run_stamps[0] and run_stamps[-1] <= stamps[-1]
        assert previous_end is None or previous_end < run_stamps[0]
        assert np.all(np.abs(np.diff(run_stamps) - step_ns) <= 1.0)
        first, last = np.searchsorted(stamps, [run_stamps[0], run_stamps[-1]])
        assert not gaps(stamps)[first:last].any()  # inside one gap-free run
        previous_end = run_stamps[-1]


@pytest.mark.hard_case
@settings(max_examples=40)
@given(recordings(), st.floats(1.0, 2000.0), finite())
def test_a_constant_channel_stays_exactly_that_constant(recording, target_hz, level):
    stamps, _ = recording
    for _, run_values in resample(stamps, np.full((stamps.size, 1), level),
                                  measured_rate(stamps, target_hz), target_hz):
        assert np.all(run_values == level)


@pytest.mark.parametrize('count', [0, 1])
def test_no_sample_or_one_gives_nothing(count):
    stamps, values = sampled(30, count / 30)
    assert resample(stamps, values, 30.0, 120.0) == []


@pytest.mark.parametrize('measured_hz, target_hz', [(30.0, 30.0 * MAX_RATIO * 1.01),
                                                    (350.0, 350.0 / MAX_RATIO / 1.01),
                                                    (30.0, 0.0), (30.0, float('nan'))])
def test_a_rate_change_beyond_the_limit_is_refused_naming_both_rates(measured_hz, target_hz):
    stamps, values = sampled(measured_hz, 1.0)
    with pytest.raises(ValueError, match=f'cannot resample {measured_hz:g} Hz to '):
        resample(stamps, values, measured_hz, target_hz)


def test_a_kept_sample_carries_only_between_kept_samples():
    stamps = np.array([0, 10, 20, 30])
    mask = np.array([True, True, False, True])
    np.testing.assert_array_equal(carry_mask(mask, stamps, np.array([0, 5, 10, 15, 25, 30])),
                                  [True, True, True, False, False, True])
