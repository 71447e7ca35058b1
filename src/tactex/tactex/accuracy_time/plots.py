# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The report's PNG plots: each names its axes with units and the data it shows."""

from __future__ import annotations

from pathlib import Path

from tactex_common import plotting


def contact_time(path: Path, points: list[dict], data: str) -> None:
    """Section 1: accuracy against contact seconds, per model and window, Pareto front."""
    plt, figure, axes = plotting.figure(1, 2, sharey=True)
    from matplotlib.ticker import FuncFormatter, NullFormatter  # after the backend is chosen
    keys = sorted({(p['model'], p['window']) for p in points})
    for model, window in keys:
        for axis, threshold_rule in zip(axes, (False, True), strict=True):
            mine = sorted((p for p in points if p['model'] == model and p['window'] == window
                           and (p['threshold'] is not None) == threshold_rule),
                          key=lambda p: p['contact_s'])
            axis.plot([p['contact_s'] for p in mine], [100 * p['accuracy'] for p in mine],
                      'o-', markersize=3, linewidth=1, label=f'{model}, window {window}')
    front = sorted((p for p in points if p['pareto']), key=lambda p: p['contact_s'])
    for axis in axes:
        axis.step([p['contact_s'] for p in front], [100 * p['accuracy'] for p in front],
                  where='post', color='black', linewidth=1.5, label='Pareto front (all)')
        axis.axvline(2.0, color='tab:red', linestyle='--', linewidth=0.8, label='2 s budget')
        axis.set_xscale('log')
        plain = FuncFormatter(lambda value, _: f'{value:g}')
        axis.xaxis.set_major_formatter(plain)
        axis.xaxis.set_minor_formatter(NullFormatter())
        axis.set_xticks([0.5, 1, 2, 4, 8])
        axis.set_xlabel('contact time a decision needs (s, log)')
        axis.grid(alpha=0.3)
    axes[0].set_ylabel('grouped-CV accuracy of the decision (%)')
    axes[0].set_title('k consecutive windows (summed log-probabilities)')
    axes[1].set_title("live node's threshold rule (median contact s at decision)")
    plotting.legend_outside(axes[1])
    plotting.save(plt, figure, path, footnote=f'data: {data}')


def compute_time(path: Path, rows: list[dict], data: str) -> None:
    """Section 2: accuracy against training time and against per-window latency."""
    plt, figure, (train, latency) = plotting.figure(1, 2, sharey=True)
    markers = {'onnxruntime': 's'}
    for index, row in enumerate(rows):  # one colour per model, named in the legend
        accuracy, colour = 100 * row['accuracy'], f'C{index % 10}'
        train.scatter(row['train_s'], accuracy, marker='o' if row['deep'] else '^',
                      color=colour, label=row['model'])
        for runtime, value in row['latency'].items():
            latency.scatter(1e3 * value['single_s'], accuracy,
                            marker=markers.get(runtime, 'o'), color=colour)
    train.set(xscale='log', xlabel='training time on every window (s, log)',
              ylabel='grouped-CV window accuracy (%)',
              title='training (circles deep, triangles baselines)')
    latency.set(xscale='log', xlabel='inference latency of one window (ms, log)',
                title='inference (squares: onnxruntime)')
    for axis in (train, latency):
        axis.grid(alpha=0.3)
    plotting.legend_outside(latency, source=train)
    plotting.save(plt, figure, path, footnote=f'data: {data}')


def probing(path: Path, rows: list[dict], data: str) -> None:
    """Section 3: normal and position error against probing time."""
    plt, figure, axes = plotting.figure(1, 2)
    for axis, key, label in ((axes[0], 'normal_mean_deg', 'mean normal error (deg)'),
                             (axes[1], 'position_mean_mm', 'mean position error (mm)')):
        for row in rows:
            axis.scatter(row['probing_s'], row[key])
        axis.set(xlabel='total probing time of the line (simulated s)', ylabel=label)
        axis.grid(alpha=0.3)
        plotting.label_points(axis, [row['probing_s'] for row in rows],
                              [row[key] for row in rows],
                              [f'{row["step_mm"]:g} mm step, {row["descent_mm_s"]:g} mm/s'
                               for row in rows], fontsize=7)
    plotting.save(plt, figure, path, footnote=f'data: {data}')


