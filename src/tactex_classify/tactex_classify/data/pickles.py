# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A restricted unpickler for pickled pandas DataFrames, old pandas layouts included.

Pickles run code when loaded. `SafeUnpickler` resolves only the names a DataFrame of
numbers, with a plain, range or datetime index, is made of: those of pandas 0.15 to 3.x
(`pandas.core.index`, `pandas.tseries.index`, `pandas.indexes.*`, `pandas.core.indexes.*`)
and numpy 1 and 2, read with `encoding='latin1'` so Python 2 pickles load. The
constructors it hands out check their arguments (an index type; a datetime index whose
frequency, if any, is a fixed step of whole hours down to nanoseconds, dropped on load,
and whose time zone is a name, a `zoneinfo` zone or a fixed offset; array shapes and
index lengths within `MAX_ROWS`; `getattr` of nothing but `ZoneInfo._unpickle`), and the
file may be at most `MAX_PICKLE_BYTES`. Every other name is refused before anything runs.
"""

from __future__ import annotations

import io
import math
from pathlib import Path
import pickle

from tactex_common.files import check_regular

MAX_PICKLE_BYTES = 512 * 2**20
MAX_ROWS = 20_000_000
MAX_COLUMNS = 10_000


class RefusedPickle(pickle.UnpicklingError):
    """A pickle asked for something outside the allow-list or beyond the size bounds."""


def _pandas_names() -> dict[tuple[str, str], object]:
    """(module, name) -> the object handed to the unpickler, for every allowed name."""
    import datetime
    import zoneinfo

    import numpy
    from numpy._core import numeric
    import pandas
    from pandas._libs import internals as libinternals
    from pandas._libs.arrays import __pyx_unpickle_NDArrayBacked
    from pandas.core.indexes import base as index_base
    from pandas.core.indexes import datetimes
    from pandas.core.internals import blocks, managers
    from pandas.tseries import offsets
    from pandas.tseries.offsets import Tick

    index_types = (pandas.Index, pandas.RangeIndex, pandas.DatetimeIndex)
    frame_types = (pandas.DataFrame, pandas.Series, managers.BlockManager,
                   managers.SingleBlockManager)

    def new_index(cls, state):
        if cls not in index_types or not isinstance(state, dict):
            raise RefusedPickle(f'refusing an index of type {cls!r}')
        if cls is pandas.RangeIndex:
            span = range(state.get('start', 0), state.get('stop', 0), state.get('step', 1))
            _check_rows(len(span))
        elif 'data' in state:
            _check_rows(len(state['data']))
        return index_base._new_Index(cls, state)

    def new_datetime_index(cls, state):
        if cls is not pandas.DatetimeIndex or not isinstance(state, dict) \
                or not set(state) <= {'data', 'freq', 'tz', 'name'} \
                or not isinstance(state.get('freq'), (Tick, type(None))) \
                or not isinstance(state.get('tz'), (str, type(None))):
            raise RefusedPickle('refusing a datetime index other than timestamps with an '
                                'optional fixed frequency and time zone')
        _check_rows(len(state.get('data', ())))  # the frequency is dropped: stamps suffice
        return datetimes._new_DatetimeIndex(
            cls, {**state, **({'freq': None} if 'freq' in state else {})})

    def fixed_frequency(cls):
        def make(n=1, normalize=False):
            if not isinstance(n, int) or not isinstance(normalize, bool):
                raise RefusedPickle(f'refusing a {cls.__name__} frequency of {n!r}')
            return cls(n, normalize)
        return make

    def fixed_zone(offset, name=None):  # datetime.timezone, e.g. UTC
        if not isinstance(offset, datetime.timedelta) or not isinstance(name, (str, type(None))):
            raise RefusedPickle(f'refusing a time zone of {offset!r}')
        return datetime.timezone(offset) if name is None else datetime.timezone(offset, name)

    def time_step(days=0, seconds=0, microseconds=0):
        if not all(isinstance(part, int) for part in (days, seconds, microseconds)):
            raise RefusedPickle('refusing a timedelta of other than whole numbers')
        return datetime.timedelta(days, seconds, microseconds)

    def zone_getattr(owner, name):  # a time zone pickles as getattr(ZoneInfo, '_unpickle')
        if owner is not zoneinfo.ZoneInfo or name != '_unpickle':
            raise RefusedPickle(f'refusing getattr({owner!r}, {name!r})')
        return zoneinfo.ZoneInfo._unpickle

    def reconstruct(subtype, shape, dtype):
        if subtype is not _NDARRAY or math.prod(shape) > 1:
            raise RefusedPickle('refusing an array constructed outside its saved data')
        return numpy.ndarray.__new__(numpy.ndarray, shape, dtype)

    def reconstructor(cls, base, state):  # protocol 0 and 1 pickles (copy_reg)
        if cls not in frame_types + index_types or base is not object or state is not None:
            raise RefusedPickle(f'refusing to construct {cls!r}')
        return cls.__new__(cls)

    names: dict[tuple[str, str], object] = {
        ('builtins', 'slice'): slice, ('__builtin__', 'slice'): slice,
        ('copyreg', '_reconstructor'): reconstructor,
        ('copy_reg', '_reconstructor'): reconstructor,
        ('_codecs', 'encode'): _encode,
        ('numpy', 'dtype'): numpy.dtype, ('numpy', 'ndarray'): _NDARRAY,
        ('pandas', 'DataFrame'): pandas.DataFrame, ('pandas', 'Series'): pandas.Series,
        ('pandas', 'StringDtype'): pandas.StringDtype,
        ('pandas.arrays', 'StringArray'): pandas.arrays.StringArray,
        ('pandas.arrays', 'DatetimeArray'): pandas.arrays.DatetimeArray,
        ('pandas._libs.arrays', '__pyx_unpickle_NDArrayBacked'): __pyx_unpickle_NDArrayBacked,
        ('pandas._libs.internals', '_unpickle_block'): libinternals._unpickle_block,
        ('pandas.core.internals.blocks', 'new_block'): blocks.new_block,
        ('pandas.core.internals.blocks', 'Block'): blocks.Block,
        ('pandas', 'DatetimeTZDtype'): pandas.DatetimeTZDtype,
        ('zoneinfo', 'ZoneInfo'): zoneinfo.ZoneInfo,
        ('datetime', 'timezone'): fixed_zone, ('datetime', 'timedelta'): time_step,
        ('builtins', 'getattr'): zone_getattr, ('__builtin__', 'getattr'): zone_getattr,
    }
    for name in ('Hour', 'Minute', 'Second', 'Milli', 'Micro', 'Nano'):
        names[('pandas._libs.tslibs.offsets', name)] = fixed_frequency(getattr(offsets, name))
    for numpy_module in ('numpy.core.multiarray', 'numpy._core.multiarray'):
        names[(numpy_module, '_reconstruct')] = reconstruct
    for numpy_module in ('numpy.core.numeric', 'numpy._core.numeric'):
        names[(numpy_module, '_frombuffer')] = numeric._frombuffer  # data from the file
    for module in ('pandas.core.frame', 'pandas'):
        names[(module, 'DataFrame')] = pandas.DataFrame
    names[('pandas.core.series', 'Series')] = pandas.Series
    for module in ('pandas.core.internals', 'pandas.core.internals.managers'):
        names[(module, 'BlockManager')] = managers.BlockManager
        names[(module, 'SingleBlockManager')] = managers.SingleBlockManager
    # Index types and their constructors under every module path pandas used.
    for module in ('pandas', 'pandas.core.index', 'pandas.indexes.base',
                   'pandas.core.indexes.base'):
        names[(module, 'Index')] = pandas.Index
        names[(module, '_new_Index')] = new_index
    for module in ('pandas.core.index', 'pandas.indexes.numeric',
                   'pandas.core.indexes.numeric'):
        names[(module, 'Int64Index')] = pandas.Index  # an Index of int64 since pandas 2
    for module in ('pandas', 'pandas.indexes.range', 'pandas.core.indexes.range'):
        names[(module, 'RangeIndex')] = pandas.RangeIndex
    for module in ('pandas', 'pandas.tseries.index', 'pandas.core.indexes.datetimes'):
        names[(module, 'DatetimeIndex')] = pandas.DatetimeIndex
        names[(module, '_new_DatetimeIndex')] = new_datetime_index
    return names


class _NdarrayToken:
    """Stands for numpy.ndarray where a pickle names it: only `_reconstruct` accepts it."""

    def __repr__(self) -> str:
        return 'numpy.ndarray'


_NDARRAY = _NdarrayToken()


def _encode(text: str, encoding: str = 'latin1') -> bytes:
    """`_codecs.encode` as protocol 2 pickles of bytes use it, for latin-1 only."""
    if encoding not in ('latin1', 'latin-1') or not isinstance(text, str):
        raise RefusedPickle(f'refusing _codecs.encode with {encoding!r}')
    return text.encode('latin1')


def _check_rows(count: int) -> None:
    if count > MAX_ROWS:
        raise RefusedPickle(f'an index of {count} rows is more than the {MAX_ROWS} allowed')


class SafeUnpickler(pickle.Unpickler):
    """Unpickler that resolves only the names of `_pandas_names`."""

    def __init__(self, file, names: dict[tuple[str, str], object]) -> None:
        super().__init__(file, encoding='latin1')
        self._names = names

    def find_class(self, module: str, name: str):
        """Resolve an allowed name, refuse every other."""
        try:
            return self._names[(module, name)]
        except KeyError:
            raise RefusedPickle(f'refusing to load {module}.{name} from a pickle: only the '
                                'parts of a pandas DataFrame are allowed') from None


def load_frame(path: Path):
    """A pandas DataFrame from a pickle file, through `SafeUnpickler`.

    Raises:
        RefusedPickle: a name outside the allow-list, or a size beyond the bounds.
        pickle.UnpicklingError: broken or not a DataFrame (the message says which).
        OSError: the file cannot be read.
    """
    import pandas
    path = Path(path)
    size = check_regular(path)  # a FIFO would block the read below
    if size > MAX_PICKLE_BYTES:
        raise RefusedPickle(f'{size} bytes is more than the {MAX_PICKLE_BYTES} allowed')
    try:
        value = SafeUnpickler(io.BytesIO(path.read_bytes()), _pandas_names()).load()
    except RefusedPickle:
        raise
    except (pickle.UnpicklingError, EOFError, AttributeError, TypeError, ValueError,
            KeyError, IndexError, NotImplementedError, AssertionError) as err:
        raise pickle.UnpicklingError(f'not a readable pickle: {type(err).__name__}: '
                                     f'{err}') from None
    if not isinstance(value, pandas.DataFrame):
        raise pickle.UnpicklingError(f'holds a {type(value).__name__}, not a DataFrame')
    if len(value) > MAX_ROWS or len(value.columns) > MAX_COLUMNS:
        raise RefusedPickle(f'a frame of {value.shape} is beyond the bounds '
                            f'({MAX_ROWS} rows, {MAX_COLUMNS} columns)')
    return value
