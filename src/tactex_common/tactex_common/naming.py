# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Names: natural order (`mat2` before `mat10`), and the known name closest to a misspelt one."""

from __future__ import annotations

from collections.abc import Iterable
import difflib
from pathlib import Path
import re

_DIGITS = re.compile(r'(\d+)')


def natural_key(name: str | Path) -> tuple:
    """Sort key that compares runs of digits as numbers, the rest case-insensitively.

    Ties (`Wood` and `wood`) fall back to the exact text, so the order is total.
    """
    text = str(name)
    parts = _DIGITS.split(text)
    return tuple((0, int(part), '') if index % 2 else (1, 0, part.casefold())
                 for index, part in enumerate(parts)) + ((2, 0, text),)


def natural_sorted(names: Iterable) -> list:
    """`names` in natural order (see `natural_key`)."""
    return sorted(names, key=natural_key)


def closest_name(name: str, known: Iterable[str]) -> str | None:
    """The name of `known` most like `name` (a typo's intended name), or None if none is close."""
    matches = difflib.get_close_matches(name, list(known), n=1)
    return matches[0] if matches else None
