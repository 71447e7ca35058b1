# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Whether a value read from a file or a message is a finite real number."""

from __future__ import annotations

import math
import numbers

import numpy as np


def is_finite_number(value) -> bool:
    """True for a real number (never a bool) that a float holds as a finite value.

    JSON, TOML and YAML read an integer literal of any length as a Python int; one past
    the float range (about 1.8e308) makes `math.isfinite` raise OverflowError, so it is
    refused here like inf and NaN are. numpy's numbers are real numbers too.
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:
        return False
