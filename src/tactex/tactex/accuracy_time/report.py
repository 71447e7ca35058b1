# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Run the seven sections, pick the three configurations, write report.md, PNGs and JSON."""

from __future__ import annotations

from collections.abc import Callable
import json
from pathlib import Path
import tempfile
import time

from tactex.accuracy_time import classification, physical, pipeline, plots, sweep_speed
from tactex.accuracy_time.sizes import Size

BUDGET_S = 2.0
NEAR_BEST = 0.05  # "fastest decision": within this much accuracy of the most accurate


def run_sections(size: Size, *, seed: int, threads: int,
                 progress: Callable[[str], None]) -> dict:
    """Measure every section; the results and the wall seconds each section took."""
    started = time.monotonic()

    def log(line: str) -> None:
        progress(f'[{time.monotonic() - started:7.1f} s] {line}')

    results: dict = {'size': size.__dict__, 'seed': seed, 'threads': threads, 'seconds': {}}

    def section(number: int, title: str, work: Callable[[], dict], *,
                may_fail: bool = False) -> dict:
        """Run one section (`may_fail`: a configuration it cannot do is reported, not fatal).

        The arm, the planner or the simulator refusing one gives the section `failed`
        with the reason; the other sections still run.
        """
        log(f'section {number}/7: {title}')
        began = time.monotonic()
        try:
            results[str(number)] = work()
        except unmeasurable() as err:
            if not may_fail:
                raise
            results[str(number)] = {'failed': f'{type(err).__name__}: {err}'}
            log(f'  section {number} not measured: {err}')
        results['seconds'][str(number)] = time.monotonic() - began
        return results[str(number)]

    with tempfile.TemporaryDirectory(prefix='tactex-accuracy-time-') as scratch:
        scratch = Path(scratch)
        data = None

        def contact():
            nonlocal data
            data = classification.build_data(scratch, size, log)
            return classification.contact_time(data, size, log, seed=seed, threads=threads)
        first = section(1, 'contact time against accuracy', contact)
        second = section(2, 'compute time against accuracy', lambda: classification.compute_time(
            data, first, size, scratch, log, seed=seed, threads=threads))
        results['data'] = {'recordings': int(len(set(data.datasets[size.windows[0]].trial))),
                           'rate_hz': data.rate_hz, 'collect_s': data.collect_s,
                           'windows': {str(w): len(d.y) for w, d in data.datasets.items()},
                           'classes': data.datasets[size.windows[0]].classes}
        results['configurations'] = choose(first['points'], second['rows'])
        probe = section(3, 'probing time against reconstruction accuracy',
                        lambda: physical.probing(size, log), may_fail=True)
        section(4, 'sweep speed against accuracy',
                lambda: sweep_speed.sweep_speed(scratch, size, log, seed=seed), may_fail=True)
        section(5, 'simulation cost against fidelity',
                lambda: physical.simulation_cost(size, log, seed=seed), may_fail=True)
        section(6, 'filter rate against attitude accuracy',
                lambda: physical.filter_rate(size, log, seed=seed), may_fail=True)
        job = results['configurations']['budget'] or results['configurations']['accurate']

        def whole_job() -> dict:
            if 'failed' in probe:
                return {'failed': 'it starts from section 3, which was not measured'}
            return pipeline.whole_job(probe.pop('_first_run'), scratch, size, job['model'],
                                      job['threshold'], log, seed=seed, threads=threads)
        section(7, 'where the time goes end to end', whole_job, may_fail=True)
    results['total_s'] = time.monotonic() - started
    return results


def unmeasurable() -> tuple[type[Exception], ...]:
    """Errors of a configuration the arm, the planner or the simulator cannot do."""
    from tactex_probe.errors import ProbeError
    from tactex_probe.motion import PathUnreachable
    from tactex_sim.errors import SimError
    from tactex_trajectory.errors import TrajectoryError
    return ProbeError, PathUnreachable, SimError, TrajectoryError


def choose(points: list[dict], compute: list[dict]) -> dict:
    """The three configurations, among the live node's threshold rules (below 1: it decides).

    fastest: least contact time within `NEAR_BEST` accuracy of the most accurate;
    accurate: the most accurate (ties: less contact time); budget: the most accurate
    deciding within `BUDGET_S` of contact (None if none does).
    """
    live = [p for p in points if p['threshold'] is not None and p['threshold'] < 1.0]
    accurate = max(live, key=lambda p: (p['accuracy'], -p['contact_s']))
    near = [p for p in live if p['accuracy'] >= accurate['accuracy'] - NEAR_BEST]
    fastest = min(near, key=lambda p: (p['contact_s'], -p['accuracy']))
    within = [p for p in live if p['contact_s'] <= BUDGET_S]
    budget = max(within, key=lambda p: (p['accuracy'], -p['contact_s'])) if within else None
    latency = {row['model']: row['latency'] for row in compute}

    def runtime(point: dict | None) -> dict | None:
        if point is None:
            return None
        timings = latency.get(point['model'], {})
        fastest_runtime = min(timings, key=lambda r: timings[r]['single_s'], default='native')
        return {**point, 'runtime': 'onnxruntime' if fastest_runtime == 'onnxruntime'
                else 'native'}
    return {'fastest': runtime(fastest), 'accurate': runtime(accurate),
            'budget': runtime(budget)}


def write_report(folder: Path, size: Size, *, seed: int = 0, threads: int = 1,
                 progress: Callable[[str], None] = print) -> dict:
    """Measure everything and write report.md, the PNGs and results.json into `folder`."""
    results = run_sections(size, seed=seed, threads=threads, progress=progress)
    write_files(folder, results)
    return results


def write_files(folder: Path, results: dict) -> None:
    """Write report.md, the PNGs and results.json of measured `results` into `folder`."""
    from tactex.accuracy_time import markdown
    data = markdown.data_line(results)
    p = markdown.PLOTS
    plots.contact_time(folder / p['1'], results['1']['points'], data)
    plots.compute_time(folder / p['2'], results['2']['rows'],
                       f'{data}, window {results["2"]["window"]}')
    measured = {number for number in p if 'failed' not in results[number]}
    if '3' in measured:
        plots.probing(folder / p['3'], results['3']['rows'],
                      f'closed-loop probing, {results["3"]["span_mm"]:g} mm line, probe scene')
    if '4' in measured:
        plots.sweep_speed(folder / p['4'], results['4']['rows'],
                          f'uneven_texture, {results["4"]["contact_s"]:g} s sliding per sweep, '
                          f'{results["4"]["model"]}, grouped CV')
    if '5' in measured:
        plots.simulation_cost(folder / p['5'], results['5']['rows'],
                              f'{results["5"]["seconds"]:g} s of sliding over wood, '
                              f'{results["5"]["scene"]} scene')
    if '6' in measured:
        plots.filter_rate(folder / p['6'], results['6']['rows'], results['6']['costs'],
                          'Madgwick MARG, synthetic motions '
                          f'{", ".join(results["6"]["motions"])}')
    if '7' in measured:
        plots.whole_job(folder / p['7'], results['7']['stages'],
                        f'one simulated job, model {results["7"]["model"]}')
    (folder / 'report.md').write_text(markdown.render(results), encoding='utf-8')
    (folder / 'results.json').write_text(json.dumps(results, indent=1) + '\n',
                                         encoding='utf-8')
