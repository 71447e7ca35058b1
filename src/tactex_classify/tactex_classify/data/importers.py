# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Datasets recorded elsewhere: the public MUN tactile texture pickles, and folders of CSV.

Both go through the converter's rules: samples are stamped (a timestamp column or
index, else row / rate), aligned and cleaned by `tactex_classify.data.stream_alignment.align`
(NaN rows dropped and counted), and windows never cross a gap, so a dropped row never
stitches two stretches of signal together and `t0` is the true start of each window.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
import pickle
import sys

import numpy as np

from tactex_classify.data.dataset import (
    check_channel_names,
    check_window,
    Dataset,
    WindowCollector,
)
from tactex_classify.data.pickles import load_frame, RefusedPickle
from tactex_classify.data.stream_alignment import align, median_period_ns, Stream
from tactex_classify.errors import DatasetError
from tactex_common.channels import CHANNELS
from tactex_common.errors import TableError
from tactex_common.naming import natural_sorted
from tactex_common.tables import read_table

MUN_IMU_COLUMNS = ('imu_ax', 'imu_ay', 'imu_az', 'imu_gx', 'imu_gy', 'imu_gz', 'imu_mx',
                   'imu_my', 'imu_mz')
MUN_RATE_HZ = 350.0
TIME_UNITS_NS = {'s': 1e9, 'ms': 1e6, 'us': 1e3, 'ns': 1.0}
# Files of one dataset may differ in rate by this fraction (clock drift), not more.
RATE_TOLERANCE = 0.02
Progress = Callable[[str], None]


def _stderr(line: str) -> None:
    print(line, file=sys.stderr)


@dataclass(frozen=True)
class ChannelSpec:
    """A dataset channel and the file column it is read from."""

    name: str
    column: str


def parse_channel_specs(text: str) -> list[ChannelSpec]:
    """'ax=acc_x,ay=acc_y,pdc' -> the dataset's channels in order, each with its column.

    A name alone reads the column of that name; NAME=COLUMN renames. Any names are
    allowed except empty ones and repeats.

    Raises:
        DatasetError: an empty item, an empty name or column, or a repeated name.
    """
    specs = []
    for item in (part.strip() for part in text.split(',')):
        name, sep, column = (piece.strip() for piece in item.partition('='))
        if not name or (sep and not column):
            raise DatasetError(f'bad --columns item {item!r}: expected NAME or NAME=COLUMN, '
                               'e.g. ax=acc_x,ay=acc_y,az=acc_z')
        specs.append(ChannelSpec(name, column if sep else name))
    check_channel_names([s.name for s in specs])
    return specs


def _windows_of(path: Path, label: str, trial: int, stream: Stream, others: Sequence[Stream],
                collector: WindowCollector, records: list, progress: Progress,
                dropped: dict[str, int] | None = None) -> float:
    """Align and window one recording; return its sampling rate (nan if too short)."""
    aligned = align(stream, others)
    aligned.dropped.update(dropped or {})
    count = collector.add(label, trial, aligned.stamps_ns, aligned.values)
    rate = 1e9 / median_period_ns(aligned.stamps_ns) if aligned.stamps_ns.size > 1 else \
        float('nan')
    records.append({'path': str(path), 'label': label, 'trial': trial,
                    'samples': int(stream.stamps_ns.size), 'kept': int(aligned.stamps_ns.size),
                    'windows': count, 'rate_hz': rate, 'dropped': aligned.dropped})
    lost = {k: v for k, v in aligned.dropped.items() if v}
    progress(f'[{trial + 1}] {path}: {label}, {aligned.stamps_ns.size} samples, {count} '
             f'windows' + (f'; dropped {lost}' if lost else ''))
    return rate if count else float('nan')


