# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Importers: MUN pickles (modern and old pandas layouts) and CSV files as people export them."""

import os
import pickle
import zoneinfo

import numpy as np
import pandas as pd
import pytest
from support.oldpickle import frame_pickle

from tactex.cli import main
from tactex_classify.data import pickles
from tactex_classify.data.importers import (
    import_csv,
    import_mun,
    MUN_IMU_COLUMNS,
    parse_channel_specs,
)
from tactex_classify.data.pickles import load_frame, RefusedPickle
from tactex_classify.errors import DatasetError

QUIET = {'progress': lambda line: None}
PERIOD_NS = 2_857_143  # 350 Hz
START_NS = 1_500_000_000_000_000_000


def mun_folder(root, speed, texture):
    folder = root / f'pickles_{speed}' / f'texture_{texture:02d}'
    (folder / 'full_imu').mkdir(parents=True, exist_ok=True)
    (folder / 'full_baro').mkdir(parents=True, exist_ok=True)
    return folder


def write_mun(root, textures=2, trials=2, samples=800, protocol=4, index=None):
    rng = np.random.default_rng(0)
    for speed in ('30', '40'):
        for texture in range(1, textures + 1):
            folder = mun_folder(root, speed, texture)
            for trial in range(trials):
                imu = pd.DataFrame(rng.normal(texture, 1.0, (samples, 9)),
                                   columns=list(MUN_IMU_COLUMNS), index=index)
                baro = pd.DataFrame({'baro': rng.normal(1000.0, 1.0, samples)}, index=index)
                name = f'trial_{trial}.pkl'
                (folder / 'full_imu' / name).write_bytes(pickle.dumps(imu, protocol=protocol))
                (folder / 'full_baro' / name).write_bytes(pickle.dumps(baro, protocol=protocol))


def write_old_mun_trial(root, texture, imu_values, baro_values, imu_ns, baro_ns, name='t.pkl'):
    """One trial as the public dataset stores it: py2 pickles over a DatetimeIndex."""
    folder = mun_folder(root, '30', texture)
    imu = {column: imu_values[:, i] for i, column in enumerate(MUN_IMU_COLUMNS)}
    (folder / 'full_imu' / name).write_bytes(frame_pickle(imu, imu_ns))
    (folder / 'full_baro' / name).write_bytes(frame_pickle({'baro': baro_values}, baro_ns))


class Boom:
    """Runs a shell command when unpickled."""

    def __reduce__(self):
        return (os.system, ('echo pwned > /tmp/tactex_pwned',))


@pytest.mark.parametrize('protocol', [2, 4, 5])
def test_mun_layout_imports_with_trials_and_classes(tmp_path, protocol):
    write_mun(tmp_path, protocol=protocol)
    data = import_mun(tmp_path, window=350, hop=175, **QUIET)
    assert data.classes == ['texture_01', 'texture_02']
    assert data.X.shape[1:] == (350, 10)
    assert len(set(data.trial.tolist())) == 8  # 2 speeds x 2 textures x 2 trials
    assert data.info['sampling_rate_hz'] == 350.0


def test_modern_pickles_over_a_datetime_index_import(tmp_path):
    write_mun(tmp_path, trials=1, index=pd.DatetimeIndex(START_NS + np.arange(800) * PERIOD_NS))
    data = import_mun(tmp_path, window=350, hop=175, **QUIET)
    assert len(data.X) == 4 * 3


def test_old_pandas_pickle_with_datetime_index_loads(tmp_path):
    stamps = START_NS + np.arange(6) * PERIOD_NS
    path = tmp_path / 'old.pkl'
    path.write_bytes(frame_pickle({'imu_ax': np.arange(6.0), 'imu_ay': -np.arange(6.0)}, stamps))
    frame = load_frame(path)
    assert isinstance(frame.index, pd.DatetimeIndex)
    np.testing.assert_array_equal(frame.index.asi8, stamps)
    np.testing.assert_array_equal(frame['imu_ay'], -np.arange(6.0))



