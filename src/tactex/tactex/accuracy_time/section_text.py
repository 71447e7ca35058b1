# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Each section's text in report.md: the data it used, notes and tables, from results only."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class SectionText:
    """What a section says under its title and plot."""

    data: str
    notes: str
    tables: list[list[str]]


def percent(value: float) -> str:
    """A share as a percentage with one decimal."""
    return f'{100 * value:.1f} %'


def table(columns: list[str], rows: list[list[str]]) -> list[str]:
    """A markdown table's lines."""
    return [f'| {" | ".join(columns)} |', f'|{"---|" * len(columns)}',
            *(f'| {" | ".join(row)} |' for row in rows)]


def labelled(row: dict) -> str:
    """A row's model, marked when it did not converge (a kept run before the mark: none)."""
    return row['model'] + (' (not converged)' if row.get('not_converged') else '')


UNCONVERGED = (' A model marked (not converged) had a fold whose training loss was still '
               'falling at its last epoch, or never fell below chance: its rows are not '
               'results to rank, are left off the Pareto front and never chosen as a '
               'configuration.')


def data_line(results: dict) -> str:
    """What the classification sections ran on."""
    size, data = results['size'], results['data']
    return (f'{data["recordings"]} simulated sweeps (uneven_texture scene, {size["textures"]} '
            f'textures x {size["sweeps"]}, {data["rate_hz"]:g} Hz), grouped '
            f'{size["folds"]}-fold CV by recording')


def contact_time(results: dict) -> SectionText:
    """Section 1: per model and window, every decision rule; the Pareto front marked."""
    rows = [[labelled(p), str(p['window']), p['rule'], f'{p["contact_s"]:.2f}',
             percent(p['accuracy']),
             '—' if p['earliness'] is None else f'{p["earliness"]:.3f}',
             '—' if p['harmonic_mean'] is None else f'{p["harmonic_mean"]:.3f}',
             '**P**' if p['pareto'] else ''] for p in results['1']['points']]
    return SectionText(
        data_line(results),
        'Contact time: for k windows, window length + (k - 1) hops; for the live rule, the '
        "median over sweeps of the contact seconds behind the decision (the node's "
        '`Evidence` replayed on out-of-fold probabilities; a sweep that never meets the '
        "threshold is decided at its end). Earliness: the share of the sweep's windowed "
        'contact used; HM: harmonic mean of accuracy and 1 - earliness (TEASER). '
        '**P**: on the Pareto front over every row.' + UNCONVERGED * any(
            p.get('not_converged') for p in results['1']['points']) + (
            f' Not run: {", ".join(results["1"]["skipped"])}.' if results['1']['skipped']
            else ''),
        [table(['model', 'window', 'rule', 'contact s', 'accuracy', 'earliness', 'HM', ''],
               rows)])


def compute_time(results: dict) -> SectionText:
    """Section 2: accuracy, training time and latency per model and runtime."""
    second = results['2']
    rows = [[labelled(row), percent(row['accuracy']), f'{row["train_s"]:.1f}',
             f'{row["cv_s"]:.0f}', runtime, f'{1e3 * value["single_s"]:.3f}',
             f'{1e3 * value["batched_s"]:.3f}']
            for row in second['rows'] for runtime, value in row['latency'].items()]
    return SectionText(
        f'{data_line(results)}, window {second["window"]}',
        'Training: one fit on every window (the CV column is the whole grouped CV of '
        'section 1). Latency: median of single-window calls after a warm-up, one thread; '
        f'batched: per window in a batch of 64. Deep models train {results["size"]["epochs"]} '
        'epochs here.' + UNCONVERGED * any(row.get('not_converged') for row in second['rows']),
        [table(['model', 'accuracy', 'training s', 'CV s', 'runtime', 'ms per window',
                'ms per window (batch 64)'], rows)])


