# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Datasets recorded elsewhere: the public MUN tactile texture pickles, and folders of CSV.

Both go through the converter's rules: samples are stamped (a timestamp column or
index, else row / rate), aligned and cleaned by `tactex_classify.data.stream_alignment.align`
(NaN rows, and values too large for the dataset's float32, dropped and counted), and
windows never cross a gap (a step over 2.5 periods, `tactex_common.stamps.gaps`), so two
or more dropped rows never stitch two stretches of signal together (one dropped row, a
step of two periods, stays inside a window, as in the converter and the live node) and
`t0` is the true start of each window. Hidden entries (names starting with
'.', such as `.ipynb_checkpoints/` or macOS `._*` files) are skipped and named; every
class found must give at least one window.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, replace
import math
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
from tactex_classify.data.resampling import resample
from tactex_classify.data.stream_alignment import align, Stream
from tactex_classify.errors import DatasetError
from tactex_classify.models.checkpoint import SAMPLING_RATE_RANGE_HZ
from tactex_common.channels import CHANNELS
from tactex_common.constants import FLOAT32_MAX
from tactex_common.errors import TableError
from tactex_common.naming import natural_sorted
from tactex_common.stamps import after_clock_resets, gaps, mean_rate_hz
from tactex_common.tables import read_table

MUN_IMU_COLUMNS = ('imu_ax', 'imu_ay', 'imu_az', 'imu_gx', 'imu_gy', 'imu_gz', 'imu_mx',
                   'imu_my', 'imu_mz')
MUN_RATE_HZ = 350.0
TIME_UNITS_NS = {'s': 1e9, 'ms': 1e6, 'us': 1e3, 'ns': 1.0}
# Files of one dataset may differ in rate by this fraction (clock drift), not more.
RATE_TOLERANCE = 0.02
# Stamps beyond this many nanoseconds from 1970 (about the year 2261) do not fit in int64.
MAX_STAMP_NS = 9.2e18
# Slower than this, a tactile log's time column is in another unit than --time-unit says.
MIN_PLAUSIBLE_RATE_HZ = 1.0
# Faster than this no tactile model is kept (checkpoint.SAMPLING_RATE_RANGE_HZ): another unit.
MAX_RATE_HZ = SAMPLING_RATE_RANGE_HZ[1]
# About the middle of the rates tactile modules stream at (this one: 120-350 Hz).
TACTILE_RATE_HZ = 200.0
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
                dropped: dict[str, int] | None = None, clock_resets: int = 0,
                resample_hz: float | None = None, time_unit: str | None = None) -> float:
    """Align and window one recording, noting what was dropped and what sorted into time order.

    With `time_unit` (its stamps come from a time column in that unit), a rate no tactile
    stream has is refused first. With `resample_hz`, each gap-free run of the aligned
    samples is then resampled onto that rate (`resampling.resample`) before it is windowed.

    Returns:
        Its own sampling rate (mean over the gap-free runs), nan when it gave no window.

    Raises:
        DatasetError: its rate is implausible in `time_unit`, or cannot be resampled onto
            `resample_hz` (the file named).
    """
    streams = [replace(s, values=_beyond_float32_as_inf(s.values)) for s in (stream, *others)]
    aligned = align(streams[0], streams[1:])
    reordered = aligned.reordered
    aligned.dropped.update(dropped or {})
    rate = mean_rate_hz(np.unique(stream.stamps_ns))  # of the clock: drops do not bias it
    if time_unit and np.isfinite(rate):  # a unit mistaken, before anything is resampled
        _check_time_unit({f'{label}/{path.name}': rate}, time_unit)
    runs = [(aligned.stamps_ns, aligned.values)]
    if resample_hz and np.isfinite(rate) and aligned.stamps_ns.size:
        try:
            runs = resample(aligned.stamps_ns, aligned.values, rate, resample_hz)
        except ValueError as err:
            raise DatasetError(f'{path}: {err}') from None
    count = sum(collector.add(label, trial, stamps, values) for stamps, values in runs)
    resampled = sum(int(stamps.size) for stamps, _ in runs)
    kept = int(aligned.stamps_ns.size)
    records.append({'path': str(path), 'label': label, 'trial': trial,
                    'samples': int(stream.stamps_ns.size), 'kept': kept,
                    'longest_run_samples': max((_longest_run(stamps) for stamps, _ in runs
                                                if stamps.size), default=0),
                    'windows': count, 'rate_hz': resample_hz or rate,
                    **({'resampled_from_hz': rate, 'resampled_samples': resampled}
                       if resample_hz else {}),
                    'clock_resets': clock_resets,
                    'dropped': aligned.dropped, 'reordered': reordered})
    lost = {k: v for k, v in aligned.dropped.items() if v}
    moved = {k: v for k, v in reordered.items() if v}
    progress(f'[{trial + 1}] {path}: {label}, {kept} samples, {count} windows'
             + (f', resampled from {rate:.4g} Hz to {resampled} samples' if resample_hz
                else '')
             + (f'; dropped {lost}' if lost else '')
             + (f'; sorted into time order {moved}' if moved else '')
             + (f'; its clock went back {clock_resets} time(s): each part windowed on its '
                'own' if clock_resets else ''))
    return rate if count else float('nan')