@pytest.mark.parametrize('zone', [None, 'Europe/Berlin', 'UTC', '+02:00'])
@pytest.mark.parametrize('protocol', [2, 5])
def test_a_fixed_frequency_and_time_zone_index_as_pandas_pickles_it_loads(tmp_path, zone,
                                                                          protocol):
    index = pd.date_range('2020-01-01', periods=6, freq='10ms', tz=zone)
    frame = pd.DataFrame({'imu_ax': np.arange(6.0)}, index=index)
    path = tmp_path / 'x.pkl'
    path.write_bytes(pickle.dumps(frame, protocol=protocol))
    loaded = load_frame(path)
    assert (loaded.index == index).all() and str(loaded.index.tz) == str(index.tz)


class OtherZoneInfoAttribute:
    """Asks the unpickler for getattr(ZoneInfo, 'clear_cache'), not the loader a zone needs."""

    def __reduce__(self):
        return (getattr, (zoneinfo.ZoneInfo, 'clear_cache'))


def test_getattr_of_anything_but_the_time_zone_loader_is_refused(tmp_path):
    path = tmp_path / 'x.pkl'
    path.write_bytes(pickle.dumps(OtherZoneInfoAttribute()))
    with pytest.raises(RefusedPickle, match="refusing getattr.*'clear_cache'"):
        load_frame(path)

def test_old_layout_mun_trials_import_and_join_baro_by_time(tmp_path):
    imu_ns = START_NS + np.arange(800) * PERIOD_NS
    imu = np.repeat(np.arange(800.0)[:, None], 9, axis=1)
    baro = 1000.0 + np.arange(800.0)
    for texture in (1, 2):
        write_old_mun_trial(tmp_path, texture, imu, baro, imu_ns, imu_ns + 1_000_000)
    data = import_mun(tmp_path, window=350, hop=175, **QUIET)
    assert data.classes == ['texture_01', 'texture_02'] and len(data.X) == 2 * 3
    np.testing.assert_array_equal(data.X[1, :, 9] - 1000.0, data.X[1, :, 0])  # same rows joined
    np.testing.assert_allclose(data.t0[1], (imu_ns[175]) * 1e-9)


def test_a_baro_table_shorter_than_the_imu_is_reported_not_cut_silently(tmp_path):
    imu_ns = START_NS + np.arange(800) * PERIOD_NS
    imu = np.ones((800, 9))
    write_old_mun_trial(tmp_path, 1, imu, np.full(600, 1000.0), imu_ns, imu_ns[:600])
    lines = []
    data = import_mun(tmp_path, window=350, hop=175, progress=lines.append)
    record = data.info['recordings'][0]
    assert record['dropped']['unaligned_samples'] == 200 and record['kept'] == 600
    assert any('unaligned_samples' in line for line in lines)


def test_mun_windows_never_stitch_across_dropped_nan_rows(tmp_path):
    imu_ns = START_NS + np.arange(800) * PERIOD_NS
    imu = np.repeat(np.arange(800.0)[:, None], 9, axis=1)
    imu[400:405, 3] = np.nan  # the gyro was silent for five samples
    write_old_mun_trial(tmp_path, 1, imu, np.full(800, 1000.0), imu_ns, imu_ns)
    data = import_mun(tmp_path, window=350, hop=175, **QUIET)
    np.testing.assert_array_equal(data.X[:, 0, 0], [0.0, 405.0])
    for window in data.X:  # consecutive samples only: no hole inside a window
        assert np.all(np.diff(window[:, 0]) == 1.0)
    np.testing.assert_allclose(data.t0, imu_ns[[0, 405]] * 1e-9)


def test_malicious_pickle_is_refused_and_runs_nothing(tmp_path):
    write_mun(tmp_path)
    target = next(tmp_path.glob('pickles_30/texture_01/full_imu/*.pkl'))
    target.write_bytes(pickle.dumps(Boom()))
    if os.path.exists('/tmp/tactex_pwned'):
        os.remove('/tmp/tactex_pwned')
    with pytest.raises(DatasetError, match='refusing to load posix.system'):
        import_mun(tmp_path, window=350, hop=175, **QUIET)
    assert not os.path.exists('/tmp/tactex_pwned')


def test_a_pickle_of_something_else_is_refused(tmp_path):
    path = tmp_path / 'x.pkl'
    path.write_bytes(pickle.dumps({'a': 1}))
    with pytest.raises(pickle.UnpicklingError, match='not a DataFrame'):
        load_frame(path)
    path.write_bytes(b'not a pickle')
    with pytest.raises(pickle.UnpicklingError, match='not a readable pickle'):
        load_frame(path)


