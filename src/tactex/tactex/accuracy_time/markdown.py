# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""report.md of the accuracy-time report, from the measured results only."""

from __future__ import annotations

from tactex.accuracy_time.configurations import BUDGET_S, NEAR_BEST
from tactex.accuracy_time.section_text import data_line, percent
from tactex.accuracy_time.sections import Section, SECTIONS
from tactex_classify.models.registry import BASELINES


def command(point: dict, *, epochs: int, folds: int) -> str:
    """Copy-paste command lines that build and run a configuration."""
    window, model = point['window'], point['model']
    epoch_option = '' if model in BASELINES else f' --epochs {epochs}'
    lines = ['tactex sim collect --sweeps 25 --out bags   # or your own recordings',
             f'tactex convert bags --window {window} --hop {window // 2} --out data.npz',
             f'tactex train data.npz --model {model}{epoch_option} --cv grouped --folds {folds} '
             '--out run']
    if point['runtime'] == 'onnxruntime':
        lines.append('tactex export run/model --onnx')
    classify = ('tactex launch classify checkpoint:=run/model '
                f'threshold:={point["threshold"]:.10g} runtime:={point["runtime"]}')
    lines += [f'{classify} source:=sim   # in simulation',
              f'{classify}   # on the arm: the sensor on port:=/dev/ttyACM0']
    return '\n'.join(lines)


def render(results: dict) -> str:
    """The whole report."""
    lines = ['# What accuracy costs in time', '',
             f'Measured by `tactex report accuracy-time` ({results["size"]["name"]} size, seed '
             f'{results["seed"]}) in {results["total_s"] / 60:.1f} min; every number below '
             'comes from this run. Classification: ' + data_line(results) + '.', '',
             '## Three configurations', '']
    titles = {'fastest': f'Fastest decision (least contact time within {100 * NEAR_BEST:g} '
                         'accuracy points of the most accurate)',
              'accurate': 'Most accurate',
              'budget': f'Best under a {BUDGET_S:g} s contact budget'}
    shown: dict[tuple, str] = {}
    for key, title in titles.items():
        point = results['configurations'][key]
        if point is None:
            lines += [f'**{title}**: no configuration decided within {BUDGET_S:g} s.', '']
            continue
        same = (point['model'], point['window'], point['threshold'], point['runtime'])
        if same in shown:
            lines += [f'**{title}**: the same configuration as {shown[same]} above.', '']
            continue
        shown[same] = f'"{title.split(" (")[0]}"'
        lines += [f'**{title}**: {point["model"]}, window {point["window"]}, threshold '
                  f'{point["threshold"]:.10g}: {percent(point["accuracy"])} of sweeps right after '
                  f'a median {point["contact_s"]:.2f} s of contact (earliness '
                  f'{point["earliness"]:.2f}), runtime {point["runtime"]}.', '', '```sh',
                  command(point, epochs=results['size']['epochs'],
                          folds=results['size']['folds']), '```', '']
    for section in SECTIONS:
        lines += section_lines(section, results) + ['']
    return '\n'.join(lines)


def section_lines(section: Section, results: dict) -> list[str]:
    """A section: title, plot, the data it used, notes, its tables (or why not measured)."""
    heading = f'## {section.number}. {section.title}'
    failed = results[section.key].get('failed')
    if failed:
        return [heading, '', f'Not measured: {failed}.']
    text = section.render(results)
    lines = [heading, '', f'![{section.title}]({section.plot_file})', '',
             f'Data: {text.data}. Section time: {results["seconds"][section.key]:.0f} s.', '']
    if text.notes:
        lines += [text.notes, '']
    for rows in text.tables:
        lines += rows + ['']
    return lines

