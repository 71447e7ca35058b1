# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Text tables (CSV) as people export them, read through pandas with the file's quirks.

Handled: `,` `;` tab and `|` delimiters (sniffed from the header, or given), rows that
end with a delimiter, quoted headers, a UTF-8 byte-order mark, latin-1 text, CRLF line
ends, `#` comment lines before the header, blank lines (empty, or spaces alone), empty
and `n/a`-style cells (NaN), decimal commas in `;`- or tab-separated files. Refused with
the file and line: binary files, rows with more or fewer fields than the header,
duplicated column names, text in a numeric column. A file with a header and no rows is
a table of zero rows.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
import io
from pathlib import Path
import re

import numpy as np

from tactex_common.errors import RefusedFileError, TableError
from tactex_common.files import read_bytes

MAX_TABLE_BYTES = 1024**3

DELIMITERS = (',', ';', '\t', '|')
# Cells read as missing, besides pandas' own list ('', 'NA', 'N/A', 'n/a', 'nan', 'null', ...).
MISSING = ('-', '?', 'none', 'None', 'missing')
_DECIMAL_COMMA = re.compile(r'^\s*[-+]?\d*,\d+(?:[eE][-+]?\d+)?\s*$')


@dataclass(frozen=True)
class Table:
    """A parsed table: its columns by header name, and where each row came from.

    Attributes:
        path: the file.
        frame: a pandas DataFrame, one column per header name (text or numbers).
        lines: (rows,) the 1-based line of the file each row started on.
        delimiter: the delimiter used.
        encoding: the text encoding the file was read with.
    """

    path: Path
    frame: object
    lines: np.ndarray
    delimiter: str
    encoding: str

    @property
    def columns(self) -> list[str]:
        """Column names in file order."""
        return [str(name) for name in self.frame.columns]

    def __len__(self) -> int:
        """Number of data rows."""
        return len(self.frame)

    def numeric(self, column: str) -> np.ndarray:
        """The column as float64; missing cells are NaN.

        Raises:
            TableError: no such column, or a cell holds text that is not a number.
        """
        import pandas
        if column not in self.frame.columns:
            raise TableError(f'{self.path}: no column {column!r}; columns: '
                             f'{", ".join(self.columns)}')
        raw = self.frame[column]
        if raw.dtype.kind in 'fiub':
            return raw.to_numpy(dtype=np.float64)
        text = raw.astype('string')
        if self.delimiter != ',' and text.dropna().str.match(_DECIMAL_COMMA).any():
            text = text.str.replace(',', '.', regex=False)
        values = pandas.to_numeric(text, errors='coerce')
        bad = np.flatnonzero(values.isna().to_numpy() & text.notna().to_numpy())
        if bad.size:
            raise TableError(f'{self.path}, line {int(self.lines[bad[0]])}: column {column!r} '
                             f'holds {str(text.iloc[bad[0]])!r}, not a number')
        return values.to_numpy(dtype=np.float64, na_value=np.nan)


def read_table(path: Path, *, delimiter: str | None = None) -> Table:
    """Read a delimited text file with a header row.

    Args:
        path: the file.
        delimiter: one character; sniffed from the header when None.

    Raises:
        TableError: unreadable, binary, empty, ragged, or a header naming a column twice.
    """
    import pandas
    path = Path(path)
    if delimiter is not None and len(delimiter) != 1:
        raise TableError(f'the delimiter must be one character, got {delimiter!r}')
    text, encoding = _decode(path)
    lines = text.splitlines()
    header_index = next((i for i, line in enumerate(lines)
                         if line.strip() and not line.lstrip().startswith('#')), None)
    if header_index is None:
        raise TableError(f'{path}: empty file (no header row)')
    delimiter = delimiter or _sniff(lines[header_index])
    # Spaces alone make a blank line, skipped as an empty one is; '\t\t' in a tab table is
    # a row of empty cells.
    body = '\n'.join(line if line.strip() or delimiter in line else ''
                     for line in lines[header_index:])
    names, row_lines = _check_shape(path, body, delimiter, first_line=header_index + 1)
    trailing = object()  # a column for the empty field after a trailing delimiter
    try:
        frame = pandas.read_csv(
            io.StringIO(body), sep=delimiter, header=None, names=[*names, trailing],
            skiprows=1, index_col=False, skipinitialspace=True, skip_blank_lines=True,
            na_values=list(MISSING), engine='c' if delimiter != '|' else 'python')
    except (ValueError, pandas.errors.ParserError) as err:
        raise TableError(f'{path}: {str(err).strip()}') from None
    frame = frame.drop(columns=[trailing])
    if len(frame) != len(row_lines):  # the shape check and pandas must agree on the rows
        raise TableError(f'{path}: {len(frame)} rows parsed but {len(row_lines)} found; '
                         'check for stray quotes')
    return Table(path, frame, np.asarray(row_lines, dtype=np.int64), delimiter, encoding)


def _decode(path: Path) -> tuple[str, str]:
    try:
        data = read_bytes(path, max_bytes=MAX_TABLE_BYTES)
    except RefusedFileError as err:
        raise TableError(str(err)) from None
    except OSError as err:
        raise TableError(f'{path}: cannot read: {err.strerror}') from None
    if b'\x00' in data[:65536]:
        raise TableError(f'{path} is a binary file, not a text table')
    try:
        return data.decode('utf-8-sig'), 'utf-8'
    except UnicodeDecodeError:
        return data.decode('latin-1'), 'latin-1'


def _sniff(header: str) -> str:
    """The candidate delimiter splitting the header into the most fields (',' if none)."""
    counts = {d: len(next(csv.reader([header], delimiter=d))) for d in DELIMITERS}
    best = max(DELIMITERS, key=lambda d: counts[d])
    return best if counts[best] > 1 else ','


def _check_shape(path: Path, body: str, delimiter: str, *, first_line: int
                 ) -> tuple[list[str], list[int]]:
    """Header names and the line of each data row; every row as wide as the header.

    One trailing empty field (a row ending with the delimiter) is allowed on the header
    and on every row.
    """
    reader = csv.reader(io.StringIO(body), delimiter=delimiter, skipinitialspace=True)
    try:
        header = next(reader)
    except csv.Error as err:
        raise TableError(f'{path}, line {first_line}: {err}') from None
    if len(header) > 1 and not header[-1].strip():
        header = header[:-1]
    names = [name.strip() for name in header]
    if not all(names):
        raise TableError(f'{path}, line {first_line}: the header has an empty column name')
    repeated = sorted({n for n in names if names.count(n) > 1})
    if repeated:
        raise TableError(f'{path}, line {first_line}: column(s) {repeated} appear twice in '
                         'the header')
    row_lines = []
    start = first_line + reader.line_num
    try:
        for row in reader:
            line = start
            start = first_line + reader.line_num
            if not row:
                continue
            width = len(row) - (1 if len(row) == len(names) + 1 and not row[-1].strip() else 0)
            if width != len(names):
                raise TableError(f'{path}, line {line}: {width} fields, but the header has '
                                 f'{len(names)}; fix or remove that row')
            row_lines.append(line)
    except csv.Error as err:
        raise TableError(f'{path}, line {first_line + reader.line_num - 1}: {err}') from None
    return names, row_lines