@pytest.mark.parametrize('build', [
    lambda: pickle.dumps(pd.DataFrame(index=pd.RangeIndex(10**12))),
    lambda: pickle.dumps(pd.Series([1.0])),
    lambda: pickle.dumps(np.arange(3.0)),
    lambda: frame_pickle({'a': np.zeros(3)}, START_NS + np.arange(3), freq='L'),
], ids=['huge-range-index', 'series', 'bare-array', 'frequency-given-as-text'])
def test_pickles_beyond_a_plain_frame_are_refused(tmp_path, build):
    path = tmp_path / 'x.pkl'
    path.write_bytes(build())
    with pytest.raises(pickle.UnpicklingError):
        load_frame(path)


def test_a_pickle_constructing_an_array_of_its_own_size_is_refused(tmp_path):
    data = pickle.dumps(np.zeros(3), protocol=2).replace(b'K\x00\x85', b'J\x00\x00\x00\x40\x85')
    path = tmp_path / 'x.pkl'
    path.write_bytes(data)
    with pytest.raises(RefusedPickle, match='outside its saved data'):
        load_frame(path)


def test_a_pickle_larger_than_the_bound_is_refused_unread(tmp_path, monkeypatch):
    write_mun(tmp_path, textures=1, trials=1)
    monkeypatch.setattr(pickles, 'MAX_PICKLE_BYTES', 1000)
    with pytest.raises(DatasetError, match='more than the 1000 allowed'):
        import_mun(tmp_path, window=350, hop=175, **QUIET)


# -- CSV --------------------------------------------------------------------------------

FOREIGN_HEADER = '"Zeit [s]";"acc_x";"acc_y";"acc_z";"Druck (hPa)";'


def foreign_csv(rows: int, *, start: float = 0.0, period: float = 0.01, nan_rows=()) -> bytes:
    """A European spreadsheet export.

    UTF-8 BOM, ';' delimiters, a quoted header, CRLF, decimal commas, a trailing ';'
    on every row, 'n/a' cells.
    """
    lines = [FOREIGN_HEADER]
    for i in range(rows):
        cells = [f'{start + i * period:.4f}', f'{i},5', f'{-i}', '9,81', f'{1013 + i * 0.01:.2f}']
        if i in nan_rows:
            cells[2] = 'n/a'
        lines.append(';'.join(c.replace('.', ',') for c in cells) + ';')
    return '\ufeff'.encode() + '\r\n'.join(lines).encode('utf-8') + b'\r\n'


def test_a_foreign_csv_layout_imports_with_renamed_channels(tmp_path):
    for label in ('mat2', 'mat10'):
        (tmp_path / label).mkdir()
        (tmp_path / label / 'trial_1.csv').write_bytes(foreign_csv(300))
    specs = parse_channel_specs('ax=acc_x, ay=acc_y, az=acc_z, baro=Druck (hPa)')
    data = import_csv(tmp_path, window=100, hop=50, columns=specs, time_column='Zeit [s]',
                      **QUIET)
    assert data.channels == ['ax', 'ay', 'az', 'baro']
    assert data.classes == ['mat2', 'mat10']  # natural order
    assert data.X.shape == (2 * 5, 100, 4)
    np.testing.assert_allclose(data.X[0, :3, 0], [0.5, 1.5, 2.5])
    np.testing.assert_allclose(data.X[0, 0, 2], 9.81, rtol=1e-6)
    assert data.info['sampling_rate_hz'] == pytest.approx(100.0)


def test_latin1_csv_and_tab_delimiter_given(tmp_path):
    (tmp_path / 'wood').mkdir()
    text = 'temp°C\tpdc\tpac1\n' + ''.join(f'{i}\t{i * 2}\t{i * 3}\n' for i in range(50))
    (tmp_path / 'wood' / 'a.csv').write_bytes(text.encode('latin-1'))
    data = import_csv(tmp_path, window=10, hop=10, columns=parse_channel_specs('pdc,pac1'),
                      rate_hz=2200.0, delimiter='\t', **QUIET)
    assert data.channels == ['pdc', 'pac1'] and data.X.shape == (5, 10, 2)
    np.testing.assert_array_equal(data.X[1, 0], [20.0, 30.0])


