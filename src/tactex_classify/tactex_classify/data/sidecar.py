# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A dataset sidecar beside its arrays: what each sweep ran at, the rate and the window."""

from __future__ import annotations

from pathlib import Path
import reprlib

from tactex_classify.errors import DatasetError
from tactex_classify.models.checkpoint import SAMPLING_RATE_RANGE_HZ
from tactex_common.numbers import is_finite_number

# A recording's metadata names its sweep's parameters under these keys (sim, sweep_node).
SWEEP_KEYS = {'speed_m_s': ('speed_m_s', 'sliding_speed_m_s'),
              'press_depth_m': ('press_depth_m',), 'edge_tilt_rad': ('edge_offset_rad',)}


def recorded_sweep(metadata: dict) -> dict[str, float]:
    """The speed, press depth and edge tilt a recording's sweep ran at, where it says."""
    sweep = metadata.get('sweep')
    if not isinstance(sweep, dict):
        return {}
    found = {}
    for name, keys in SWEEP_KEYS.items():
        value = next((sweep[key] for key in keys if key in sweep), None)
        if is_finite_number(value):
            found[name] = float(value)
    return found


def check_sidecar_stream(sidecar: dict, window: int | None, path: Path) -> None:
    """A sidecar's rate (a model's range) and window (X's) agree with the arrays, when given.

    Raises:
        DatasetError: naming the sidecar, the value and what it must be.
    """
    rate, (low, high) = sidecar.get('sampling_rate_hz'), SAMPLING_RATE_RANGE_HZ
    if rate is not None and not (is_finite_number(rate) and low <= rate <= high):
        raise DatasetError(f'{path}: sampling_rate_hz must be a finite number in {low:g}..'
                           f'{high:g} Hz, got {reprlib.repr(rate)}: convert or import the '
                           'recordings again')
    stated = sidecar.get('window')
    if stated is not None and window is not None and stated != window:
        raise DatasetError(f'{path}: window {stated!r} but the dataset holds {window}-sample '
                           'windows: the sidecar belongs to another dataset; convert again')
