# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The chips' quantisation and saturation: idempotent, monotone, exact at the rails, any input."""

import math

from hypothesis import given, settings
from hypothesis import strategies as st
import numpy as np
import pytest

from tactex_common import chips

pytestmark = pytest.mark.hard_case

RANGES = [*chips.ACCEL_RANGES.values(), *chips.GYRO_RANGES.values(),
          *chips.MAG_RANGES.values()]
ANY = st.floats(allow_nan=False)  # infinities and extreme finite values included


@pytest.mark.parametrize('chip_range', RANGES, ids=lambda r: f'{r.nominal:g}x{r.unit_si:.3g}')
@settings(max_examples=60)
@given(a=ANY, b=ANY)
def test_quantise_is_idempotent_and_monotone(chip_range, a, b):
    lsb = chip_range.lsb_si
    qa, qb = chips.quantise([a, b], lsb)
    assert chips.quantise(qa, lsb) == qa
    if a <= b:
        assert qa <= qb
    low, high = chip_range.rails_si
    assert low <= qa <= high


@pytest.mark.parametrize('chip_range', RANGES, ids=lambda r: f'{r.nominal:g}x{r.unit_si:.3g}')
def test_values_beyond_the_range_sit_exactly_at_the_rails(chip_range):
    low, high = chip_range.rails_si
    reported = chips.quantise([-math.inf, -1e300, 10 * low, 10 * high, 1e300, math.inf],
                              chip_range.lsb_si)
    assert list(reported) == [low, low, low, high, high, high]
    assert high == chips.COUNTS_MAX * chip_range.lsb_si
    # The rails lie at or past the nominal range, by the datasheet's sensitivity (+-2 g:
    # 32767 x 0.061 mg is 1.999 g; +-245 dps: 287 dps; +-16 g: 24 g).
    assert high >= 0.999 * chip_range.full_scale_si


def test_a_missing_channel_stays_missing():
    assert np.isnan(chips.quantise([math.nan], 1e-3)).all()
    assert np.isnan(chips.quantise_pressure(math.nan))


@settings(max_examples=100)
@given(a=ANY, b=ANY)
def test_pressure_is_a_10_bit_code_over_50_to_115_kpa(a, b):
    pa, pb = chips.quantise_pressure([a, b])
    assert chips.PRESSURE_MIN_PA <= pa <= chips.PRESSURE_MAX_PA
    assert chips.quantise_pressure(pa) == pa
    code = (pa - chips.PRESSURE_MIN_PA) / chips.PRESSURE_LSB_PA
    assert abs(code - round(code)) < 1e-6
    if a <= b:
        assert pa <= pb


def test_an_unknown_range_names_the_chips_ranges():
    with pytest.raises(ValueError, match=r'no \+-300 dps range; it has \+-245, \+-500, '):
        chips.gyro_range(300)