def import_mun(root: Path, *, window: int, hop: int, progress: Progress = _stderr) -> Dataset:
    """The Multimodal Tactile Texture Dataset (doi 10.17632/n666tk4mw9.1, CC BY 4.0).

    Layout: pickles_{30,35,40}/texture_NN/full_baro|full_imu/*.pkl; a trial is the pair
    of baro and imu pickles with the same file name. Rows are stamped by the frames'
    DatetimeIndex (else row / 350 Hz) and the barometer joined to the IMU by time;
    IMU rows without a barometer sample are dropped and counted, never cut silently.
    Values stay in the dataset's units.

    Raises:
        DatasetError: no pickles, a refused or broken pickle, missing columns, no window.
    """
    check_window(window, hop)
    root = Path(root)
    if not root.is_dir():
        raise DatasetError(f'{root} is not a folder; give the folder holding pickles_*/')
    pairs = natural_sorted(root.glob('pickles_*/texture_*/full_imu/*.pkl'))
    if not pairs:
        raise DatasetError(f'{root}: no pickles_*/texture_*/full_imu/*.pkl found')
    collector = WindowCollector(window, hop)
    records: list = []
    skipped = []
    for trial, imu_path in enumerate(pairs):
        baro_path = imu_path.parent.parent / 'full_baro' / imu_path.name
        label = imu_path.parent.parent.name
        if not baro_path.is_file():
            skipped.append({'path': str(imu_path), 'reason': f'no {baro_path.name} in '
                            'full_baro'})
            progress(f'{imu_path}: no matching {baro_path.name} in full_baro, skipped')
            continue
        imu, baro = _frame(imu_path), _frame(baro_path)
        missing = [c for c in MUN_IMU_COLUMNS if c not in imu.columns]
        if missing or 'baro' not in baro.columns:
            raise DatasetError(f'{imu_path if missing else baro_path}: missing column(s) '
                               f'{missing or ["baro"]}')
        imu_stream = Stream('imu', CHANNELS[:9], _frame_stamps(imu),
                            imu[list(MUN_IMU_COLUMNS)].to_numpy(np.float64))
        baro_stream = Stream('baro', CHANNELS[9:], _frame_stamps(baro),
                             baro[['baro']].to_numpy(np.float64))
        _windows_of(imu_path, label, trial, imu_stream, [baro_stream], collector, records,
                    progress)
    return collector.dataset(CHANNELS, {
        'sampling_rate_hz': MUN_RATE_HZ, 'filter': 'all samples (imported)',
        'source': str(root), 'units': 'as recorded in the MUN dataset',
        'recordings': records, 'skipped': skipped})


def _frame(path: Path):
    try:
        return load_frame(path)
    except RefusedPickle as err:
        raise DatasetError(f'{path}: {err}') from None
    except pickle.UnpicklingError as err:
        raise DatasetError(f'{path}: {err}') from None
    except OSError as err:
        raise DatasetError(f'{path}: cannot read: {err.strerror}') from None


def _frame_stamps(frame) -> np.ndarray:
    """Row stamps (ns) from a DatetimeIndex, else row number / the dataset's rate."""
    import pandas
    if isinstance(frame.index, pandas.DatetimeIndex):
        return frame.index.as_unit('ns').asi8.astype(np.int64)
    return np.round(np.arange(len(frame)) * (1e9 / MUN_RATE_HZ)).astype(np.int64)