def test_csv_nan_rows_are_dropped_and_windows_respect_the_gap(tmp_path):
    (tmp_path / 'wood').mkdir()
    (tmp_path / 'wood' / 'a.csv').write_bytes(foreign_csv(300, nan_rows=range(100, 105)))
    specs = parse_channel_specs('ax=acc_x,ay=acc_y')
    data = import_csv(tmp_path, window=100, hop=100, columns=specs, time_column='Zeit [s]',
                      **QUIET)
    np.testing.assert_allclose(data.t0, [0.0, 1.05])  # row 105 restarts after the gap
    assert data.info['recordings'][0]['dropped']['nan_samples'] == 5


def test_a_timestamp_column_gives_rate_and_gaps(tmp_path):
    (tmp_path / 'wood').mkdir()
    first = foreign_csv(150, period=0.004).decode('utf-8-sig')
    second = foreign_csv(150, start=10.0, period=0.004).decode('utf-8-sig').split('\r\n', 1)[1]
    (tmp_path / 'wood' / 'a.csv').write_text(first + second, encoding='utf-8')
    data = import_csv(tmp_path, window=100, hop=50, columns=parse_channel_specs('ax=acc_x'),
                      time_column='Zeit [s]', **QUIET)
    assert data.info['sampling_rate_hz'] == pytest.approx(250.0)
    np.testing.assert_allclose(data.t0, [0.0, 0.2, 10.0, 10.2])  # nothing spans the jump


def test_date_time_stamps_are_read(tmp_path):
    (tmp_path / 'wood').mkdir()
    stamps = pd.date_range('2024-03-01 12:00', periods=40, freq='10ms')
    rows = ''.join(f'{s.isoformat()},{i}\n' for i, s in enumerate(stamps))
    (tmp_path / 'wood' / 'a.csv').write_text('time,pdc\n' + rows)
    data = import_csv(tmp_path, window=20, hop=20, columns=parse_channel_specs('pdc'),
                      time_column='time', **QUIET)
    assert data.info['sampling_rate_hz'] == pytest.approx(100.0) and len(data.X) == 2


def test_header_only_files_are_skipped_and_named(tmp_path):
    (tmp_path / 'wood').mkdir()
    (tmp_path / 'wood' / 'a.csv').write_text('pdc\n' + ''.join(f'{i}\n' for i in range(30)))
    (tmp_path / 'wood' / 'b.csv').write_text('pdc\n')
    data = import_csv(tmp_path, window=10, hop=10, columns=parse_channel_specs('pdc'),
                      rate_hz=100.0, **QUIET)
    assert len(data.X) == 3 and data.info['skipped'][0]['path'].endswith('b.csv')


@pytest.mark.parametrize('content, match', [
    (b'pdc,pac\n1,2\n3,4,5,6\n', r'a\.csv, line 3: 4 fields, but the header has 2'),
    (b'pdc,pac\n1,2\n3\n', r'a\.csv, line 3: 1 fields'),
    (b'pdc,pac\n1,2\n3,x\n', r"a\.csv, line 3: column 'pac' holds 'x', not a number"),
    (b'\x00\x01\x02binary', 'binary file'),
    (b'pdc,pdc\n1,2\n', 'appear twice'),
    (b'', 'empty file'),
], ids=['long-row', 'short-row', 'text-cell', 'binary', 'repeated-column', 'empty'])
def test_unreadable_csv_names_file_and_line(tmp_path, content, match):
    (tmp_path / 'wood').mkdir()
    (tmp_path / 'wood' / 'a.csv').write_bytes(content)
    with pytest.raises(DatasetError, match=match):
        import_csv(tmp_path, window=2, hop=1, columns=parse_channel_specs('pdc,pac'),
                   rate_hz=100.0, **QUIET)


def test_missing_columns_and_bad_specs_are_explained(tmp_path):
    (tmp_path / 'wood').mkdir()
    (tmp_path / 'wood' / 'a.csv').write_text('acc_x,acc_y\n1,2\n')
    with pytest.raises(DatasetError, match=r"no column\(s\) \['ax', 'ay'.*acc_x.*--columns"):
        import_csv(tmp_path, window=2, hop=1, rate_hz=100.0, **QUIET)
    with pytest.raises(DatasetError, match='repeat'):
        parse_channel_specs('ax=acc_x,ax=acc_y')
    with pytest.raises(DatasetError, match='NAME or NAME=COLUMN'):
        parse_channel_specs('ax=,ay')


