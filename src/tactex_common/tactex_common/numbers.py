# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Whether a value read from a file or a message is a finite real number."""

from __future__ import annotations

import math


def is_finite_number(value) -> bool:
    """True for an int or a float (never a bool) that a float holds as a finite value.

    JSON, TOML and YAML read an integer literal of any length as a Python int; one past
    the float range (about 1.8e308) makes `math.isfinite` raise OverflowError, so it is
    refused here like inf and NaN are.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:
        return False
