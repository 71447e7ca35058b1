# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Reading the files a user names: regular files only, size and nesting bounded, no waits.

Opening a FIFO for reading blocks until a writer comes, and a device or a folder is no
file: `open_regular` looks at what a path is before opening it (and again at what it
opened), and refuses anything but a regular file of at most `max_bytes`. The readers
below all go through it; `load_json` also refuses nesting deeper than `max_depth`
before parsing (Python's parser would recurse once per level), and `check_npz_sizes`
refuses arrays of an .npz whose headers promise more than `max_bytes` before any is read
(a compressed member can expand a thousandfold).
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
import re
import stat
from typing import Any, BinaryIO

from tactex_common.errors import RefusedFileError

# A JSON string (with its escapes) or a bracket: what nesting depth is counted over.
_JSON_STRING_OR_BRACKET = re.compile(r'"(?:[^"\\]|\\.)*"|[\[\]{}]', re.DOTALL)


def file_kind(mode: int) -> str:
    """What a path of `st_mode` is, in words ('regular file', 'FIFO', ...)."""
    for test, name in ((stat.S_ISREG, 'regular file'), (stat.S_ISDIR, 'folder'),
                       (stat.S_ISFIFO, 'FIFO (named pipe)'), (stat.S_ISCHR, 'character device'),
                       (stat.S_ISBLK, 'block device'), (stat.S_ISSOCK, 'socket')):
        if test(mode):
            return name
    return 'special file'


def check_regular(path: Path | str, *, max_bytes: int | None = None) -> int:
    """Refuse anything at `path` but a regular file of at most `max_bytes`; return its size.

    Raises:
        FileNotFoundError, PermissionError: as os.stat raises them.
        RefusedFileError: a folder, FIFO, device or socket, or a file too large.
    """
    info = os.stat(path)
    _check_mode_and_size(path, info, max_bytes)
    return info.st_size


def open_regular(path: Path | str, *, max_bytes: int) -> BinaryIO:
    """`path` opened for binary reading, never blocking on what it turns out to be.

    Raises:
        FileNotFoundError, PermissionError: as opening raises them.
        RefusedFileError: not a regular file, or larger than `max_bytes`.
    """
    check_regular(path, max_bytes=max_bytes)
    # O_NONBLOCK: should the path have become a FIFO since, opening it still returns.
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOCTTY | os.O_CLOEXEC)
    try:
        _check_mode_and_size(path, os.fstat(fd), max_bytes)
        os.set_blocking(fd, True)
        return os.fdopen(fd, 'rb')
    except BaseException:
        os.close(fd)
        raise


def read_bytes(path: Path | str, *, max_bytes: int) -> bytes:
    """The bytes of a regular file of at most `max_bytes` (see `open_regular`)."""
    with open_regular(path, max_bytes=max_bytes) as handle:
        data = handle.read(max_bytes + 1)
    if len(data) > max_bytes:  # it grew while being read
        raise RefusedFileError(f'{path}: larger than {max_bytes} bytes: refused')
    return data


def read_text(path: Path | str, *, max_bytes: int) -> str:
    """The UTF-8 text of a regular file of at most `max_bytes`.

    Raises:
        UnicodeDecodeError: not UTF-8 text.
    """
    return read_bytes(path, max_bytes=max_bytes).decode('utf-8')


def load_json(path: Path | str, *, max_bytes: int, max_depth: int) -> Any:
    """The JSON value of a regular file, at most `max_bytes` and `max_depth` levels deep.

    Raises:
        UnicodeDecodeError, ValueError: not UTF-8 JSON.
        RefusedFileError: not a regular file, too large, or nested too deep.
    """
    text = read_text(path, max_bytes=max_bytes)
    depth = json_depth(text)
    if depth > max_depth:
        raise RefusedFileError(f'{path}: JSON nested {depth} levels deep; at most {max_depth} '
                               'are read')
    return json.loads(text)


def json_depth(text: str) -> int:
    """Deepest nesting of arrays and objects in JSON text (brackets in strings ignored)."""
    depth = deepest = 0
    for token in _JSON_STRING_OR_BRACKET.finditer(text):
        mark = token.group()
        if mark in ('[', '{'):
            depth += 1
            deepest = max(deepest, depth)
        elif mark in (']', '}'):
            depth -= 1
    return deepest


def check_npz_sizes(npz, max_bytes: int, source: Path | str) -> None:
    """Refuse an open `numpy.load` .npz whose arrays would take more than `max_bytes`.

    Raises:
        ValueError: a member is not an .npy array.
        RefusedFileError: the arrays' headers add up to more than `max_bytes`.
    """
    import numpy as np
    total = 0
    for member in npz.zip.infolist():
        with npz.zip.open(member) as stream:
            version = np.lib.format.read_magic(stream)
            read_header = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                           else np.lib.format.read_array_header_2_0)
            shape, _, dtype = read_header(stream)
        total += math.prod(shape) * dtype.itemsize
    if total > max_bytes:
        raise RefusedFileError(f'{source}: its arrays would take {total} bytes, more than the '
                               f'{max_bytes} bytes read: refused')


def npz_refusal(err: Exception) -> str:
    """Why `numpy.load` refused a file, without numpy's advice to load pickles unsafely."""
    text = str(err)
    if 'pickle' in text:
        return ('it is not an .npz of plain arrays (reading it would mean unpickling, which '
                'tactex never does with a file it did not write)')
    return text


def _check_mode_and_size(path, info: os.stat_result, max_bytes: int | None) -> None:
    if not stat.S_ISREG(info.st_mode):
        raise RefusedFileError(f'{path} is a {file_kind(info.st_mode)}, not a regular file; '
                               'give a file')
    if max_bytes is not None and info.st_size > max_bytes:
        raise RefusedFileError(f'{path}: {info.st_size} bytes, larger than the {max_bytes} '
                               'bytes read: refused')