def test_files_of_different_rates_are_refused(tmp_path):
    (tmp_path / 'wood').mkdir()
    (tmp_path / 'wood' / 'a.csv').write_bytes(foreign_csv(50, period=0.01))
    (tmp_path / 'wood' / 'b.csv').write_bytes(foreign_csv(50, period=0.02))
    with pytest.raises(DatasetError, match='differ in rate'):
        import_csv(tmp_path, window=10, hop=10, columns=parse_channel_specs('ax=acc_x'),
                   time_column='Zeit [s]', **QUIET)


def test_cli_import(tmp_path, capsys):
    write_mun(tmp_path / 'mun')
    assert main(['import', 'mun', str(tmp_path / 'mun'), '--out', str(tmp_path / 'm.npz'),
                 '--window', '350']) == 0
    assert 'wrote' in capsys.readouterr().out
    (tmp_path / 'csv' / 'wood').mkdir(parents=True)
    (tmp_path / 'csv' / 'wood' / 'a.csv').write_bytes(foreign_csv(300))
    assert main(['import', 'csv', str(tmp_path / 'csv'), '--out', str(tmp_path / 'c.npz'),
                 '--columns', 'ax=acc_x,ay=acc_y,az=acc_z', '--time', 'Zeit [s]',
                 '--window', '100']) == 0
    assert '1 class, 1 recording, channels ax,ay,az, 100 Hz' in capsys.readouterr().out


def test_mun_plain_frames_never_stitch_across_nan_rows_and_keep_t0(tmp_path):
    write_mun(tmp_path, textures=1, trials=1)
    path = next(tmp_path.glob('pickles_30/texture_01/full_imu/*.pkl'))
    frame = pd.read_pickle(path)
    frame.iloc[:, 0] = np.arange(800.0)
    frame.iloc[400:405, 3] = np.nan
    path.write_bytes(pickle.dumps(frame))
    data = import_mun(tmp_path, window=350, hop=175, **QUIET)
    first = data.trial == data.trial.min()
    np.testing.assert_array_equal(data.X[first, 0, 0], [0.0, 405.0])
    np.testing.assert_allclose(data.t0[first], [0.0, 405 / 350.0])


# -- Red-team findings: text in pickles, huge values and times, hidden entries, classes
# without windows, rounded stamps, sorted rows, an existing --out ----------------------

def write_csv(path, times, values, header='time,pdc'):
    """A CSV of a time column and one value column."""
    path.parent.mkdir(parents=True, exist_ok=True)
    rows = ''.join(f'{t},{v}\n' for t, v in zip(times, values, strict=True))
    path.write_text(f'{header}\n{rows}')


def write_ramps(root, classes, rows=100, rate_hz=100.0):
    """One CSV of `rows` samples (time in s, pdc a ramp) per class."""
    for label in classes:
        write_csv(root / label / 'a.csv', np.arange(rows) / rate_hz, np.arange(rows))


def import_ramps(root, window=10, **options):
    return import_csv(root, window=window, hop=window, columns=parse_channel_specs('pdc'),
                      time_column='time', **{**QUIET, **options})


def test_text_in_a_pickle_column_is_refused_naming_file_column_and_value(tmp_path):
    write_mun(tmp_path, textures=1, trials=1)
    path = next(tmp_path.glob('pickles_30/texture_01/full_imu/*.pkl'))
    frame = pd.read_pickle(path)
    frame['imu_ax'] = frame['imu_ax'].astype(str)
    frame.iloc[5, 0] = 'oops'
    path.write_bytes(pickle.dumps(frame))
    with pytest.raises(DatasetError, match=r"full_imu/trial_0\.pkl: column 'imu_ax' holds "
                                           r"'oops', not a number"):
        import_mun(tmp_path, window=350, hop=175, **QUIET)


