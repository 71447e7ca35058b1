# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Bounded decompression for rosbags: no compressed chunk, message or file inflates without limit.

rosbags inflates a ROS 1 chunk (bz2, lz4), an MCAP chunk (lz4, zstd), a zstd message and a
zstd-compressed rosbag2 file whole, however large the result: a few kilobytes of crafted
data can ask for gigabytes. `install` swaps rosbags' decompressors for the same libraries'
incremental decompressors with an output limit: the larger of `MIN_LIMIT_BYTES` and
`MAX_RATIO` times the compressed size (recorded sensor data inflates 2-20 times). Past it
the read stops with `InflationError`, having held at most the limit in memory.
"""

from __future__ import annotations

import bz2
import os
from typing import BinaryIO

import lz4.frame

MIN_LIMIT_BYTES = 256 * 1024**2
MAX_RATIO = 100


class InflationError(ValueError):
    """Compressed data would inflate past its limit."""


def limit_for(compressed_bytes: int) -> int:
    """The most bytes `compressed_bytes` of compressed data may inflate to."""
    return max(MIN_LIMIT_BYTES, MAX_RATIO * compressed_bytes)


def _zstd():
    """The zstd module rosbags uses (the standard library's from Python 3.14, else a backport)."""
    from rosbags.rosbag2 import storage_mcap
    return storage_mcap.zstd


def _refuse(kind: str, limit: int) -> InflationError:
    return InflationError(f'a {kind}-compressed block inflates past {limit / 1024**2:.0f} MiB '
                          f'(over {MAX_RATIO} times its size): a decompression bomb or a '
                          'damaged block; refused')


def _inflate(make, data: bytes, kind: str, limit: int) -> bytes:
    """Every frame of `data` through decompressors from `make`, at most `limit` bytes out."""
    out, rest = bytearray(), bytes(data)
    while rest:
        decompressor = make()
        out += decompressor.decompress(rest, max_length=limit + 1 - len(out))
        if len(out) > limit or not decompressor.eof:
            if len(out) > limit or not decompressor.needs_input:
                raise _refuse(kind, limit)
            break  # a frame cut short: the caller's size and checksum checks name it
        rest = decompressor.unused_data
    return bytes(out)


def _bz2(data: bytes) -> bytes:
    return _inflate(bz2.BZ2Decompressor, data, 'bz2', limit_for(len(data)))


def _lz4(data: bytes, size: int | None = None) -> bytes:
    return _inflate(lz4.frame.LZ4FrameDecompressor, data, 'lz4', _declared(size, data, 'lz4'))


def _zstd_block(data: bytes, size: int | None = None) -> bytes:
    return _inflate(_zstd().ZstdDecompressor, data, 'zstd', _declared(size, data, 'zstd'))


def _declared(size: int | None, data: bytes, kind: str) -> int:
    """The limit of a block whose inflated `size` its container declares (MCAP chunks)."""
    limit = limit_for(len(data))
    if size is not None and size > limit:
        raise _refuse(kind, limit)
    return limit if size is None else size


class _BoundedReader:
    """A zstd file reader that stops past the limit of the compressed file's size."""

    def __init__(self, raw: BinaryIO, mode: str) -> None:
        self._inner = _zstd().open(raw, mode)
        self._limit = limit_for(os.fstat(raw.fileno()).st_size)
        self._read = 0

    def read(self, size: int = -1) -> bytes:
        chunk = self._inner.read(min(size, 1 << 20) if size and size > 0 else 1 << 20)
        self._read += len(chunk)
        if self._read > self._limit:
            raise _refuse('zstd', self._limit)
        return chunk

    def __enter__(self) -> _BoundedReader:
        return self

    def __exit__(self, *exc) -> None:
        self._inner.close()


class _BoundedZstd:
    """Stands in for the zstd module in rosbags' rosbag2 reader (message and file mode)."""

    decompress = staticmethod(_zstd_block)
    open = _BoundedReader


def install() -> None:
    """Swap rosbags' decompressors for the bounded ones (idempotent)."""
    from rosbags.rosbag1 import reader as rosbag1_reader
    from rosbags.rosbag2 import reader as rosbag2_reader
    from rosbags.rosbag2 import storage_mcap

    rosbag1_reader.decompressors.update({'bz2': _bz2, 'lz4': _lz4})
    storage_mcap.DECOMPRESSORS.update({'lz4': _lz4, 'zstd': _zstd_block})
    rosbag2_reader.zstd = _BoundedZstd
