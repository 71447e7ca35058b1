# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The eight sections, one row each: number, title, plot file, how to measure, plot, render.

The runner (runner.py) runs them in order and the page (markdown.py) writes them in
order; both read a section's identity only from `SECTIONS`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from tactex.accuracy_time import (
    classification,
    configurations,
    identification,
    physical,
    plots,
    section_text,
    sweep_speed,
    whole_job,
)
from tactex.accuracy_time.section_text import SectionText
from tactex.accuracy_time.sizes import Size


@dataclass
class Run:
    """What the sections of one report share while it is measured."""

    size: Size
    seed: int
    threads: int
    scratch: Path
    log: Callable[[str], None]
    results: dict
    data: classification.Data | None = None


@dataclass(frozen=True)
class Section:
    """One section: what it measures, the plot it draws and the text it renders.

    `measure` returns the section's results (kept under `key` in results.json); `draw`
    writes its plot from the whole results and the data line; `may_fail`: a
    configuration the arm, the planner or the simulator cannot do is reported in the
    section, and the other sections still run.
    """

    number: int
    title: str
    plot_file: str
    measure: Callable[[Run], dict]
    draw: Callable[[Path, dict, str], None]
    render: Callable[[dict], SectionText]
    may_fail: bool = True

    @property
    def key(self) -> str:
        """The section's key in results.json."""
        return str(self.number)


def _measure_contact_time(run: Run) -> dict:
    run.data = classification.build_data(run.scratch, run.size, run.log)
    return classification.contact_time(run.data, run.size, run.log, seed=run.seed,
                                       threads=run.threads)


def _measure_compute_time(run: Run) -> dict:
    return classification.compute_time(run.data, run.results['1'], run.size, run.scratch,
                                       run.log, seed=run.seed, threads=run.threads)


def _measure_whole_job(run: Run) -> dict:
    probe = run.results['3']
    if 'failed' in probe:
        return {'failed': 'it starts from section 3, which was not measured'}
    chosen = configurations.choose(run.results['1']['points'], run.results['2']['rows'])
    job = chosen['budget'] or chosen['accurate']
    return whole_job.whole_job(probe.pop('_first_run'), run.scratch, run.size, job['model'],
                              job['threshold'], run.log, seed=run.seed, threads=run.threads)


def _draw_compute_time(path: Path, results: dict, data: str) -> None:
    plots.compute_time(path, results['2']['rows'], f'{data}, window {results["2"]["window"]}')


def _draw_probing(path: Path, results: dict, data: str) -> None:
    plots.probing(path, results['3']['rows'],
                  f'closed-loop probing, {results["3"]["span_mm"]:g} mm line, probe scene')


def _draw_sweep_speed(path: Path, results: dict, data: str) -> None:
    fourth = results['4']
    plots.sweep_speed(path, fourth['rows'], f'uneven_texture, {fourth["contact_s"]:g} s '
                      f'sliding per sweep, {fourth["model"]}, grouped CV')


def _draw_simulation_cost(path: Path, results: dict, data: str) -> None:
    fifth = results['5']
    plots.simulation_cost(path, fifth['rows'], f'{fifth["seconds"]:g} s of sliding over '
                          f'wood, {fifth["scene"]} scene')


def _draw_filter_rate(path: Path, results: dict, data: str) -> None:
    sixth = results['6']
    plots.filter_rate(path, sixth['rows'], sixth['costs'],
                      f'Madgwick MARG, synthetic motions {", ".join(sixth["motions"])}')


def _draw_whole_job(path: Path, results: dict, data: str) -> None:
    plots.whole_job(path, results['7']['stages'], f'one simulated job, model '
                    f'{results["7"]["model"]}')


def _draw_identification(path: Path, results: dict, data: str) -> None:
    eighth = results['8']
    plots.identification(path, eighth['grid_s'], eighth['curves'],
                         f'{eighth["textures"]} textures x {len(eighth["movements"])} '
                         f'movements x {eighth["sweeps"]} sweeps, held out by recording')


SECTIONS: tuple[Section, ...] = (
    Section(1, 'Contact time against accuracy', 'contact_time.png', _measure_contact_time,
            lambda path, results, data: plots.contact_time(path, results['1']['points'], data),
            section_text.contact_time, may_fail=False),
    Section(2, 'Compute time against accuracy', 'compute_time.png', _measure_compute_time,
            _draw_compute_time, section_text.compute_time, may_fail=False),
    Section(3, 'Probing time against reconstruction accuracy', 'probing_time.png',
            lambda run: physical.probing(run.size, run.log), _draw_probing,
            section_text.probing),
    Section(4, 'Sweep speed against accuracy', 'sweep_speed.png',
            lambda run: sweep_speed.sweep_speed(run.scratch, run.size, run.log, seed=run.seed),
            _draw_sweep_speed, section_text.sweep_speed),
    Section(5, 'Simulation cost against fidelity', 'simulation_cost.png',
            lambda run: physical.simulation_cost(run.size, run.log, seed=run.seed),
            _draw_simulation_cost, section_text.simulation_cost),
    Section(6, 'Filter rate against attitude accuracy', 'filter_rate.png',
            lambda run: physical.filter_rate(run.size, run.log, seed=run.seed),
            _draw_filter_rate, section_text.filter_rate),
    Section(7, 'Where the time goes end to end', 'whole_job.png', _measure_whole_job,
            _draw_whole_job, section_text.whole_job),
    Section(8, 'Choosing each next movement: contact time against accuracy',
            'identification.png',
            lambda run: identification.identification(run.scratch, run.size, run.log,
                                                      seed=run.seed),
            _draw_identification, section_text.identification),
)


def data_summary(run: Run) -> dict:
    """What the classification sections ran on, for results.json and the data line."""
    first = run.data.datasets[run.size.windows[0]]
    return {'recordings': int(len(set(first.trial))), 'rate_hz': run.data.rate_hz,
            'collect_s': run.data.collect_s,
            'windows': {str(w): len(d.y) for w, d in run.data.datasets.items()},
            'classes': first.classes}