@pytest.mark.filterwarnings('error')
def test_csv_values_beyond_float32_are_dropped_and_counted_as_nan_samples(tmp_path):
    values = np.arange(100.0)
    values[[20, 70]] = [3e39, -1e300]
    write_csv(tmp_path / 'wood' / 'a.csv', np.arange(100) / 100.0, values)
    data = import_ramps(tmp_path)
    assert np.all(np.isfinite(data.X)) and np.all(np.abs(data.X) < 100)
    record = data.info['recordings'][0]
    assert record['dropped']['nan_samples'] == 2 and record['kept'] == 98


@pytest.mark.filterwarnings('error')
def test_mun_values_beyond_float32_are_dropped_and_counted_as_nan_samples(tmp_path):
    write_mun(tmp_path, textures=1, trials=1)
    path = next(tmp_path.glob('pickles_30/texture_01/full_imu/*.pkl'))
    frame = pd.read_pickle(path)
    frame.iloc[10, 3] = 1e300
    path.write_bytes(pickle.dumps(frame))
    data = import_mun(tmp_path, window=350, hop=175, **QUIET)
    assert np.all(np.isfinite(data.X))
    assert data.info['recordings'][0]['dropped']['nan_samples'] == 1


@pytest.mark.filterwarnings('error')
@pytest.mark.parametrize('start, unit', [(1.7e18, 's'), (1.7e12, 's'), (1.7e15, 'ms')],
                         ids=['epoch-ns-as-s', 'epoch-ms-as-s', 'epoch-us-as-ms'])
def test_times_beyond_int64_nanoseconds_are_refused_with_the_unit_to_give(tmp_path, start,
                                                                           unit):
    write_csv(tmp_path / 'wood' / 'a.csv', start + np.arange(100), np.arange(100))
    with pytest.raises(DatasetError, match=rf"a\.csv: time column 'time' holds values up to "
                                           rf"1\.7e\+\d\d {unit}, which do not fit .*"
                                           r'--time-unit \(.*ns\)'):
        import_ramps(tmp_path, time_unit=unit)


def test_epoch_nanoseconds_import_with_time_unit_ns(tmp_path):
    write_csv(tmp_path / 'wood' / 'a.csv', START_NS + np.arange(100) * 10_000_000,
              np.arange(100))
    data = import_ramps(tmp_path, time_unit='ns')
    assert data.info['sampling_rate_hz'] == pytest.approx(100.0) and len(data.X) == 10



def test_milliseconds_read_as_seconds_are_refused_with_the_unit_that_fits(tmp_path):
    write_csv(tmp_path / 'wood' / 'a.csv', np.arange(100) * 10, np.arange(100))
    with pytest.raises(DatasetError, match=r'wood/a.csv: its time column in s gives 0.1 Hz, too '
                       r'slow for a tactile stream; if its times are in ms, give --time-unit '
                       r'ms \(100 Hz\)'):
        import_ramps(tmp_path)
    assert import_ramps(tmp_path, time_unit='ms').info['sampling_rate_hz'] == \
        pytest.approx(100.0)

def test_milliseconds_read_as_nanoseconds_are_refused_with_the_unit_that_fits(tmp_path):
    write_csv(tmp_path / 'wood' / 'a.csv', np.arange(100) * 10, np.arange(100))
    with pytest.raises(DatasetError, match=r'wood/a.csv: its time column in ns gives 1e\+08 Hz, '
                       r'too fast for a tactile stream; if its times are in ms, give '
                       r'--time-unit ms \(100 Hz\)'):
        import_ramps(tmp_path, time_unit='ns')


def test_a_clock_that_restarts_mid_file_gives_parts_windowed_on_their_own(tmp_path):
    times = np.concatenate([np.arange(50) + 1000.0, np.arange(50)]) * 4  # ms, back 4 s
    write_csv(tmp_path / 'wood' / 'a.csv', times, np.arange(100))
    lines = []
    data = import_ramps(tmp_path, time_unit='ms', progress=lines.append)
    assert data.info['sampling_rate_hz'] == pytest.approx(250.0)
    assert data.info['recordings'][0]['clock_resets'] == 1
    assert 'its clock went back 1 time(s): each part windowed on its own' in lines[0]
    # each window holds one part's ramp in order: no sample of the other part between
    assert len(data.X) == 10 and np.all(np.diff(data.X[:, :, 0], axis=1) == 1)


def rated_files(root, rates_hz):
    """One CSV (time in s, pdc a ramp) of 200 rows per rate, in one class folder."""
    for index, rate in enumerate(rates_hz):
        write_csv(root / 'wood' / f'{index}.csv', np.arange(200) / rate, np.arange(200))


