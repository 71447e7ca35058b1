# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex sim stats`: per texture and channel what the module reported, beside its limits."""

import dataclasses
import json
import math
from pathlib import Path
import subprocess
import sys

import numpy as np
import pytest

from tactex_classify.data import signal_stats
from tactex_common import chips
from tactex_sim.collect import record_sweep
from tactex_sim.scene import load_scene, resolve_scene

TACTEX = Path(sys.executable).parent / 'tactex'
LIMITS = signal_stats.Limits.configured()


def test_a_channel_row_counts_the_rails_and_what_lies_beyond_the_full_scale():
    rate = 120.0
    t = np.arange(1200) / rate
    high = chips.gyro_range().rails_si[1]
    values = 0.5 * np.sin(2 * math.pi * 12.0 * t)
    values[:3] = high  # three samples on the rail, beyond the nominal +-245 dps
    row = signal_stats.channel_row(values, rate, 'gyro', LIMITS)
    assert row['samples'] == 1200
    assert row['at_rails'] == pytest.approx(3 / 1200)
    assert row['beyond_full_scale'] == 3
    assert row['max'] == pytest.approx(high)
    assert row['peak_hz'] == pytest.approx(12.0, abs=0.5)


def test_an_empty_or_missing_channel_gives_no_numbers():
    assert signal_stats.channel_row(np.full(10, np.nan), 120.0, 'accel', LIMITS) == {
        'samples': 0}


def test_warnings_name_the_texture_and_channel():
    table = {'wood': {'channels': {'gx': {'beyond_full_scale': 2}, 'gy': {
        'beyond_full_scale': 0}}}}
    assert signal_stats.warnings(table) == [
        'wood: gx has 2 sample(s) beyond the configured full scale']


def test_samples_whose_true_attitude_is_no_attitude_are_left_out_of_the_tilt_median():
    # A zero quaternion on the ground-truth topic gives NaN, not the identity's tilt.
    signals = signal_stats.TextureSignals(120.0, tilt_errors_deg=[np.array([1.0, np.nan, 3.0]),
                                                                   np.full(4, np.nan)])
    table = signal_stats.statistics({'wood': signals}, LIMITS)
    assert table['wood']['madgwick_tilt_deg_median'] == 2.0
    only_nan = signal_stats.TextureSignals(120.0, tilt_errors_deg=[np.full(3, np.nan)])
    assert signal_stats.statistics({'x': only_nan}, LIMITS)['x'][
        'madgwick_tilt_deg_median'] is None


@pytest.mark.slow
def test_sim_stats_writes_the_table_spectra_and_the_madgwick_tilt(tmp_path):
    scene = load_scene(resolve_scene('uneven_texture'))
    scene = dataclasses.replace(scene, effects=(*scene.effects, 'sensor'))
    bags = tmp_path / 'bags'
    for index, texture in enumerate(('ridged polymer', 'wood')):
        record_sweep(scene, texture, index, bags, np.random.SeedSequence(index))
    out = tmp_path / 'stats'
    result = subprocess.run([str(TACTEX), 'sim', 'stats', str(bags), '--out', str(out)],
                            capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stderr
    assert 'warning' not in result.stderr  # the default scene stays within full scale
    table = json.loads((out / 'stats.json').read_text())
    assert set(table) == {'ridged polymer', 'wood'}
    for entry in table.values():
        assert set(entry['channels']) == {'ax', 'ay', 'az', 'gx', 'gy', 'gz', 'mx', 'my', 'mz',
                                          'baro'}
        assert all(row['beyond_full_scale'] == 0 for row in entry['channels'].values())
        assert entry['madgwick_tilt_deg_median'] < 2.0
    for group in ('accel', 'gyro', 'mag', 'baro'):
        assert (out / f'spectrum_{group}.png').read_bytes()[:8] == b'\x89PNG\r\n\x1a\n'
    assert '## gyro (rad/s)' in (out / 'stats.md').read_text()


def test_sim_stats_refuses_a_missing_folder_in_one_line(tmp_path):
    result = subprocess.run([str(TACTEX), 'sim', 'stats', str(tmp_path / 'nope'), '--out',
                             str(tmp_path / 'out')], capture_output=True, text=True)
    assert result.returncode == 1
    assert result.stderr.startswith('error: BAG_OR_DIR') and 'Traceback' not in result.stderr
    assert not (tmp_path / 'out').exists()
