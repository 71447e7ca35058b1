# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Run the eight sections, pick the three configurations, write report.md, PNGs and JSON."""

from __future__ import annotations

from collections.abc import Callable
import json
from pathlib import Path
import tempfile
import time

from tactex.accuracy_time import configurations, markdown
from tactex.accuracy_time.section_text import data_line
from tactex.accuracy_time.sections import data_summary, Run, SECTIONS
from tactex.accuracy_time.sizes import Size


def run_sections(size: Size, *, seed: int, threads: int,
                 progress: Callable[[str], None]) -> dict:
    """Measure every section; the results and the wall seconds each section took.

    A section that may fail and meets a configuration the arm, the planner or the
    simulator cannot do gets `failed` with the reason; the other sections still run.
    """
    started = time.monotonic()

    def log(line: str) -> None:
        progress(f'[{time.monotonic() - started:7.1f} s] {line}')

    results: dict = {'size': size.__dict__, 'seed': seed, 'threads': threads, 'seconds': {}}
    with tempfile.TemporaryDirectory(prefix='tactex-accuracy-time-') as scratch:
        run = Run(size, seed, threads, Path(scratch), log, results)
        for section in SECTIONS:
            log(f'section {section.number}/{len(SECTIONS)}: '
                f'{section.title[0].lower()}{section.title[1:]}')
            began = time.monotonic()
            try:
                results[section.key] = section.measure(run)
            except unmeasurable() as err:
                if not section.may_fail:
                    raise
                results[section.key] = {'failed': f'{type(err).__name__}: {err}'}
                log(f'  section {section.number} not measured: {err}')
            results['seconds'][section.key] = time.monotonic() - began
        results['data'] = data_summary(run)
        results['configurations'] = configurations.choose(results['1']['points'],
                                                          results['2']['rows'])
    results['total_s'] = time.monotonic() - started
    return results


def unmeasurable() -> tuple[type[Exception], ...]:
    """Errors of a configuration the arm, the planner or the simulator cannot do."""
    from tactex_probe.errors import ProbeError
    from tactex_probe.motion import PathUnreachable
    from tactex_sim.errors import SimError
    from tactex_trajectory.errors import TrajectoryError
    return ProbeError, PathUnreachable, SimError, TrajectoryError


def write_report(folder: Path, size: Size, *, seed: int = 0, threads: int = 1,
                 progress: Callable[[str], None] = print) -> dict:
    """Measure everything and write report.md, the PNGs and results.json into `folder`."""
    results = run_sections(size, seed=seed, threads=threads, progress=progress)
    write_files(folder, results)
    return results


def write_files(folder: Path, results: dict) -> None:
    """Write report.md, the PNGs and results.json of measured `results` into `folder`."""
    data = data_line(results)
    for section in SECTIONS:
        if 'failed' not in results[section.key]:
            section.draw(folder / section.plot_file, results, data)
    (folder / 'report.md').write_text(markdown.render(results), encoding='utf-8')
    (folder / 'results.json').write_text(json.dumps(results, indent=1) + '\n',
                                         encoding='utf-8')