def import_csv(root: Path, *, window: int, hop: int, columns: Sequence[ChannelSpec] | None = None,
               rate_hz: float | None = None, time_column: str | None = None,
               time_unit: str = 's', delimiter: str | None = None,
               progress: Progress = _stderr) -> Dataset:
    """A folder of CSV files, one per trial, class from the parent folder's name.

    Args:
        root: folder of class folders of .csv files (each with a header row).
        window: samples per window.
        hop: samples between window starts.
        columns: the dataset's channels in order, each with its file column (default:
            this system's ten channels, columns of the same names).
        rate_hz: sampling rate, for files without a timestamp column.
        time_column: a column of timestamps (numbers in `time_unit`, or date-times);
            it gives the rate and the gaps.
        time_unit: unit of a numeric time column: s, ms, us or ns.
        delimiter: one character; sniffed from each header when None.
        progress: receives a line per file.

    Raises:
        DatasetError: no files, an unreadable or ragged file (file and line), a missing
            column, no rate, files of different rates, or no window at all.
    """
    check_window(window, hop)
    specs = list(columns) if columns else [ChannelSpec(c, c) for c in CHANNELS]
    if rate_hz is not None and not (np.isfinite(rate_hz) and rate_hz > 0):
        raise DatasetError(f'the rate must be a finite number > 0 Hz, got {rate_hz!r}')
    if rate_hz is None and time_column is None:
        raise DatasetError('give the sampling rate (--rate HZ) or a timestamp column '
                           '(--time COLUMN)')
    if time_unit not in TIME_UNITS_NS:
        raise DatasetError(f'time unit must be one of {", ".join(TIME_UNITS_NS)}')
    root = Path(root)
    if not root.is_dir():
        raise DatasetError(f'{root} is not a folder; give a folder of CLASS/*.csv files')
    files = natural_sorted(p for p in root.glob('*/*') if p.suffix.lower() == '.csv'
                           and not p.is_dir())  # a FIFO or device is refused when read
    if not files:
        raise DatasetError(f'{root}: no CLASS/*.csv files found (one folder per class, '
                           'one file per trial)')
    collector = WindowCollector(window, hop)
    records: list = []
    rates: dict[str, float] = {}
    skipped = []
    for trial, path in enumerate(files):
        try:
            table = read_table(path, delimiter=delimiter)
            if len(table) == 0:
                skipped.append({'path': str(path), 'reason': 'header only, no rows'})
                progress(f'[{trial + 1}] {path}: header only, no rows: skipped')
                continue
            missing = [s.column for s in specs if s.column not in table.columns]
            if missing:
                raise DatasetError(f'{path}: no column(s) {missing}; its columns are '
                                   f'{table.columns}; name them with --columns '
                                   'NAME=COLUMN,...')
            values = np.column_stack([table.numeric(s.column) for s in specs])
            if time_column:
                stamps, timed = _time_stamps(table, time_column, time_unit)
            else:
                stamps = np.round(np.arange(len(table)) * (1e9 / rate_hz)).astype(np.int64)
                timed = np.ones(len(table), dtype=bool)
        except TableError as err:
            raise DatasetError(str(err)) from None
        # A row without a time cannot be placed: dropped and counted.
        stream = Stream('rows', tuple(s.name for s in specs), stamps[timed], values[timed])
        rate = _windows_of(path, path.parent.name, trial, stream, [], collector, records,
                           progress, {'rows_without_time': int(np.sum(~timed))})
        if np.isfinite(rate):
            rates[path.name] = rate
    info_rate = _common_rate(rates, rate_hz)
    return collector.dataset([s.name for s in specs], {
        'sampling_rate_hz': info_rate, 'filter': 'all samples (imported)',
        'source': str(root), 'columns': {s.name: s.column for s in specs},
        'recordings': records, 'skipped': skipped})


def _time_stamps(table, column: str, unit: str) -> tuple[np.ndarray, np.ndarray]:
    """Stamps (int64 ns) of a numeric or date-time column, and which rows have a time.

    Raises:
        TableError: no such column, cells that are neither numbers nor date-times, or no
            time at all.
    """
    import pandas
    try:
        seconds = table.numeric(column)
        valid = np.isfinite(seconds)
        stamps = np.round(np.where(valid, seconds, 0.0) * TIME_UNITS_NS[unit]).astype(np.int64)
    except TableError:
        if column not in table.columns:
            raise
        raw = table.frame[column]
        parsed = pandas.to_datetime(raw, errors='coerce', utc=True, format='mixed')
        valid = parsed.notna().to_numpy()
        bad = np.flatnonzero(~valid & raw.notna().to_numpy())
        if bad.size:
            raise TableError(f'{table.path}, line {int(table.lines[bad[0]])}: time column '
                             f'{column!r} holds {raw.iloc[bad[0]]!r}, neither a number nor a '
                             'date-time') from None
        stamps = parsed.dt.as_unit('ns').fillna(pandas.Timestamp(0, tz='UTC')).astype(
            'int64').to_numpy()
    if not valid.any():
        raise TableError(f'{table.path}: time column {column!r} holds no time')
    return stamps, valid


def _common_rate(rates: dict[str, float], given: float | None) -> float:
    """The dataset's rate: files must agree with each other and with --rate.

    Raises:
        DatasetError: naming the two files (or the option) that disagree.
    """
    if not rates:
        return float(given) if given else float('nan')
    names = list(rates)
    low, high = min(names, key=rates.get), max(names, key=rates.get)
    if rates[high] > rates[low] * (1 + RATE_TOLERANCE):
        raise DatasetError(f'files differ in rate: {low} {rates[low]:.1f} Hz, {high} '
                           f'{rates[high]:.1f} Hz; import them separately')
    rate = float(np.median(list(rates.values())))
    if given and abs(rate - given) > given * RATE_TOLERANCE:
        raise DatasetError(f'--rate {given:g} Hz disagrees with the time column '
                           f'({rate:.1f} Hz); leave --rate out or fix it')
    return rate