def _beyond_float32_as_inf(values: np.ndarray) -> np.ndarray:
    """The values, those too large for the dataset's float32 made inf (dropped as NaN are)."""
    return np.where(np.abs(values) > FLOAT32_MAX, np.inf, values)


def _longest_run(stamps_ns: np.ndarray) -> int:
    """Samples in the longest gap-free stretch of sorted stamps: the largest window it gives."""
    edges = np.concatenate([[0], np.flatnonzero(gaps(stamps_ns)) + 1, [stamps_ns.size]])
    return int(np.max(np.diff(edges)))


def _visible(paths: Iterable[Path], root: Path, progress: Progress) -> list[Path]:
    """The paths with no hidden part below `root` (a name starting with '.'); the rest named.

    A `.ipynb_checkpoints/` folder is no class, and a macOS `._run1.csv` is no recording.
    """
    kept, hidden = [], set()
    for path in paths:
        parts = path.relative_to(root).parts
        first = next((i for i, part in enumerate(parts) if part.startswith('.')), None)
        if first is None:
            kept.append(path)
        else:
            hidden.add('/'.join(parts[:first + 1]) + ('/' if first + 1 < len(parts) else ''))
    if hidden:
        progress(f'skipped hidden entries (names starting with "."): '
                 f'{", ".join(natural_sorted(hidden))}')
    return kept


def _check_windows(classes: Iterable[str], records: Sequence[dict], window: int) -> None:
    """Refuse a dataset without windows, or missing a class found under the root.

    Raises:
        DatasetError: naming --window and the longest gap-free stretch, per class missing.
    """
    longest: dict[str, int | None] = dict.fromkeys(classes)  # None: no file of it was read
    windows = dict.fromkeys(longest, 0)
    for record in records:
        label = record['label']
        longest[label] = max(longest[label] or 0, record['longest_run_samples'])
        windows[label] += record['windows']
    if not records:
        raise DatasetError('no windows: every recording was skipped (see above)')
    if not any(windows.values()):
        raise DatasetError(f'no windows: the longest recording has '
                           f'{max(n for n in longest.values() if n is not None)} samples '
                           f'without a gap, shorter than one window of {window}; give a '
                           'smaller --window')
    empty = [label for label in natural_sorted(windows) if not windows[label]]
    if empty:
        sizes = ', '.join(f'{label} (every file skipped)' if longest[label] is None else
                          f'{label} (longest recording {longest[label]} samples)'
                          for label in empty)
        raise DatasetError(f'no windows of {window} samples for class(es) {sizes}: the dataset '
                           'would miss them (the lines above say what each file kept); give a '
                           'smaller --window, or move those class folders out of the root')


def import_mun(root: Path, *, window: int, hop: int, progress: Progress = _stderr) -> Dataset:
    """The Multimodal Tactile Texture Dataset (doi 10.17632/n666tk4mw9.1, CC BY 4.0).

    Layout: pickles_{30,35,40}/texture_NN/full_baro|full_imu/*.pkl; a trial is the pair
    of baro and imu pickles with the same file name. Rows are stamped by the frames'
    DatetimeIndex (else row / 350 Hz) and the barometer joined to the IMU by time;
    IMU rows without a barometer sample are dropped and counted, never cut silently.
    Values stay in the dataset's units.

    Raises:
        DatasetError: no pickles, a refused or broken pickle, missing columns or text in
            them, a texture without a window, or no window at all.
    """
    check_window(window, hop)
    root = Path(root)
    if not root.is_dir():
        raise DatasetError(f'{root} is not a folder; give the folder holding pickles_*/')
    pairs = natural_sorted(_visible(root.glob('pickles_*/texture_*/full_imu/*.pkl'), root,
                                    progress))
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
                            _numbers(imu_path, imu, MUN_IMU_COLUMNS))
        baro_stream = Stream('baro', CHANNELS[9:], _frame_stamps(baro),
                             _numbers(baro_path, baro, ('baro',)))
        _windows_of(imu_path, label, trial, imu_stream, [baro_stream], collector, records,
                    progress)
    _check_windows({path.parent.parent.name for path in pairs}, records, window)
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