def probing(results: dict) -> SectionText:
    """Section 3: errors and probing time per step and descent speed."""
    third = results['3']
    rows = [[f'{r["step_mm"]:g}', f'{r["descent_mm_s"]:g}', str(r['points']),
             str(r['contacts']), f'{r["normal_mean_deg"]:.2f} / {r["normal_max_deg"]:.2f}',
             f'{r["position_mean_mm"]:.2f} / {r["position_max_mm"]:.2f}',
             f'{r["probing_s"]:.1f}', f'{r["wall_s"]:.0f}'] for r in third['rows']]
    return SectionText(
        f'closed-loop probing of a {third["span_mm"]:g} mm line of the uneven plate (probe '
        'scene, sensor noise and barometer on), scored against the true surface', '',
        [table(['step mm', 'descent mm/s', 'probes', 'contacts', 'normal mean / max deg',
                'position mean / max mm', 'probing s (simulated)', 'wall s'], rows)])


def sweep_speed(results: dict) -> SectionText:
    """Section 4: contact fraction and accuracy per sliding speed."""
    fourth = results['4']
    rows = [[f'{r["speed_mm_s"]:g}', f'not measured: {r["failed"]}', '', '', '', '', '']
            if r['failed'] else
            [f'{r["speed_mm_s"]:g}', f'{r["distance_mm"]:.0f}',
             f'{percent(r["contact_fraction"])} ({percent(r["contact_fraction_min"])})',
             str(r['windows']), percent(r['window_accuracy']), percent(r['sweep_accuracy']),
             f'{r["collect_s"]:.0f}'] for r in fourth['rows']]
    return SectionText(
        f'uneven_texture sweeps, {fourth["textures"]} textures x {fourth["sweeps"]} per '
        f'speed, {fourth["contact_s"]:g} s of sliding each, window {fourth["window"]}, '
        f'{fourth["model"]}, grouped CV',
        'Every speed gets the same contact time, so faster sweeps cover more texture per '
        'second. Contact fraction: share of the planned sliding samples in true sliding '
        'contact over the texture (what the converter keeps).',
        [table(['speed mm/s', 'distance mm', 'contact mean (worst)', 'windows',
                'window accuracy', 'whole-sweep accuracy', 'collect s'], rows)])


def simulation_cost(results: dict) -> SectionText:
    """Section 5: real-time factor and spectral distance per variant."""
    fifth = results['5']
    rows = [[r['variant'], f'{r["step_ms"]:.3f}', f'{r["real_time_factor"]:.1f}x',
             f'{r["distance_db"]:.2f}' + (f' (without {", ".join(r["not_simulated"])})'
                                          if r['not_simulated'] else '')]
            for r in fifth['rows']]
    return SectionText(
        f'one sweep of the {fifth["scene"]} scene over wood per variant, '
        f'{fifth["seconds"]:g} s of sliding; Welch spectra of accelerometer, gyroscope and '
        'barometer while sliding',
        'Distance: RMS over frequency of 10 log10(power / reference power), averaged over '
        'the 7 signals (those a variant does not simulate left out). The reference with '
        'another noise seed shows what noise alone gives. Real-time factor: one run per '
        'variant, so it carries the load of the machine at that moment.',
        [table(['variant', 'physics step ms', 'real-time factor', 'spectral distance dB'],
               rows)])


def filter_rate(results: dict) -> SectionText:
    """Section 6: errors per rate and gain; cost per sample per rate."""
    sixth = results['6']
    errors = [[f'{r["rate_hz"]:g}', f'{r["gain"]:g}{"*" if r["default"] else ""}',
               f'{r["rms_tilt_deg"]:.3f}', f'{r["rms_attitude_deg"]:.3f}']
              for r in sixth['rows']]
    costs = [[f'{c["rate_hz"]:g}', f'{c["stream_us"]:.1f}', f'{c["batch_us"]:.2f}',
              f'{100 * c["stream_cpu_share"]:.2f} %'] for c in sixth['costs']]
    return SectionText(
        f'Madgwick (MARG) on synthetic motions with exact truth '
        f'({", ".join(sixth["motions"])}; {sixth["seconds"]:g} s each, noise, no gyro bias); '
        'errors after 3 s', f'The default gain ({sixth["default_gain"]:g}) is marked *.',
        [table(['rate Hz', 'gain', 'RMS tilt deg', 'RMS attitude deg'], errors),
         table(['rate Hz', 'us per sample, streaming (the node)', 'batch',
                'CPU share of one core, streaming'], costs)])


