# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Datasets recorded elsewhere: the public MUN tactile texture pickles, and folders of CSV.

Pickles run code when loaded, so the MUN files go through `SafeUnpickler`, which builds
only the pandas and numpy objects a DataFrame is made of and refuses anything else.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
import io
from pathlib import Path
import pickle
import re
import sys

import numpy as np

from tactex_classify.dataset import Dataset
from tactex_classify.errors import DatasetError
from tactex_common.channels import CHANNELS

# (module, name) a pickled DataFrame may refer to, across pandas 1.x to 3.x and numpy 1/2.
ALLOWED_GLOBALS = frozenset({
    ('builtins', 'slice'), ('__builtin__', 'slice'), ('_codecs', 'encode'),
    ('numpy', 'dtype'), ('numpy', 'ndarray'),
    ('numpy.core.multiarray', '_reconstruct'), ('numpy._core.multiarray', '_reconstruct'),
    ('numpy.core.numeric', '_frombuffer'), ('numpy._core.numeric', '_frombuffer'),
    ('pandas', 'DataFrame'), ('pandas', 'Series'), ('pandas', 'Index'),
    ('pandas', 'RangeIndex'), ('pandas', 'StringDtype'), ('pandas.arrays', 'StringArray'),
    ('pandas.core.frame', 'DataFrame'), ('pandas.core.series', 'Series'),
    ('pandas.core.indexes.base', 'Index'), ('pandas.core.indexes.base', '_new_Index'),
    ('pandas.core.indexes.range', 'RangeIndex'), ('pandas.core.indexes.numeric', 'Int64Index'),
    ('pandas.core.internals.managers', 'BlockManager'),
    ('pandas.core.internals.managers', 'SingleBlockManager'),
    ('pandas.core.internals.blocks', 'new_block'), ('pandas.core.internals.blocks', 'Block'),
    ('pandas._libs.internals', '_unpickle_block'),
    ('pandas._libs.arrays', '__pyx_unpickle_NDArrayBacked'),
})
MUN_IMU_COLUMNS = ('imu_ax', 'imu_ay', 'imu_az', 'imu_gx', 'imu_gy', 'imu_gz', 'imu_mx',
                   'imu_my', 'imu_mz')
MUN_RATE_HZ = 350.0


class RefusedPickle(pickle.UnpicklingError):
    """A pickle asked for something outside the allow-list."""


class SafeUnpickler(pickle.Unpickler):
    """Unpickler that resolves only `ALLOWED_GLOBALS`."""

    def find_class(self, module: str, name: str):
        """Resolve an allowed global, refuse every other."""
        if (module, name) not in ALLOWED_GLOBALS:
            raise RefusedPickle(f'refusing to load {module}.{name} from a pickle: only pandas '
                                'DataFrame parts are allowed')
        return super().find_class(module, name)


def load_frame(path: Path):
    """A pandas DataFrame from a pickle, through `SafeUnpickler`.

    Raises:
        DatasetError: the file is refused, broken, or not a DataFrame.
    """
    import pandas
    try:
        value = SafeUnpickler(io.BytesIO(Path(path).read_bytes())).load()
    except RefusedPickle as err:
        raise DatasetError(f'{path}: {err}') from None
    except (pickle.UnpicklingError, EOFError, AttributeError, TypeError, ValueError) as err:
        raise DatasetError(f'{path}: not a readable pickle: {err}') from None
    if not isinstance(value, pandas.DataFrame):
        raise DatasetError(f'{path}: holds a {type(value).__name__}, not a DataFrame')
    return value


def _windows(values: np.ndarray, window: int, hop: int) -> list[int]:
    return list(range(0, len(values) - window + 1, hop))


def _build(records: Sequence[tuple[str, int, np.ndarray]], window: int, hop: int,
           rate_hz: float, info: dict, progress: Callable[[str], None]) -> Dataset:
    """Windows of (label, trial, values) recordings into a Dataset."""
    X, labels, trials, starts, skipped = [], [], [], [], []
    for label, trial, values in records:
        finite = values[np.all(np.isfinite(values), axis=1)]
        found = _windows(finite, window, hop)
        if not found:
            skipped.append({'trial': trial, 'label': label,
                            'reason': f'{len(finite)} samples, shorter than one window'})
            progress(f'trial {trial} ({label}): {len(finite)} samples < window {window}')
            continue
        for start in found:
            X.append(finite[start:start + window])
            labels.append(label)
            trials.append(trial)
            starts.append(start / rate_hz)
    if not X:
        raise DatasetError('no windows: every recording was shorter than one window')
    classes = sorted(set(labels))
    return Dataset(np.asarray(X, dtype=np.float32),
                   np.array([classes.index(v) for v in labels], dtype=np.int64),
                   np.array(trials, dtype=np.int64), np.array(starts), classes,
                   {'sampling_rate_hz': rate_hz, 'window': window, 'hop': hop,
                    'filter': 'all samples (imported)', 'skipped': skipped, **info})