def sweep_speed(path: Path, rows: list[dict], data: str) -> None:
    """Section 4: contact fraction and accuracy against sliding speed."""
    plt, figure, axis = plotting.figure()
    rows = [r for r in rows if not r['failed']]
    speeds = [r['speed_mm_s'] for r in rows]
    axis.plot(speeds, [100 * r['contact_fraction'] for r in rows], 'o-',
              label='contact fraction (mean)')
    axis.plot(speeds, [100 * r['contact_fraction_min'] for r in rows], 'o:',
              label='contact fraction (worst sweep)')
    axis.plot(speeds, [100 * r['window_accuracy'] for r in rows], 's-',
              label='window accuracy')
    axis.plot(speeds, [100 * r['sweep_accuracy'] for r in rows], 'D-',
              label='whole-sweep accuracy')
    axis.set(xlabel='sliding speed (mm/s)', ylabel='%', ylim=(0, 105))
    axis.grid(alpha=0.3)
    plotting.legend_outside(axis)
    plotting.save(plt, figure, path, footnote=f'data: {data}')


def simulation_cost(path: Path, rows: list[dict], data: str) -> None:
    """Section 5: spectral distance against real-time factor."""
    plt, figure, axis = plotting.figure()
    for index, row in enumerate(rows):
        axis.scatter(row['real_time_factor'], row['distance_db'], color=f'C{index % 10}',
                     marker='os^Dv'[index // 10 % 5], label=row['variant'])
    axis.set(xlabel='real-time factor (simulated s per wall s)',
             ylabel='spectral distance to the reference (dB)')
    axis.grid(alpha=0.3)
    plotting.legend_outside(axis)
    plotting.save(plt, figure, path, footnote=f'data: {data}')


def filter_rate(path: Path, rows: list[dict], costs: list[dict], data: str) -> None:
    """Section 6: RMS attitude error against gain per rate; cost per sample against rate."""
    plt, figure, (errors, cost) = plotting.figure(1, 2)
    for rate in sorted({r['rate_hz'] for r in rows}):
        mine = [r for r in rows if r['rate_hz'] == rate]
        errors.plot([r['gain'] for r in mine], [r['rms_attitude_deg'] for r in mine], 'o-',
                    label=f'{rate:g} Hz')
    errors.set(xscale='log', yscale='log', xlabel='Madgwick gain beta (log)',
               ylabel='RMS attitude error after settling (deg, log)')
    plotting.legend_outside(errors)
    rates = [c['rate_hz'] for c in costs]
    cost.plot(rates, [c['stream_us'] for c in costs], 'o-', label='streaming (the node)')
    cost.plot(rates, [c['batch_us'] for c in costs], 's-', label='batch (compiled)')
    cost.set(xlabel='sample rate (Hz)', ylabel='cost per sample (us)', yscale='log')
    plotting.legend_outside(cost)
    for axis in (errors, cost):
        axis.grid(alpha=0.3)
    plotting.save(plt, figure, path, footnote=f'data: {data}')


def whole_job(path: Path, stages: list[dict], data: str) -> None:
    """Section 7: stacked bars of seconds per stage (this run's wall time, arm time)."""
    plt, figure, axis = plotting.figure()
    bars = ('wall time of this run', "arm's time (simulated s)")
    left = [0.0, 0.0]
    for stage in stages:
        widths = [stage['wall_s'], stage['arm_s']]
        axis.barh(bars, widths, left=left, label=stage['stage'])
        left = [a + b for a, b in zip(left, widths, strict=True)]
    axis.set(xlabel='seconds')
    plotting.legend_outside(axis)
    axis.grid(alpha=0.3, axis='x')
    plotting.save(plt, figure, path, footnote=f'data: {data}')


def identification(path: Path, grid_s: list[float], curves: dict[str, list[float]],
                   data: str) -> None:
    """Section 8: accuracy against contact seconds, one curve per policy."""
    plt, figure, axis = plotting.figure()
    for policy, curve in curves.items():
        axis.plot(grid_s, [100 * a for a in curve], label=policy)
    axis.set(xlabel='contact seconds', ylabel='held-out textures identified right (%)',
             ylim=(0, 101))
    plotting.legend_outside(axis)
    axis.grid(alpha=0.3)
    plotting.save(plt, figure, path, footnote=f'data: {data}')