def test_files_of_rates_further_apart_than_the_tolerance_are_refused_with_resample(tmp_path):
    rated_files(tmp_path, [247.5, 250.0, 252.5, 255.0])
    with pytest.raises(DatasetError, match=r'files differ in rate by more than 2 %: wood/0.csv '
                                           r'247.5 Hz, wood/3.csv 255.0 Hz; give --resample HZ'):
        import_ramps(tmp_path)


def test_resample_puts_every_file_onto_one_rate(tmp_path):
    rated_files(tmp_path, [247.5, 255.0])
    lines = []
    data = import_ramps(tmp_path, resample_hz=250.0, progress=lines.append)
    assert data.info['sampling_rate_hz'] == 250.0
    rows = data.info['recordings']
    assert [row['resampled_from_hz'] for row in rows] == pytest.approx([247.5, 255.0])
    assert {row['rate_hz'] for row in rows} == {250.0} and 'resampled from 247.5 Hz' in lines[0]
    assert [row['kept'] for row in rows] == [200, 200]  # rows of the file, as without
    # 200 rows over 0.80 s and 0.78 s: about 201 and 196 samples at 250 Hz
    assert [row['resampled_samples'] for row in rows] == [pytest.approx(201, abs=1),
                                                          pytest.approx(196, abs=1)]


def test_a_time_unit_mistaken_is_refused_before_any_file_is_resampled(tmp_path):
    rated_files(tmp_path, [250.0])  # seconds, read as milliseconds: 250 kHz
    with pytest.raises(DatasetError, match=r'wood/0.csv: its time column in ms gives 2.5e\+05 '
                                           r'Hz, too fast .*give --time-unit s \(250 Hz\)'):
        import_ramps(tmp_path, time_unit='ms', resample_hz=250.0)


def test_with_resample_a_rate_given_beside_the_time_column_is_still_checked(tmp_path):
    rated_files(tmp_path, [250.0])
    with pytest.raises(DatasetError, match='--rate 100 Hz disagrees with the time column'):
        import_ramps(tmp_path, rate_hz=100.0, resample_hz=250.0)
    with pytest.raises(DatasetError, match='resampling rate must be a finite number > 0 Hz'):
        import_ramps(tmp_path, resample_hz=0.0)


def test_hidden_folders_and_files_are_skipped_and_named(tmp_path):
    write_ramps(tmp_path, ['cork', 'felt'])
    write_ramps(tmp_path / '.ipynb_checkpoints', ['cork'])
    (tmp_path / '.ipynb_checkpoints' / 'a.csv').write_text('time,pdc\n0,1\n')
    (tmp_path / 'cork' / '._a.csv').write_bytes(b'\x00\x05\x16\x07AppleDouble')
    lines = []
    data = import_ramps(tmp_path, progress=lines.append)
    assert data.classes == ['cork', 'felt'] and len(set(data.trial.tolist())) == 2
    assert 'skipped hidden entries (names starting with "."): .ipynb_checkpoints/, ' \
           'cork/._a.csv' in lines


def test_hidden_mun_pickles_are_skipped_and_named(tmp_path):
    write_mun(tmp_path, textures=1, trials=1)
    folder = mun_folder(tmp_path, '30', 1)
    for part in ('full_imu', 'full_baro'):
        (folder / part / '._trial_0.pkl').write_bytes(b'\x00\x05\x16\x07AppleDouble')
    lines = []
    data = import_mun(tmp_path, window=350, hop=175, progress=lines.append)
    assert len(set(data.trial.tolist())) == 2
    assert any('pickles_30/texture_01/full_imu/._trial_0.pkl' in line for line in lines)


def test_a_class_without_windows_is_refused_by_name_and_per_file_lines_kept(tmp_path):
    write_ramps(tmp_path, ['cork', 'felt'], rows=300)
    write_ramps(tmp_path, ['wood'], rows=99)
    lines = []
    with pytest.raises(DatasetError, match=r'no windows of 256 samples for class\(es\) wood '
                                           r'\(longest recording 99 samples\).*smaller '
                                           '--window'):
        import_ramps(tmp_path, window=256, progress=lines.append)
    assert any('wood/a.csv: wood, 99 samples, 0 windows' in line for line in lines)


