# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Pickles laid out as Python 2 with pandas 0.16-0.19 wrote them, built from opcodes.

A modern pandas cannot write this layout: module paths `pandas.core.index`,
`pandas.tseries.index` and `pandas.core.internals`, numpy arrays whose raw data are
Python 2 `str` (read back with encoding='latin1'), and a DataFrame state dict holding
a BlockManager in its 0.14.1 layout. `frame_pickle` writes such a file for a frame of
float columns over a DatetimeIndex, as the public MUN dataset's pickles are.
"""

import struct

import numpy as np


def _text(value: str | bytes) -> bytes:
    """A Python 2 str: SHORT_BINSTRING or BINSTRING."""
    raw = value.encode('latin1') if isinstance(value, str) else value
    if len(raw) < 256:
        return b'U' + bytes([len(raw)]) + raw
    return b'T' + struct.pack('<I', len(raw)) + raw


def _value(value) -> bytes:
    if value is None:
        return b'N'
    if value is True or value is False:
        return b'\x88' if value else b'\x89'
    if isinstance(value, int):
        return b'J' + struct.pack('<i', value)
    if isinstance(value, (str, bytes)):
        return _text(value)
    if isinstance(value, tuple):
        return b'(' + b''.join(map(_value, value)) + b't'
    if isinstance(value, list):
        return b']' + (b'(' + b''.join(map(_value, value)) + b'e' if value else b'')
    if isinstance(value, dict):
        return b'}' + (b'(' + b''.join(_value(k) + _value(v) for k, v in value.items())
                       + b'u' if value else b'')
    if isinstance(value, Raw):
        return value.data
    raise TypeError(type(value))


class Raw:
    """Opcodes inserted as they are."""

    def __init__(self, data: bytes) -> None:
        self.data = data


def _global(module: str, name: str) -> bytes:
    return b'c' + module.encode() + b'\n' + name.encode() + b'\n'


def _call(module: str, name: str, *args) -> Raw:
    return Raw(_global(module, name) + _value(tuple(args)) + b'R')


def _dtype(code: str, state: tuple) -> Raw:
    return Raw(_call('numpy', 'dtype', code, 0, 1).data + _value(state) + b'b')


def _array(values: np.ndarray) -> Raw:
    """numpy.core.multiarray._reconstruct + BUILD with the raw data as a py2 str."""
    values = np.asarray(values)
    if values.dtype.kind == 'f':
        dtype, data = _dtype('f8', (3, '<', None, None, None, -1, -1, 0)), \
            values.astype('<f8').tobytes()
    elif values.dtype.kind == 'M':
        dtype = _dtype('M8', (4, '<', None, None, None, -1, -1, 0, (None, ('ns', 1, 1, 1))))
        data = values.astype('<M8[ns]').tobytes()
    else:
        dtype, data = _dtype('O8', (3, '|', None, None, None, -1, -1, 63)), list(values)
    start = _global('numpy.core.multiarray', '_reconstruct') + _value(
        (Raw(_global('numpy', 'ndarray')), (0,), 'b')) + b'R'
    return Raw(start + _value((1, tuple(values.shape), dtype, False, data)) + b'b')


def _index(names) -> Raw:
    return _call('pandas.core.index', '_new_Index', Raw(_global('pandas.core.index', 'Index')),
                 {'data': _array(np.array(list(names), dtype=object)), 'name': None})


def _datetime_index(stamps_ns: np.ndarray, freq=None) -> Raw:
    return _call('pandas.tseries.index', '_new_DatetimeIndex',
                 Raw(_global('pandas.tseries.index', 'DatetimeIndex')),
                 {'data': _array(np.asarray(stamps_ns).astype('M8[ns]')), 'freq': freq,
                  'tz': None, 'name': None})


def frame_pickle(columns: dict[str, np.ndarray], stamps_ns: np.ndarray, *, freq=None) -> bytes:
    """Protocol 2 pickle of a float DataFrame over a DatetimeIndex, old pandas layout."""
    names = list(columns)
    block = np.stack([np.asarray(columns[n], dtype=float) for n in names])
    axes = [_index(names), _datetime_index(stamps_ns, freq)]
    state = ([Raw(a.data) for a in axes], [_array(block)], [_index(names)],
             {'0.14.1': {'axes': axes, 'blocks': [
                 {'values': _array(block), 'mgr_locs': _call('__builtin__', 'slice', 0,
                                                             len(names), 1)}]}})
    manager = _global('pandas.core.internals', 'BlockManager') + b')\x81' + _value(state) + b'b'
    frame = _global('pandas.core.frame', 'DataFrame') + b')\x81' + _value(
        {'_data': Raw(manager), '_typ': 'dataframe', '_metadata': []}) + b'b'
    return b'\x80\x02' + frame + b'.'