def import_mun(root: Path, *, window: int, hop: int,
               progress: Callable[[str], None] = lambda line: print(line, file=sys.stderr)
               ) -> Dataset:
    """The Multimodal Tactile Texture Dataset (doi 10.17632/n666tk4mw9.1, CC BY 4.0).

    Layout: pickles_{30,35,40}/texture_NN/full_baro|full_imu/*.pkl; a trial is the pair
    of baro and imu pickles with the same file name. Values stay in the dataset's units.
    """
    root = Path(root)
    pairs = sorted(root.glob('pickles_*/texture_*/full_imu/*.pkl'))
    if not pairs:
        raise DatasetError(f'{root}: no pickles_*/texture_*/full_imu/*.pkl found')
    records = []
    for trial, imu_path in enumerate(pairs):
        baro_path = imu_path.parent.parent / 'full_baro' / imu_path.name
        label = imu_path.parent.parent.name
        if not baro_path.is_file():
            progress(f'{imu_path}: no matching {baro_path.name} in full_baro, skipped')
            continue
        imu, baro = load_frame(imu_path), load_frame(baro_path)
        missing = [c for c in MUN_IMU_COLUMNS if c not in imu.columns]
        if missing or 'baro' not in baro.columns:
            raise DatasetError(f'{imu_path}: missing column(s) {missing or ["baro"]}')
        length = min(len(imu), len(baro))
        values = np.column_stack([imu[list(MUN_IMU_COLUMNS)].to_numpy(float)[:length],
                                  baro['baro'].to_numpy(float)[:length]])
        records.append((label, trial, values))
        progress(f'[{trial + 1}/{len(pairs)}] {imu_path.parent.parent.parent.name}/{label}/'
                 f'{imu_path.name}: {length} samples')
    return _build(records, window, hop, MUN_RATE_HZ,
                  {'source': str(root), 'units': 'as recorded in the MUN dataset'}, progress)


def import_csv(root: Path, *, rate_hz: float, window: int, hop: int,
               columns: Mapping[str, str] | None = None,
               progress: Callable[[str], None] = lambda line: print(line, file=sys.stderr)
               ) -> Dataset:
    """A folder of CSV files, one per trial, class from the parent folder's name.

    Args:
        root: folder of class folders of .csv files (with a header row).
        rate_hz: sampling rate of the files.
        window: samples per window.
        hop: samples between window starts.
        columns: our channel name -> the file's column name (default: the same names).
        progress: receives a line per file.
    """
    mapping = {c: c for c in CHANNELS} | dict(columns or {})
    unknown = sorted(set(mapping) - set(CHANNELS))
    if unknown:
        raise DatasetError(f'unknown channel(s) {unknown} in the column mapping; channels: '
                           f'{", ".join(CHANNELS)}')
    if not rate_hz > 0:
        raise DatasetError(f'rate_hz must be > 0, got {rate_hz!r}')
    files = sorted(Path(root).glob('*/*.csv'))
    if not files:
        raise DatasetError(f'{root}: no CLASS/*.csv files found')
    records = []
    for trial, path in enumerate(files):
        with open(path, encoding='utf-8') as handle:
            header = [name.strip() for name in handle.readline().split(',')]
        missing = [mapping[c] for c in CHANNELS if mapping[c] not in header]
        if missing:
            raise DatasetError(f'{path}: missing column(s) {missing}; map them with --columns')
        table = np.loadtxt(path, delimiter=',', skiprows=1, ndmin=2)
        values = table[:, [header.index(mapping[c]) for c in CHANNELS]]
        records.append((path.parent.name, trial, values))
        progress(f'[{trial + 1}/{len(files)}] {path.parent.name}/{path.name}: '
                 f'{len(values)} samples')
    return _build(records, window, hop, rate_hz, {'source': str(root)}, progress)


def parse_column_mapping(text: str) -> dict[str, str]:
    """'ax=acc_x,ay=acc_y' -> {'ax': 'acc_x', 'ay': 'acc_y'}."""
    mapping = {}
    for item in filter(None, (part.strip() for part in text.split(','))):
        match = re.fullmatch(r'(\w+)=(.+)', item)
        if not match:
            raise DatasetError(f'bad column mapping {item!r}: expected CHANNEL=COLUMN')
        mapping[match.group(1)] = match.group(2).strip()
    return mapping
