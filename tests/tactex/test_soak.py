# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The soak test's bookkeeping: fault rotation, window ledger, memory slope, losses, report."""

import math
import os

import numpy as np
import pytest

from tactex.soak.bookkeeping import (
    COUNTERS,
    fault_schedule,
    FaultRecord,
    FAULTS,
    losses,
    memory_growth_mb_per_hour,
    memory_report,
    per_period,
    plot_memory,
    read_back,
    rss_bytes,
    table,
    WindowLedger,
)


def counters(cut, classified, dropped, **faults):
    """The ledger's counters: these windows, and every fault zero but those given."""
    return {**dict.fromkeys(COUNTERS, 0), 'windows_cut': cut, 'windows_classified': classified,
            'windows_dropped': dropped, **faults}


def test_faults_rotate_once_a_period_inside_the_run():
    schedule = fault_schedule(5 * 60, 60)
    assert schedule == [(60, 'sensor_unplug'), (120, 'crc_burst'), (180, 'servo_silence'),
                        (240, 'node_kill')]
    every = [f for _, f in fault_schedule((2 * len(FAULTS) + 1) * 60, 60)]
    assert every == list(FAULTS) * 2
    assert fault_schedule(60, 60) == []


@pytest.mark.parametrize('period', [0.0, -1.0, math.nan, math.inf])
def test_fault_schedule_refuses_a_bad_period(period):
    with pytest.raises(ValueError, match='fault period'):
        fault_schedule(60, period)


def test_ledger_sums_the_counters_over_the_classifiers_lives():
    ledger = WindowLedger()
    ledger.update(counters(10, 8, 2))
    ledger.update(counters(20, 17, 3))
    ledger.update(counters(4, 4, 0))  # respawned: the counters start again
    ledger.update(counters(6, 5, 1))
    assert ledger.totals() == counters(26, 22, 4)
    assert ledger.lives == 2


def test_memory_slope_is_the_least_squares_growth_per_hour():
    times = np.arange(0, 600, 5.0)
    rss = 100e6 + 2e6 / 3600 * times + np.where(np.arange(times.size) % 2, 1e5, -1e5)
    assert memory_growth_mb_per_hour(times, rss) == pytest.approx(2.0, rel=0.05)
    assert math.isnan(memory_growth_mb_per_hour([3.0, 3.0], [1.0, 2.0]))
    report = memory_report({'a': [(0.0, 5e6)], 'b': [(0.0, 1e6), (3600.0, 2e6)]})
    assert report['a']['growth_mb_per_hour'] is None
    assert report['b'] == {'rss_mb_last': 2.0, 'samples': 2,
                           'growth_mb_per_hour': pytest.approx(1.0)}
    start_up = {'c': [(100.0, 1e6), (110.0, 9e6), (3700.0, 9e6), (7300.0, 9e6)]}
    assert memory_report(start_up, warmup_s=60.0)['c']['growth_mb_per_hour'] == pytest.approx(
        0.0, abs=1e-9)
    assert memory_report(start_up, warmup_s=7200.0)['c']['growth_mb_per_hour'] is None


def test_decisions_are_counted_per_period_the_last_one_short():
    assert per_period([1.0, 599.0, 600.0, 1250.0, 1300.0], 600.0, 1300.0) == [2, 1, 2]
    assert per_period([], 600.0, 0.0) == [0]


def test_rss_of_this_process_and_none_for_a_gone_one():
    assert rss_bytes(os.getpid()) > 1e6
    assert rss_bytes(2**22 + 12345) is None


def test_losses_name_every_unaccounted_loss():
    ok = [FaultRecord(60, 'crc_burst', True)]
    assert losses(counters(10, 7, 3), 2, 2, ok, 1) == []
    assert losses(counters(10, 5, 3, faults_frozen=1, faults_refused=1), 2, 2, ok, 1) == []
    found = losses(counters(10, 7, 2), 3, 2, [FaultRecord(60, 'node_kill', False, 'gone')], 2)
    assert found == ['10 windows expected but 9 classified, counted as dropped or skipped '
                     'for a fault',
                     '1 of 3 bags unreadable', '1 of 2 faults injected',
                     'no recovery from node_kill at 60 s: gone']


def test_an_empty_folder_is_not_a_readable_recording(tmp_path):
    assert 'BagError' in read_back(tmp_path)


def test_table_and_plot_of_a_summary(tmp_path):
    faults = [FaultRecord(30, 'sensor_unplug', True), FaultRecord(60, 'node_kill', False)]
    summary = {'minutes': 2, 'loops': 3, 'sweeps_ok': 2, 'sweeps_sent': 3, 'probes_ok': 3,
               'probes_sent': 3, 'windows': counters(10, 7, 3), 'classifier_lives': 1,
               'bags_written': 3, 'bags_readable': 3, 'faults': [vars(f) for f in faults],
               'memory': memory_report({'sweep_node': [(0, 1e8), (60, 1e8)]}),
               'losses': ['no recovery from node_kill at 60 s']}
    rows = {line[:32].strip(): line[32:].strip() for line in table(summary).splitlines()}
    assert rows['windows expected'] == '10' and rows['faults injected / recovered'] == '2 / 1'
    assert rows['sweep_node RSS MB (growth MB/h)'] == '100 (+0.0)'
    assert rows['windows skipped for a fault'] == ('0 refused, 0 frozen, 0 saturated, '
                                                   '0 model_errors')
    assert rows['verdict'] == 'FAIL: no recovery from node_kill at 60 s'
    plot_memory(tmp_path / 'memory.png', {'sweep_node': [(0, 1e8), (60, 1.1e8)]}, faults)
    assert (tmp_path / 'memory.png').stat().st_size > 1000
