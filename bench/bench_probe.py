# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Pathway accuracy against probing time, and where the remaining error comes from.

Every run probes the same line of the uneven plate (probe scene: the original's 8 mm /
120 mm concave-convex wave, sensor noise and barometer on) closed-loop in the simulator
(`tactex_probe.closed_loop`), and scores each contact against the true surface: the
angle between the reported and the true normal at the nearest surface point, and the
distance from the reported point to the surface.

1. Accuracy against total probing time (simulated seconds, the arm's time): the
   original's method (tool vertical, one touch, normal from the deformed orientation,
   point where the body's torque puts the contact) as the reference measured in the same
   run; the face alone turned to the extrapolated normal with refinement; and ours
   (locate with the tip, measure with the face) at several descent speeds, step sizes
   and refinement counts. Table, and `bench/results/probe_accuracy_vs_time.png` drawn
   from the points kept beside it (`--plot` redraws it without probing).
2. Error budget of our default run: per contact, the normal error split into the
   orientation filter's (estimated face normal against the true face normal of the
   simulated body) and the compliance model's (the true face normal against the true
   surface normal: the body not lying flat, the face's size on a curved surface); the
   position error beside the contact timing: the lag of the detected onset behind the
   first simulated contact, and the travel of the descent in that time.
3. The default run again on the texture scene (the texture effect's vibration fools
   the filter; the gravity cross-check takes over).

Run: `python bench/bench_probe.py` (a few minutes on one core; `--plot` redraws the figure
from the kept points).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
from pathlib import Path
import sys
import time

import numpy as np
from transforms3d.quaternions import quat2mat

from tactex_common import plotting
from tactex_probe.closed_loop import (
    nearest_surface_point,
    PLATE_LINE,
    run_probe,
    score_run,
    summary,
    true_normal,
)
from tactex_probe.explorer_interface import ExplorerConfig, Method
from tactex_probe.motion import FACE_AXIS
from tactex_probe.normals import angle_between
from tactex_probe.pathway import ProbeParameters
from tactex_sim.scene import load_scene, resolve_scene

RESULTS = Path(__file__).parent / 'results'
KEPT = RESULTS / 'probe_accuracy_vs_time.json'  # the plotted points, so `--plot` redraws
LINE = PLATE_LINE


@dataclasses.dataclass(frozen=True)
class Variant:
    """One probing configuration."""

    label: str
    config: ExplorerConfig
    descent_speed: float = 0.005
    step: float = 0.01


ORIGINAL = Variant('original: vertical, one touch',
                   ExplorerConfig(method=Method.FACE_ONLY, align_tool=False, refinements=0))
VARIANTS = [
    ORIGINAL,
    Variant('face only, aligned, 2 refinements',
            ExplorerConfig(method=Method.FACE_ONLY, refinements=2)),
    Variant('tip+face (default)', ExplorerConfig()),
    Variant('tip+face, no refinement', ExplorerConfig(refinements=0)),
    Variant('tip+face, 2.5 mm/s descent', ExplorerConfig(), descent_speed=0.0025),
    Variant('tip+face, 10 mm/s descent', ExplorerConfig(), descent_speed=0.010),
    Variant('tip+face, 20 mm/s descent', ExplorerConfig(), descent_speed=0.020),
    Variant('tip+face, 5 mm step', ExplorerConfig(), step=0.005),
    Variant('tip+face, 20 mm step', ExplorerConfig(), step=0.02),
]


def probe(variant: Variant, scene_name: str = 'probe'):
    parameters = ProbeParameters(**LINE, step=variant.step, descent_speed=variant.descent_speed)
    started = time.perf_counter()
    run = run_probe(load_scene(resolve_scene(scene_name)), parameters, variant.config)
    return run, time.perf_counter() - started


