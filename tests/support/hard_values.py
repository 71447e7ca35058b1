# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Hypothesis strategies of the values that break numeric code, shared by the hard cases."""

import math
import sys

from hypothesis import strategies as st
import numpy as np

FLOAT32_MAX = float(np.finfo(np.float32).max)
FLOAT64_MAX = sys.float_info.max
SUBNORMALS = (5e-324, 1e-310, float(np.finfo(np.float32).smallest_subnormal))
# The finite values that overflow, underflow or cancel: +-float32 max, +-1e300, +-float64
# max, subnormals, +-0.0.
EXTREME_FINITE = tuple(sign * value for value in (
    0.0, FLOAT32_MAX, 1e300, FLOAT64_MAX, *SUBNORMALS) for sign in (1.0, -1.0))
NON_FINITE = (math.nan, math.inf, -math.inf)
# Steps of time that break integrators: zero, negative, subnormal, huge, not finite.
BAD_STEPS_S = (0.0, -0.0, -1e-3, -1.0, 5e-324, 1e300, FLOAT64_MAX, *NON_FINITE)


# Whole numbers past the float range, as JSON, TOML and YAML read a long integer literal.
HUGE_INTEGERS = (10**400, -10**400, 2**1024, -2**1024)


def parsed_numbers() -> st.SearchStrategy:
    """Any number a JSON, TOML or YAML file can hold: floats, ints of any size, booleans."""
    return st.one_of(anything(), st.integers(), st.sampled_from(HUGE_INTEGERS), st.booleans())


def finite_as_float(value) -> bool:
    """Whether `value` (not a bool) converts to a finite float: the oracle of the checks."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.number)):
        return False
    try:
        return math.isfinite(float(value))
    except OverflowError:
        return False


def finite() -> st.SearchStrategy[float]:
    """Any finite float, the extreme ones often."""
    return st.one_of(st.sampled_from(EXTREME_FINITE),
                     st.floats(allow_nan=False, allow_infinity=False))


def anything() -> st.SearchStrategy[float]:
    """Any float at all: extremes, NaN and infinities included."""
    return st.one_of(finite(), st.sampled_from(NON_FINITE))


def steps_s(nominal_s: float) -> st.SearchStrategy[float]:
    """A time step: a bad one or a plausible one around `nominal_s`."""
    return st.one_of(st.sampled_from(BAD_STEPS_S), st.floats(0.0, 10 * nominal_s))


def vectors(elements: st.SearchStrategy[float], size: int = 3
            ) -> st.SearchStrategy[tuple[float, ...]]:
    """Tuples of `size` elements."""
    return st.tuples(*[elements] * size)