def whole_job(results: dict) -> SectionText:
    """Section 7: wall and arm seconds per stage of one job."""
    job = results['7']
    stages = job['stages']
    rows = [[t['stage'], f'{t["wall_s"]:.2f}', f'{t["arm_s"]:.1f}'] for t in stages]
    rows.append(['total', f'{sum(t["wall_s"] for t in stages):.1f}',
                 f'{sum(t["arm_s"] for t in stages):.1f}'])
    return SectionText(
        f'one simulated job: probe ({job["probed"]} contacts), sweep along them, record '
        f'{job["textures"]} textures x {job["sweeps"]} sweeps, convert (window '
        f'{job["window"]}), train {job["model"]}, decide {job["held_out"]} held-out sweeps '
        f'at threshold {job["threshold"]:.10g}',
        f'The planned sweep held {percent(job["contact_fraction"])} of its contact segment; the '
        f'live decisions were right for {percent(job["live_accuracy"])} of the held-out sweeps. '
        'Live decision: mean per sweep (compute wall time; contact seconds).',
        [table(['stage', 'wall s (this run)', 'arm s (simulated)'], rows)])


def identification(results: dict) -> SectionText:
    """Section 8: each policy's accuracy, contact seconds and movements; active against fixed."""
    from tactex.accuracy_time.identification import contact_for
    eighth = results['8']
    policies = eighth['policies']
    rows = [[policy, percent(row['accuracy']), percent(row['decided']),
             f'{row["median_contact_s"]:.1f}', f'{row["p90_contact_s"]:.1f}',
             f'{row["median_movements"]:g}',
             *(percent(row['accuracy_after_k'][min(k, len(row['accuracy_after_k'])) - 1])
               if row['accuracy_after_k'] else '—' for k in (1, 2, 3))]
            for policy, row in policies.items()]
    notes = ('An episode identifies one held-out texture: the policy picks a movement, the '
             "movement's next held-out sweep of that texture updates the belief, until the "
             f'leader passes {eighth["threshold"]:g} or no sweep is left. Accuracy after k: the '
             'leader after k movements.')
    if 'active' in policies and 'fixed' in policies:
        fixed = policies['fixed']
        reached = contact_for(fixed, eighth['grid_s'], eighth['curves']['active'])
        notes += (f' Active reaches fixed\'s final {percent(fixed["accuracy"])} after '
                  + (f'{reached:.1f} s of contact (fixed stops after a median '
                     f'{fixed["median_contact_s"]:.1f} s).' if reached is not None else
                     'no contact time measured here: it ends below it.'))
    tables = [table(['policy', 'accuracy', 'decided', 'median contact s', 'p90 contact s',
                     'median movements', 'after 1', 'after 2', 'after 3'], rows)]
    curves = eighth.get('tradeoff') or {}  # a run kept before the trade-off: none
    if curves:
        notes += (' What a lower threshold buys: each episode cut after its first step whose '
                  'leader passes it (the same movements, as no policy chooses by the '
                  'threshold); accuracy / mean contact seconds per identification.')
        by_threshold = [{row['threshold']: row for row in curve} for curve in curves.values()]
        thresholds = sorted({threshold for rows in by_threshold for threshold in rows})
        tables.append(table(['threshold', *curves], [
            [f'{threshold:g}', *(f'{percent(row["accuracy"])} / {row["mean_contact_s"]:.1f} s'
                                 if (row := rows.get(threshold)) else '—'
                                 for rows in by_threshold)]
            for threshold in thresholds]))
    return SectionText(
        f'{eighth["textures"]} textures x {len(eighth["movements"])} movements '
        f'({", ".join(eighth["movements"])}) x {eighth["sweeps"]} simulated sweeps, '
        f'{eighth["model"]} per movement, {eighth["folds"]} folds grouped by recording x '
        f'{eighth["seeds"]} seeds ({eighth["episodes"]} episodes per policy)',
        notes, tables)
