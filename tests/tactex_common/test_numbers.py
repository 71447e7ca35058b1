# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Hard cases: a number read from a file is finite when a float holds it finitely."""

from hypothesis import example, given
from hypothesis import strategies as st
import numpy as np
import pytest
from support.hard_values import finite_as_float, HUGE_INTEGERS, parsed_numbers

from tactex_common.numbers import is_finite_number

pytestmark = pytest.mark.hard_case


@given(st.one_of(parsed_numbers(), st.none(), st.text(max_size=3), st.lists(st.integers())))
@example(10**400)
def test_a_value_is_a_finite_number_when_a_float_holds_it_finitely(value):
    assert is_finite_number(value) is finite_as_float(value)


@pytest.mark.parametrize('value', HUGE_INTEGERS)
def test_a_whole_number_past_the_float_range_is_refused_like_inf(value):
    assert not is_finite_number(value)


@pytest.mark.parametrize('value', [True, False, np.bool_(True), '1', None, [1.0], 1j])
def test_booleans_and_non_numbers_are_not_numbers(value):
    assert not is_finite_number(value)


@pytest.mark.parametrize('value, finite', [(np.float32(1.5), True), (np.int64(-3), True),
                                           (np.float64('nan'), False), (np.float32('inf'),
                                                                         False)])
def test_numpys_numbers_are_numbers(value, finite):
    assert is_finite_number(value) is finite
