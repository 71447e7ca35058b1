# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The soak test's bookkeeping, without ROS: the fault schedule, the window ledger, memory.

`bench/soak.py` runs the launched system for minutes with a fault injected every period;
this module says which fault comes when, adds up classifier_node's window counters
across its restarts, fits memory growth by least squares, and names every unaccounted
loss.
"""

from __future__ import annotations

from dataclasses import dataclass, field
import math
from pathlib import Path

import numpy as np

from tactex_common import plotting

# The system's faults, then the live stream's (played on the tactile topics during a sweep).
FAULTS = ('sensor_unplug', 'crc_burst', 'servo_silence', 'node_kill', 'overflow',
          'clock_jump', 'burst', 'stamp_jitter', 'frozen', 'saturated')
# classifier_node's windows not classified for a fault (each is also cut).
SKIPPED = ('faults_refused', 'faults_frozen', 'faults_saturated', 'faults_model_errors')
COUNTERS = ('windows_cut', 'windows_classified', 'windows_dropped', *SKIPPED,
            'faults_invalid', 'faults_off_timeline', 'faults_resyncs')


def fault_schedule(duration_s: float, period_s: float, kinds: tuple[str, ...] = FAULTS
                   ) -> list[tuple[float, str]]:
    """(seconds after the start, fault) every `period_s` within `duration_s`, `kinds` in turn.

    Raises:
        ValueError: a period that is not finite and > 0.
    """
    if not (math.isfinite(period_s) and period_s > 0):
        raise ValueError(f'the fault period must be finite and > 0 s, got {period_s!r}')
    count = max(0, math.ceil(duration_s / period_s) - 1) if math.isfinite(duration_s) else 0
    return [((i + 1) * period_s, kinds[i % len(kinds)]) for i in range(count)]


@dataclass
class WindowLedger:
    """classifier_node's window counters summed over its lives (a restart zeroes them)."""

    finished: dict[str, int] = field(default_factory=lambda: dict.fromkeys(COUNTERS, 0))
    current: dict[str, int] = field(default_factory=lambda: dict.fromkeys(COUNTERS, 0))
    lives: int = 0

    def update(self, counters: dict[str, int]) -> None:
        """The counters of one diagnostics message (a fall means the node restarted)."""
        if not self.lives or any(counters[k] < self.current[k] for k in COUNTERS):
            for key in COUNTERS:
                self.finished[key] += self.current[key]
            self.lives += 1
        self.current = {key: int(counters[key]) for key in COUNTERS}

    def totals(self) -> dict[str, int]:
        """Every counter over every life."""
        return {key: self.finished[key] + self.current[key] for key in COUNTERS}


def memory_growth_mb_per_hour(times_s, rss_bytes) -> float:
    """Least-squares slope of RSS over time, MB per hour (nan with fewer than 2 times)."""
    times, rss = np.asarray(times_s, dtype=float), np.asarray(rss_bytes, dtype=float)
    if np.unique(times).size < 2:
        return float('nan')
    slope = np.polyfit(times, rss, 1)[0]  # bytes per second
    return float(slope * 3600 / 1e6)


def memory_report(samples: dict[str, list[tuple[float, int]]],
                  warmup_s: float = 0.0) -> dict[str, dict]:
    """Per process: last RSS (MB) and growth (MB/h) fitted after its first `warmup_s`.

    Start-up, when imports and first allocations dominate, is left out of the fit (of a
    respawned node's life too). The growth is None with fewer than 2 sample times left.
    """
    report = {}
    for name, points in samples.items():
        fitted = [(t, r) for t, r in points if t >= points[0][0] + warmup_s]
        growth = (memory_growth_mb_per_hour(*zip(*fitted, strict=True)) if fitted
                  else float('nan'))
        report[name] = {'rss_mb_last': points[-1][1] / 1e6, 'samples': len(points),
                        'growth_mb_per_hour': growth if math.isfinite(growth) else None}
    return report


def read_back(recording: Path) -> str:
    """Read every message of a recording and decode it; '' if it reads, else what failed."""
    from tactex_classify.data.sources import bag_parts, open_part
    try:
        count = 0
        for part in bag_parts(recording):
            with open_part(part) as reader:
                for connection, _, raw in reader.messages():
                    reader.deserialize(raw, connection.msgtype)
                    count += 1
    except Exception as err:  # noqa: BLE001 - rosbags raises many unrelated types
        return f'{type(err).__name__}: {err}'
    return '' if count else 'no messages'


def rss_bytes(pid: int) -> int | None:
    """Resident set size of a process (None if it is gone)."""
    try:
        status = Path(f'/proc/{pid}/status').read_text(encoding='ascii')
    except OSError:
        return None
    for line in status.splitlines():
        if line.startswith('VmRSS:'):
            return int(line.split()[1]) * 1024
    return None