def budget(run, descent_speed: float) -> list[dict[str, float]]:
    """Per contact: total, filter and compliance normal errors (deg); position errors (mm)."""
    trace = run.trace
    times = trace[:, 0]
    rows = []
    errors = {e.index: e for e in score_run(run)}
    for record in run.pathway.contacts:
        measured = run.measurements[record.index]
        start, end = (t * 1e-9 for t in measured.window_ns)
        inside = (times >= start) & (times <= end)
        attitudes = trace[inside, 5:9]
        true_face = np.mean([-(quat2mat(q) @ FACE_AXIS) for q in attitudes], axis=0)
        nearest = nearest_surface_point(run.surface, record.position)
        surface_normal = true_normal(run.surface, float(nearest[0]))
        onset = measured.onset_ns * 1e-9
        near = (times > onset - 1.0) & (times < onset + 1.0) & (trace[:, 9] > 0.5)
        first_touch = float(times[near][0]) if near.any() else math.nan
        rows.append({
            'normal': errors[record.index].normal_deg,
            'filter': math.degrees(angle_between(measured.estimate.normal, true_face)),
            'compliance': math.degrees(angle_between(true_face, surface_normal)),
            'position': errors[record.index].position_mm,
            'lag': (onset - first_touch) * 1e3,
            'timing': abs(onset - first_touch) * descent_speed * 1e3})
    return rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--plot', action='store_true',
                        help=f'redraw the plot from the kept points ({KEPT.name}), probe nothing')
    if parser.parse_args().plot:
        try:
            variants = json.loads(KEPT.read_text(encoding='utf-8'))
            plot(variants)
        except (OSError, ValueError, KeyError, TypeError) as err:
            print(f'error: --plot: cannot draw from {KEPT} ({err}); run the bench without '
                  '--plot to probe and keep the points again', file=sys.stderr)
            return 1
        return 0
    RESULTS.mkdir(exist_ok=True)
    print(__doc__.split('\n')[0])
    print(f'line: {LINE}; times are simulated seconds of arm time for the whole line\n')
    header = (f'{"variant":38s} {"points":>6s} {"ok":>3s} {"time s":>7s} {"normal mean":>11s} '
              f'{"max":>6s} {"pos mean mm":>11s} {"max":>6s} {"wall s":>7s}')
    print(header)
    print('-' * len(header))
    rows = []
    default_run = None
    for variant in VARIANTS:
        run, wall = probe(variant)
        result = summary(score_run(run))
        points = len(run.pathway.probes)
        rows.append((variant, run, result))
        if variant.label == 'tip+face (default)':
            default_run = run
        print(f'{variant.label:38s} {points:6d} {result["contacts"]:3d} {run.sim_time_s:7.1f} '
              f'{result["normal_mean_deg"]:9.2f} d {result["normal_max_deg"]:5.2f} '
              f'{result["position_mean_mm"]:11.2f} {result["position_max_mm"]:6.2f} '
              f'{wall:7.1f}', flush=True)
    reference = rows[0][2]
    ours = next(r for v, _, r in rows if v.label == 'tip+face (default)')
    ours_time = next(run.sim_time_s for v, run, _ in rows if v.label == 'tip+face (default)')
    print(f'\nours (default) against the original measured in this run: mean normal error '
          f'{ours["normal_mean_deg"] / reference["normal_mean_deg"]:.2f}x, mean position '
          f'error {ours["position_mean_mm"] / reference["position_mean_mm"]:.2f}x, probing '
          f'time {ours_time / rows[0][1].sim_time_s:.2f}x')

    print('\nerror budget of the default run (per contact; deg and mm):')
    contacts = budget(default_run, 0.005)
    print(f'{"normal":>8s} {"filter":>8s} {"compliance":>11s} {"position":>9s} '
          f'{"onset lag ms":>13s} {"its travel":>11s}')
    for c in contacts:
        print(f'{c["normal"]:8.2f} {c["filter"]:8.2f} {c["compliance"]:11.2f} '
              f'{c["position"]:9.3f} {c["lag"]:13.1f} {c["timing"]:11.3f}')
    mean = {k: float(np.mean([c[k] for c in contacts])) for k in contacts[0]}
    filter_share = mean['filter'] ** 2 / (mean['filter'] ** 2 + mean['compliance'] ** 2)
    print(f'mean: normal {mean["normal"]:.2f} deg = orientation filter {mean["filter"]:.2f} '
          f'and compliance model {mean["compliance"]:.2f} (variance shares '
          f'{100 * filter_share:.0f} % / {100 * (1 - filter_share):.0f} %); position '
          f'{mean["position"]:.3f} mm, contact timing: the onset lags the first simulated '
          f'contact by {mean["lag"]:.1f} ms, {mean["timing"]:.3f} mm of descent (the '
          f'simulator flags contact a little before the bodies meet, so this bounds the '
          f'timing share rather than adding to the error)')

    texture_run, wall = probe(VARIANTS[2], 'uneven_texture')
    texture = summary(score_run(texture_run))
    used_gravity = sum('gravity used' in p.detail for p in texture_run.pathway.contacts)
    print(f'\ntexture scene, default: {texture["contacts"]} contacts, normal mean '
          f'{texture["normal_mean_deg"]:.2f} deg (max {texture["normal_max_deg"]:.2f}), '
          f'position mean {texture["position_mean_mm"]:.2f} mm (max '
          f'{texture["position_max_mm"]:.2f}); the filter was overruled by gravity at '
          f'{used_gravity} of them ({texture_run.sim_time_s:.0f} s, wall {wall:.0f} s)')

    KEPT.write_text(json.dumps([
        {'variant': variant.label, 'points': len(run.pathway.probes),
         'contacts': result['contacts'], 'probing_s': run.sim_time_s,
         'normal_mean_deg': result['normal_mean_deg'],
         'position_mean_mm': result['position_mean_mm']} for variant, run, result in rows],
        indent=1) + '\n', encoding='utf-8')
    plot(json.loads(KEPT.read_text()))
    return 0


def plot(variants: list[dict]) -> None:
    """Each variant's mean normal and position error against its probing time."""
    plt, figure, axes = plotting.figure(1, 2)
    for axis, key, label, must, goal in (
            (axes[0], 'normal_mean_deg', 'mean normal error (deg)', 3.0, 1.5),
            (axes[1], 'position_mean_mm', 'mean position error (mm)', 2.0, 1.0)):
        for row in variants:
            axis.scatter(row['probing_s'], row[key], s=30)
        axis.axhline(must, color='tab:red', linestyle='--', linewidth=0.8, label='must')
        axis.axhline(goal, color='tab:green', linestyle='--', linewidth=0.8, label='goal')
        axis.set(xlabel='probing time for the line (simulated s)', ylabel=label, yscale='log')
        plotting.legend_outside(axis)
        plotting.label_points(axis, [row['probing_s'] for row in variants],
                              [row[key] for row in variants],
                              [row['variant'] for row in variants], fontsize=7)
    path = RESULTS / 'probe_accuracy_vs_time.png'
    plotting.save(plt, figure, path, footnote='pathway accuracy against probing time '
                  '(uneven plate, noise on; `python bench/bench_probe.py`)')
    print(f'\nplot: {path}')


if __name__ == '__main__':
    sys.exit(main())