def _numbers(path: Path, frame, columns: Sequence[str]) -> np.ndarray:
    """(rows, len(columns)) float64 of a frame's columns; missing cells are NaN.

    Raises:
        DatasetError: a cell holds something that is not a number (file, column, value).
    """
    import pandas
    values = []
    for column in columns:
        raw = frame[column]
        numbers = pandas.to_numeric(raw, errors='coerce')
        bad = np.flatnonzero(numbers.isna().to_numpy() & raw.notna().to_numpy())
        if bad.size:
            raise DatasetError(f'{path}: column {column!r} holds {str(raw.iloc[bad[0]])!r}, '
                               'not a number')
        values.append(numbers.to_numpy(dtype=np.float64, na_value=np.nan))
    return np.column_stack(values)


def _frame_stamps(frame) -> np.ndarray:
    """Row stamps (ns) from a DatetimeIndex, else row number / the dataset's rate."""
    import pandas
    if isinstance(frame.index, pandas.DatetimeIndex):
        return frame.index.as_unit('ns').asi8.astype(np.int64)
    return np.round(np.arange(len(frame)) * (1e9 / MUN_RATE_HZ)).astype(np.int64)


def import_csv(root: Path, *, window: int, hop: int, columns: Sequence[ChannelSpec] | None = None,
               rate_hz: float | None = None, time_column: str | None = None,
               time_unit: str = 's', delimiter: str | None = None,
               resample_hz: float | None = None, progress: Progress = _stderr) -> Dataset:
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
        resample_hz: put every file onto this rate (files of different rates are
            refused without it).
        progress: receives a line per file.

    Raises:
        DatasetError: no files, an unreadable or ragged file (file and line), a missing
            column, no rate, times beyond int64 nanoseconds in `time_unit`, files of
            different rates, a class without a window, or no window at all.
    """
    check_window(window, hop)
    specs = list(columns) if columns else [ChannelSpec(c, c) for c in CHANNELS]
    for name, given in (('rate', rate_hz), ('resampling rate', resample_hz)):
        if given is not None and not (np.isfinite(given) and given > 0):
            raise DatasetError(f'the {name} must be a finite number > 0 Hz, got {given!r}')
    if rate_hz is None and time_column is None:
        raise DatasetError('give the sampling rate (--rate HZ) or a timestamp column '
                           '(--time COLUMN)')
    if time_unit not in TIME_UNITS_NS:
        raise DatasetError(f'time unit must be one of {", ".join(TIME_UNITS_NS)}')
    root = Path(root)
    if not root.is_dir():
        raise DatasetError(f'{root} is not a folder; give a folder of CLASS/*.csv files')
    files = natural_sorted(_visible((p for p in root.glob('*/*') if p.suffix.lower() == '.csv'
                                     and not p.is_dir()),  # a FIFO is refused when read
                                    root, progress))
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
        try:  # a logger that restarted its clock mid-file: its parts follow each other
            stamps, resets = after_clock_resets(stamps[timed])
        except OverflowError:
            raise DatasetError(f'{path}: its time column restarts so late that the parts do '
                               'not fit in int64 nanoseconds; split the file at the restart'
                               ) from None
        # A row without a time cannot be placed: dropped and counted.
        stream = Stream('rows', tuple(s.name for s in specs), stamps, values[timed])
        rate = _windows_of(path, path.parent.name, trial, stream, [], collector, records,
                           progress, {'rows_without_time': int(np.sum(~timed))}, resets,
                           resample_hz, time_unit if time_column else None)
        if np.isfinite(rate):
            rates[f'{path.parent.name}/{path.name}'] = rate
    _check_windows({path.parent.name for path in files}, records, window)
    if resample_hz:
        _median_rate(rates, rate_hz)  # a --rate beside the time column is still checked
    info_rate = float(resample_hz) if resample_hz else _common_rate(rates, rate_hz)
    return collector.dataset([s.name for s in specs], {
        'sampling_rate_hz': info_rate, 'filter': 'all samples (imported)',
        'source': str(root), 'columns': {s.name: s.column for s in specs},
        'recordings': records, 'skipped': skipped})


def _time_stamps(table, column: str, unit: str) -> tuple[np.ndarray, np.ndarray]:
    """Stamps (int64 ns) of a numeric or date-time column, and which rows have a time.

    Raises:
        TableError: no such column, cells that are neither numbers nor date-times, numbers
            beyond int64 nanoseconds in `unit`, or no time at all.
    """
    try:
        times = table.numeric(column)
    except TableError:
        if column not in table.columns:
            raise
        stamps, valid = _date_time_stamps(table, column)
    else:
        stamps, valid = _numeric_stamps(table, column, times, unit)
    if not valid.any():
        raise TableError(f'{table.path}: time column {column!r} holds no time')
    return stamps, valid


def _numeric_stamps(table, column: str, times: np.ndarray, unit: str
                    ) -> tuple[np.ndarray, np.ndarray]:
    """Stamps (int64 ns) of times in `unit`, and which rows have one (NaN: none).

    Raises:
        TableError: a time beyond int64 nanoseconds, such as epoch ms or ns read as seconds.
    """
    valid = np.isfinite(times)
    scale = TIME_UNITS_NS[unit]
    largest = float(np.max(np.abs(times[valid]), initial=0.0))
    if largest * scale > MAX_STAMP_NS:
        finer = [name for name, ns in TIME_UNITS_NS.items() if ns < scale]
        fix = f'give their unit with --time-unit ({", ".join(finer)})' if finer else \
            'check the column'
        raise TableError(f'{table.path}: time column {column!r} holds values up to '
                         f'{largest:.2g} {unit}, which do not fit in int64 nanoseconds '
                         f'(beyond the year 2261); {fix}')
    return np.round(np.where(valid, times, 0.0) * scale).astype(np.int64), valid


def _date_time_stamps(table, column: str) -> tuple[np.ndarray, np.ndarray]:
    """Stamps (int64 ns) of a date-time column, and which rows have one (empty: none).

    Raises:
        TableError: a cell that is neither a number nor a date-time.
    """
    import pandas
    raw = table.frame[column]
    parsed = pandas.to_datetime(raw, errors='coerce', utc=True, format='mixed')
    valid = parsed.notna().to_numpy()
    bad = np.flatnonzero(~valid & raw.notna().to_numpy())
    if bad.size:
        raise TableError(f'{table.path}, line {int(table.lines[bad[0]])}: time column '
                         f'{column!r} holds {raw.iloc[bad[0]]!r}, neither a number nor a '
                         'date-time')
    stamps = parsed.dt.as_unit('ns').fillna(pandas.Timestamp(0, tz='UTC')).astype(
        'int64').to_numpy()
    return stamps, valid


def _check_time_unit(rates: dict[str, float], unit: str) -> None:
    """Refuse a rate outside MIN_PLAUSIBLE_RATE_HZ..MAX_RATE_HZ: its times are in another unit.

    Raises:
        DatasetError: naming the file, its rate and the --time-unit that fits.
    """
    wrong = [name for name, rate in rates.items()
             if not MIN_PLAUSIBLE_RATE_HZ <= rate <= MAX_RATE_HZ]
    if not wrong:
        return
    rate = rates[wrong[0]]
    speed = 'too slow' if rate < MIN_PLAUSIBLE_RATE_HZ else 'too fast'
    rates_in = {name: rate * TIME_UNITS_NS[unit] / ns for name, ns in TIME_UNITS_NS.items()}
    fitting = [name for name, value in rates_in.items()
               if MIN_PLAUSIBLE_RATE_HZ <= value <= MAX_RATE_HZ]
    # of the units that fit, the one whose rate lies nearest to a tactile stream's
    likely = min(fitting, key=lambda name: abs(math.log(rates_in[name] / TACTILE_RATE_HZ)),
                 default=None)
    raise DatasetError(f'{wrong[0]}: its time column in {unit} gives {rate:.3g} Hz, {speed} for '
                       'a tactile stream; ' + (
                           f'if its times are in {likely}, give --time-unit {likely} '
                           f'({rates_in[likely]:.4g} Hz)' if likely else 'check the time column'))


def _common_rate(rates: dict[str, float], given: float | None) -> float:
    """The dataset's rate: files must agree with each other and with --rate.

    Args:
        rates: CLASS/FILE -> its rate (Hz).
        given: the --rate given, if any.

    Raises:
        DatasetError: naming the two files (or the option) that disagree.
    """
    if not rates:
        return float(given) if given else float('nan')
    names = list(rates)
    low, high = min(names, key=rates.get), max(names, key=rates.get)
    if rates[high] > rates[low] * (1 + RATE_TOLERANCE):
        raise DatasetError(f'files differ in rate by more than {100 * RATE_TOLERANCE:g} %: '
                           f'{low} {rates[low]:.1f} Hz, {high} {rates[high]:.1f} Hz; give '
                           '--resample HZ to put every file onto one rate')
    return _median_rate(rates, given)


def _median_rate(rates: dict[str, float], given: float | None) -> float:
    """The files' median rate (nan for none); a --rate more than RATE_TOLERANCE off refused."""
    rate = float(np.median(list(rates.values()))) if rates else float('nan')
    if given and abs(rate - given) > given * RATE_TOLERANCE:
        raise DatasetError(f'--rate {given:g} Hz disagrees with the time column '
                           f'({rate:.1f} Hz); leave --rate out or fix it')
    return rate