def test_a_mun_texture_without_windows_is_refused_by_name(tmp_path):
    write_mun(tmp_path, textures=1, trials=1)
    write_old_mun_trial(tmp_path, 2, np.ones((100, 9)), np.ones(100),
                        START_NS + np.arange(100) * PERIOD_NS, START_NS + np.arange(100) *
                        PERIOD_NS)
    with pytest.raises(DatasetError, match=r'class\(es\) texture_02 \(longest recording 100 '
                                           r'samples\)'):
        import_mun(tmp_path, window=350, hop=175, **QUIET)


def test_no_windows_at_all_names_window_and_the_longest_recording(tmp_path):
    write_ramps(tmp_path, ['cork'], rows=300)
    write_ramps(tmp_path, ['felt'], rows=200)
    with pytest.raises(DatasetError, match='no windows: the longest recording has 300 samples '
                                           'without a gap, shorter than one window of 5000; '
                                           'give a smaller --window'):
        import_ramps(tmp_path, window=5000)


def test_whitespace_only_lines_are_skipped_like_empty_ones(tmp_path):
    write_ramps(tmp_path, ['wood'])
    path = tmp_path / 'wood' / 'a.csv'
    lines = path.read_text().splitlines(keepends=True)
    path.write_text(''.join(lines[:30] + ['   \n', '\n', ' \t \n'] + lines[30:]))
    data = import_ramps(tmp_path)
    assert len(data.X) == 10
    np.testing.assert_array_equal(data.X[:, 0, 0], np.arange(0, 100, 10))


def test_the_rate_of_millisecond_rounded_stamps_is_the_true_rate(tmp_path):
    times_ms = np.round(np.arange(2000) * 1000 / 350)  # 350 Hz logged in whole milliseconds
    write_csv(tmp_path / 'wood' / 'a.csv', times_ms.astype(int), np.arange(2000))
    data = import_ramps(tmp_path, time_unit='ms')
    assert data.info['sampling_rate_hz'] == pytest.approx(350.0, rel=1e-3)


def test_rows_sorted_into_time_order_are_reported_not_dropped(tmp_path):
    order = np.random.default_rng(1).permutation(100)
    write_csv(tmp_path / 'wood' / 'a.csv', (np.arange(100) / 100.0)[order], order)
    lines = []
    data = import_ramps(tmp_path, progress=lines.append)
    record = data.info['recordings'][0]
    came_late = int(np.sum(order[1:] < np.maximum.accumulate(order)[:-1]))
    assert record['kept'] == 100 and record['reordered'] == {'rows': came_late}
    assert not any(record['dropped'].values()) and 'out_of_order' not in str(record['dropped'])
    np.testing.assert_array_equal(data.X[:, :, 0].ravel(), np.arange(100))
    assert 'sorted into time order' in lines[0] and 'dropped' not in lines[0]


def test_files_of_different_rates_are_named_with_their_class(tmp_path):
    write_csv(tmp_path / 'cork' / 'run1.csv', np.arange(100) / 100.0, np.arange(100))
    write_csv(tmp_path / 'felt' / 'run1.csv', np.arange(100) / 50.0, np.arange(100))
    with pytest.raises(DatasetError, match='differ in rate by more than 2 %: felt/run1.csv '
                                           '50.0 Hz, cork/run1.csv 100.0 Hz'):
        import_ramps(tmp_path)


def test_cli_import_refuses_an_existing_out_unless_forced(tmp_path, capsys):
    write_ramps(tmp_path / 'csv', ['wood'])
    argv = ['import', 'csv', str(tmp_path / 'csv'), '--out', str(tmp_path / 'd.npz'),
            '--columns', 'pdc', '--time', 'time', '--window', '10']
    assert main(argv) == 0
    (tmp_path / 'd.npz').write_bytes(b'mine')
    assert main(argv) == 1
    assert capsys.readouterr().err.splitlines()[-1] == (
        f'error: --out {tmp_path / "d.npz"} exists; give --force to replace it, or another '
        '--out')
    assert (tmp_path / 'd.npz').read_bytes() == b'mine'
    assert main([*argv, '--force']) == 0 and (tmp_path / 'd.npz').read_bytes() != b'mine'
