# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Channel statistics of any samples a foreign recording may hold: counts right, no exception."""

import math

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest

from tactex_classify.data import signal_stats

pytestmark = pytest.mark.hard_case

LIMITS = signal_stats.Limits.configured()


@pytest.mark.parametrize('group', list(signal_stats.GROUPS))
@settings(max_examples=60)
@given(values=st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=300),
       rate=st.sampled_from([120.0, 350.0, 0.0, -1.0, math.nan, math.inf]))
def test_any_samples_give_a_row_that_counts_them(group, values, rate):
    array = np.array(values, dtype=float)
    with np.errstate(all='ignore'):
        row = signal_stats.channel_row(array, rate, group, LIMITS)
    finite = array[np.isfinite(array)]
    assert row['samples'] == finite.size
    if finite.size:
        assert 0.0 <= row['at_rails'] <= 1.0
        assert 0 <= row['beyond_full_scale'] <= finite.size
        assert row['max'] == np.abs(finite).max()
        assert math.isnan(row['peak_hz']) or row['peak_hz'] > signal_stats.MIN_PEAK_HZ