@dataclass(frozen=True)
class FaultRecord:
    """One injected fault: when (s after the start), which, whether it was recovered from, how."""

    at_s: float
    fault: str
    recovered: bool
    detail: str = ''


def per_period(times_s: list[float], period_s: float, duration_s: float) -> list[int]:
    """How many of `times_s` fall in each `period_s` of `duration_s` (the last may be short)."""
    bins = max(1, math.ceil(duration_s / period_s))
    counts = [0] * bins
    for t in times_s:
        counts[min(bins - 1, max(0, int(t // period_s)))] += 1
    return counts


def windows_accounted(windows: dict[str, int]) -> int:
    """Windows classified, dropped (newer ones queued) or skipped for a fault."""
    return windows['windows_classified'] + windows['windows_dropped'] + sum(
        windows[key] for key in SKIPPED)


def losses(windows: dict[str, int], bags: int, readable: int, faults: list[FaultRecord],
           scheduled: int) -> list[str]:
    """Every unaccounted loss, in words (empty: the soak passed)."""
    found = []
    accounted = windows_accounted(windows)
    if windows['windows_cut'] != accounted:
        found.append(f'{windows["windows_cut"]} windows expected but {accounted} classified, '
                     'counted as dropped or skipped for a fault')
    if readable != bags:
        found.append(f'{bags - readable} of {bags} bags unreadable')
    if len(faults) != scheduled:
        found.append(f'{len(faults)} of {scheduled} faults injected')
    found += [f'no recovery from {f.fault} at {f.at_s:.0f} s: {f.detail}' for f in faults
              if not f.recovered]
    return found


def table(summary: dict) -> str:
    """The final table of a soak summary (bench/soak.py's summary.json)."""
    w = summary['windows']
    rows = [('minutes', f'{summary["minutes"]:g}'), ('loops', summary['loops']),
            ('sweeps ok / sent', f'{summary["sweeps_ok"]} / {summary["sweeps_sent"]}'),
            ('probes ok / sent', f'{summary["probes_ok"]} / {summary["probes_sent"]}'),
            ('windows expected', w['windows_cut']),
            ('windows classified', w['windows_classified']),
            ('windows dropped', w['windows_dropped']),
            ('windows skipped for a fault', ', '.join(
                f'{w[key]} {key.removeprefix("faults_")}' for key in SKIPPED)),
            ('samples invalid / off timeline', f'{w["faults_invalid"]} / '
             f'{w["faults_off_timeline"]} ({w["faults_resyncs"]} resyncs)'),
            ('windows in the bags (converter)', summary.get('windows_in_bags', 'n/a')),
            ('classifier lives', summary['classifier_lives']),
            ('decisions per 10 min', ' '.join(map(str, summary.get('decisions_per_10_min',
                                                                   [])))),
            ('bags written / readable',
             f'{summary["bags_written"]} / {summary["bags_readable"]}'),
            ('faults injected / recovered',
             f'{len(summary["faults"])} / {sum(f["recovered"] for f in summary["faults"])}')]
    for name, m in summary['memory'].items():
        growth = m['growth_mb_per_hour']
        rows.append((f'{name} RSS MB (growth MB/h)', f'{m["rss_mb_last"]:.0f} (' + (
            f'{round(growth, 1) + 0.0:+.1f})' if growth is not None else 'n/a)')))
    rows.append(('verdict', 'PASS' if not summary['losses'] else
                 'FAIL: ' + '; '.join(summary['losses'])))
    width = max(len(name) for name, _ in rows)
    return '\n'.join(f'{name:<{width}}  {value}' for name, value in rows) + '\n'


def plot_memory(path: Path, samples: dict[str, list[tuple[float, int]]],
                faults: list[FaultRecord]) -> None:
    """RSS against time per node, each injected fault marked."""
    plt, figure, axes = plotting.figure()
    for name, points in samples.items():
        if points:
            t, rss = np.array(points, dtype=float).T
            axes.plot(t / 60, rss / 1e6, label=name)
    for record in faults:
        axes.axvline(record.at_s / 60, color='red' if not record.recovered else 'grey',
                     linestyle='--', linewidth=0.8)
        axes.annotate(record.fault, (record.at_s / 60, 1.0), xycoords=('data', 'axes fraction'),
                      rotation=90, va='top', ha='right', fontsize=7)
    axes.set(xlabel='time (min)', ylabel='RSS (MB)',
             title='Soak: resident memory per node (dashed: faults)')
    plotting.legend_outside(axes)
    plotting.save(plt, figure, path)
