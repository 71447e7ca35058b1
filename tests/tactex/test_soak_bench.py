# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""bench/soak.py for 2 minutes: each fault injected and recovered from, the windows add up."""

import json
from pathlib import Path
import subprocess
import sys

import pytest

from tactex.soak.bookkeeping import windows_accounted

pytestmark = pytest.mark.integration

SOAK = Path(__file__).parents[2] / 'bench' / 'soak.py'


@pytest.mark.slow
@pytest.mark.ros
@pytest.mark.timeout(1500)
def test_two_minute_soak_recovers_from_every_fault_and_accounts_for_every_window(tmp_path):
    out = tmp_path / 'soak'
    # A fault every 18 s: the system's four kinds and the live-stream faults that need no
    # sweep to play in, within two minutes (the hour-long run in bench/results has them all).
    kinds = ['sensor_unplug', 'crc_burst', 'servo_silence', 'node_kill', 'overflow',
             'clock_jump']
    result = subprocess.run([sys.executable, str(SOAK), '--minutes', '2', '--fault-period',
                             '18', '--faults', ','.join(kinds), '--out', str(out)],
                            capture_output=True, text=True, timeout=1400,
                            stdin=subprocess.DEVNULL)
    assert result.returncode == 0, result.stdout[-6000:] + result.stderr[-3000:]
    summary = json.loads((out / 'summary.json').read_text())
    assert [f['fault'] for f in summary['faults']] == kinds
    assert all(f['recovered'] for f in summary['faults']), summary['faults']
    windows = summary['windows']
    assert windows['windows_cut'] > 0
    assert windows['windows_cut'] == windows_accounted(windows)
    assert windows['faults_invalid'] > 0 and windows['faults_resyncs'] > 0
    assert summary['bags_written'] >= 1 and summary['bags_readable'] == summary['bags_written']
    assert summary['losses'] == []
    assert {'table.txt', 'memory.png'} <= {p.name for p in out.iterdir()}


def test_soak_refuses_a_folder_that_holds_files(tmp_path):
    (tmp_path / 'kept.txt').write_text('mine')
    result = subprocess.run([sys.executable, str(SOAK), '--minutes', '1', '--out',
                             str(tmp_path)], capture_output=True, text=True, timeout=120)
    assert result.returncode == 1
    assert result.stderr.startswith('error: --out') and 'Traceback' not in result.stderr
    assert [p.name for p in tmp_path.iterdir()] == ['kept.txt']
