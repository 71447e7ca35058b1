# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A comparison's table and plots: per model x window, both schemes, mean +- sd over cells.

The table has the layout of the original's comparison (window, model, training
accuracy, accuracy, precision, recall), with the grouped (honest) and stratified
(leaky) schemes side by side, each figure the mean +- sd over the seeds and folds that
finished, plus the epochs, the training time per fold and the latency of one window.
`summary.json`, `report.md`, `accuracy.png` and `cost.png` are written together (the cost
plot, against grouped accuracy, only where the grid ran grouped).
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable
import json
from pathlib import Path

import numpy as np

from tactex_classify.evaluation.cross_validation import confusion, metrics
from tactex_classify.models.registry import ALL_MODELS, BASELINES, SCHEMES
from tactex_classify.training.convergence import unconverged_because
from tactex_common import plotting
from tactex_common.numbers import is_finite_number

SCHEME_LABELS = {'grouped': 'grouped by recording (honest)',
                 'stratified': 'stratified windows (leaky)'}
# Points the cost plot names one by one; beyond it, only the Pareto front is named.
MAX_COST_LABELS = 16
FIGURES = ('accuracy', 'macro_precision', 'macro_recall', 'macro_f1', 'train_accuracy',
           'train_s', 'latency_ms', 'throughput_ms', 'epochs_per_s', 'chosen_epoch')


def _spread(values: list) -> dict | None:
    """Mean, sd (n - 1) and count of the values that exist."""
    present = [float(v) for v in values if v is not None]
    if not present:
        return None
    return {'mean': float(np.mean(present)),
            'sd': float(np.std(present, ddof=1)) if len(present) > 1 else 0.0,
            'min': min(present), 'max': max(present), 'n': len(present)}


def cell_unconverged_because(cell: dict, classes: int) -> str | None:
    """Why a kept cell's training did not converge, or None if it did or is a baseline's.

    `unconverged_because` of the cell's training losses and epochs.
    """
    losses = cell.get('train_losses') or []
    if not losses:
        return None
    return unconverged_because(losses, classes, (cell.get('config') or {}).get(
        'epochs', len(losses)))


def summarise(results: list[dict], classes: dict[int, list[str]]) -> list[dict]:
    """One row per (window, model), best honest accuracy first within a window.

    A row is `not_converged` when a cell's training did not converge
    (`cell_unconverged_because`); such rows follow the converged ones.

    Per scheme: every figure as mean, sd, range and count over the row's cells, and the
    metrics of the confusion matrix summed over them (the original's way).
    """
    groups: dict[tuple, dict[str, list[dict]]] = defaultdict(lambda: defaultdict(list))
    for result in results:
        cell = result['cell']
        groups[(cell['window'], cell['model'])][cell['scheme']].append(result)
    rows = []
    for (window, model), schemes in groups.items():
        row = {'window': window, 'model': model, 'schemes': {},
               'not_converged': any(cell_unconverged_because(c, len(classes[window]))
                                    for cells in schemes.values() for c in cells)}
        for scheme, cells in schemes.items():
            names = classes[window]
            pooled = confusion(np.concatenate([c['y_true'] for c in cells]).astype(int),
                               np.concatenate([c['y_pred'] for c in cells]).astype(int),
                               len(names))
            pooled_scores = metrics(pooled, names)
            row['schemes'][scheme] = {
                'cells': len(cells), **{key: _spread([c.get(key) for c in cells])
                                        for key in FIGURES},
                'pooled': {key: pooled_scores[key] for key in
                           ('accuracy', 'macro_precision', 'macro_recall', 'macro_f1')},
                'confusion': pooled.tolist()}
        rows.append(row)
    _compare_with_best_baseline(rows, groups)
    order = {name: index for index, name in enumerate(ALL_MODELS)}
    # A row whose training had not converged is never ranked among the converged ones.
    return sorted(rows, key=lambda r: (r['window'], r['not_converged'],
                                       -_mean(r, 'grouped', 'accuracy'),
                                       order.get(r['model'], len(order))))


def paired_difference(ours: dict, theirs: dict) -> dict | None:
    """Mean and 95 % interval of ours - theirs over the keys both have (paired cells).

    The interval is Student's t over the paired differences (n - 1 degrees of freedom),
    cut to the differences two accuracies can have (-1..1: few pairs give a wide t
    interval); one pair has no interval (low and high None), and no pair gives None.
    """
    from scipy import stats
    shared = sorted(set(ours) & set(theirs))
    if not shared:
        return None
    differences = np.array([ours[key] - theirs[key] for key in shared], dtype=float)
    mean = float(differences.mean())
    if len(differences) < 2:
        return {'mean': mean, 'low': None, 'high': None, 'n': 1}
    half = float(stats.t.ppf(0.975, len(differences) - 1) * differences.std(ddof=1)
                 / np.sqrt(len(differences)))
    low, high = np.clip([mean - half, mean + half], -1.0, 1.0)  # (NaN stays NaN)
    return {'mean': mean, 'low': float(low), 'high': float(high), 'n': len(differences)}


def _compare_with_best_baseline(rows: list[dict], groups: dict) -> None:
    """Give each deep row its paired grouped difference to its window's best baseline.

    Cells pair by seed and fold: the same training and test recordings for both models.
    """
    def accuracies(window: int, model: str) -> dict:
        return {(c['cell']['seed'], c['cell']['fold']): c['accuracy']
                for c in groups[(window, model)].get('grouped', [])}
    for window in {row['window'] for row in rows}:
        baselines = [row for row in rows if row['window'] == window and row['model'] in BASELINES
                     and 'grouped' in row['schemes']]
        if not baselines:
            continue
        best = max(baselines, key=lambda row: _mean(row, 'grouped', 'accuracy'))['model']
        for row in rows:
            if row['window'] == window and row['model'] not in BASELINES:
                difference = paired_difference(accuracies(window, row['model']),
                                               accuracies(window, best))
                if difference is not None:
                    row['vs_best_baseline'] = {'baseline': best, **difference}


def _mean(row: dict, scheme: str, key: str) -> float:
    figure = row['schemes'].get(scheme, {}).get(key)
    return figure['mean'] if figure else float('nan')


def _percent(figure: dict | None) -> str:
    return '-' if figure is None else f'{100 * figure["mean"]:.1f} ± {100 * figure["sd"]:.1f}'


def _epochs(row: dict) -> str:
    """Epochs trained: fixed, or the range early stopping chose."""
    figure = row['schemes'].get('grouped', row['schemes'].get('stratified', {})).get(
        'chosen_epoch')
    if figure is None:
        return '-'
    if figure['min'] == figure['max']:
        return f'{figure["min"]:.0f}'
    return f'{figure["mean"]:.0f} ({figure["min"]:.0f}-{figure["max"]:.0f})'


def table(rows: list[dict], expected_cells: int | None = None) -> str:
    """The markdown comparison table (percentages as mean ± sd over cells).

    `expected_cells` is the cells a row has when its grid is complete (seeds x folds x
    schemes); the last column then shows how far each row is. A scheme no row ran has no
    columns.
    """
    schemes = _schemes_run(rows)
    head = ['window', 'model', 'epochs', 'training accuracy']
    for scheme in schemes:
        tag = 'honest' if scheme == 'grouped' else 'leaky'
        head += [f'accuracy ({tag})', f'precision ({tag})', f'recall ({tag})']
    honest = 'grouped' in schemes  # the paired difference is of grouped accuracy only
    head += ['training s per fold', 'latency ms', 'cells'] + (
        ['vs best baseline (honest, paired, 95 % CI)'] if honest else [])
    lines = ['| ' + ' | '.join(head) + ' |', '|' + '---|' * len(head)]
    for row in rows:
        costs = row['schemes'].get('grouped' if honest else schemes[0], {})
        label = _model_label(row['model']) + (' (not converged)' if row.get('not_converged')
                                              else '')
        cells = [str(row['window']), label, _epochs(row),
                 _percent(costs.get('train_accuracy'))]
        for scheme in schemes:
            values = row['schemes'].get(scheme, {})
            cells += [_percent(values.get(key)) for key in
                      ('accuracy', 'macro_precision', 'macro_recall')]
        train_s, latency = costs.get('train_s'), costs.get('latency_ms')
        done = sum(values['cells'] for values in row['schemes'].values())
        cells += ['-' if train_s is None else f'{train_s["mean"]:.0f}',
                  '-' if latency is None else f'{latency["mean"]:.2f}',
                  f'{done}' + (f' of {expected_cells}' if expected_cells else '')] + (
            [_versus(row.get('vs_best_baseline'))] if honest else [])
        lines.append('| ' + ' | '.join(cells) + ' |')
    return '\n'.join(lines) + '\n'


def _schemes_run(rows: list[dict]) -> list[str]:
    """The schemes some row ran, in the table's order (all of them for no rows)."""
    run = [scheme for scheme in SCHEMES if any(scheme in row['schemes'] for row in rows)]
    return run or list(SCHEMES)


def _versus(difference: dict | None) -> str:
    """'+8.7 [+2.1, +15.3] vs multirocket' in points, '+8.7 (one pair) vs ...', or '-'."""
    if difference is None:
        return '-'
    if difference['low'] is None:
        return (f'{100 * difference["mean"]:+.1f} (one pair, no interval) vs '
                f'{difference["baseline"]}')
    return (f'{100 * difference["mean"]:+.1f} [{100 * difference["low"]:+.1f}, '
            f'{100 * difference["high"]:+.1f}] vs {difference["baseline"]}')


def _model_label(model: str) -> str:
    return f'{model} (baseline)' if model in BASELINES else model


def fold_notes(results: list[dict]) -> list[str]:
    """One line per fold whose training windows lack a class (every model shares the folds)."""
    absent = {}
    for result in results:
        cell = result['cell']
        if result.get('absent_from_training'):  # cells kept before it was recorded: none
            absent[(cell['window'], cell['scheme'], cell['seed'], cell['fold'])] = \
                result['absent_from_training']
    return [f'window {window}, {scheme} fold {fold}, seed {seed}: {", ".join(names)}'
            for (window, scheme, seed, fold), names in sorted(absent.items())]


def write_report(folder: Path, results: list[dict], manifest: dict, *,
                 expected_cells: int | None = None) -> Path:
    """Write summary.json, report.md, accuracy.png and cost.png (grouped runs) into `folder`."""
    classes = {int(window): data['classes'] for window, data in manifest['data'].items()}
    rows = summarise(results, classes)
    (folder / 'summary.json').write_text(json.dumps(
        {'settings': manifest['settings'], 'data': manifest['data'], 'rows': rows},
        indent=1) + '\n', encoding='utf-8')
    plot_grid(folder, rows)
    settings = manifest['settings']
    data = ', '.join(f'{window}: {d["windows"]} windows of {d["recordings"]} recordings'
                     for window, d in sorted(manifest['data'].items(), key=lambda i: int(i[0])))
    described = {'grouped': 'grouped by recording (honest)',
                 'stratified': 'stratified by window (leaky: overlapping windows of one '
                               'recording on both sides)'}
    schemes = ' and '.join(described[scheme] for scheme in _schemes_run(rows))
    lines = ['# Model comparison', '',
             f'Data ({data}); {settings["folds"]}-fold cross-validation, {schemes}; at most '
             f'{settings["epochs"]} epochs' + (f', early stopping after '
                                                f'{settings["early_stopping"]} epochs without '
                                                'improvement on held-out recordings'
                                                if settings['early_stopping'] else '')
             + f'; deep models trained with the {settings.get("profile", "original")} profile '
             f'and {settings.get("scaling", "minmax")} scaling'
             + '. Figures are mean ± sd over seeds and folds (%); training time is seconds '
             'per fold, latency the time to classify one window.', '',
             table(rows, expected_cells)]
    notes = fold_notes(results)
    if notes:
        lines += ["Classes absent from a fold's training windows (too few recordings of "
                  'them for the folds), so none of their held-out windows can be right there:',
                  '', *(f'- {note}' for note in notes), '']
    if any(row['not_converged'] for row in rows):
        lines += ['A row marked (not converged) has a cell whose training loss was still '
                  'falling at its last epoch, or never fell below chance (the loss of '
                  'predicting every class alike): it is ranked after the converged rows and '
                  'left off the Pareto front.', '']
    lines += ['![accuracy](accuracy.png)', '']
    lines += (['![cost](cost.png)', ''] if 'grouped' in _schemes_run(rows) else [
        'No cost plot: it sets cost against accuracy grouped by recording, which this grid '
        'did not run (`--cv grouped` or `both`).', ''])
    path = folder / 'report.md'
    path.write_text('\n'.join(lines), encoding='utf-8')
    return path


def plot_grid(folder: Path, rows: list[dict]) -> list[Path]:
    """accuracy.png and cost.png of a comparison's rows (as summary.json keeps them).

    Returns the files drawn: cost.png only where the grid ran grouped (it plots cost
    against grouped accuracy).
    """
    drawn = [folder / 'accuracy.png']
    _plot_accuracy(drawn[0], rows)
    if 'grouped' in _schemes_run(rows):
        drawn.append(folder / 'cost.png')
        _plot_cost(drawn[-1], rows)
    return drawn


def _plot_accuracy(path: Path, rows: list[dict]) -> None:
    windows = sorted({row['window'] for row in rows})
    plt, figure, axes = plotting.figure(1, max(len(windows), 1), squeeze=False)
    for axis, window in zip(axes[0], windows, strict=False):
        picked = [row for row in rows if row['window'] == window]
        positions = np.arange(len(picked))
        for offset, scheme in ((-0.2, 'grouped'), (0.2, 'stratified')):
            figures = [row['schemes'].get(scheme, {}).get('accuracy') for row in picked]
            axis.barh(positions + offset, [100 * f['mean'] if f else 0 for f in figures], 0.4,
                      xerr=[100 * f['sd'] if f else 0 for f in figures],
                      label=SCHEME_LABELS[scheme], capsize=2)
        axis.set_yticks(positions, [_model_label(row['model']) for row in picked], fontsize=8)
        axis.invert_yaxis()
        axis.set_xlim(0, 100)
        axis.set_xlabel('accuracy (%), mean ± sd over seeds and folds')
        axis.set_title(f'window {window}')
        axis.grid(axis='x', alpha=0.3)
    plotting.legend_outside(axes[0][-1], source=axes[0][0])
    plotting.save(plt, figure, path)


def pareto_front(items: list, point: Callable = lambda item: item) -> list:
    """The items whose (cost, accuracy) `point` no other item beats in both, cheapest first.

    Items at the same point are all on the front or all off it. An item whose cost or
    accuracy is not finite (NaN from a corrupt file) cannot be compared, so is left off.
    """
    comparable = [item for item in items if all(is_finite_number(v) for v in point(item))]
    front: list = []
    for item in sorted(comparable, key=lambda item: (point(item)[0], -point(item)[1])):
        if not front or point(item)[1] > point(front[-1])[1] or point(item) == point(front[-1]):
            front.append(item)
    return front


def cost_point(row: dict, cost: str) -> tuple[float, float]:
    """A summary row's (mean `cost`, grouped accuracy %)."""
    grouped = row['schemes']['grouped']
    return grouped[cost]['mean'], 100 * grouped['accuracy']['mean']


def cost_front(rows: list[dict], cost: str) -> list[dict]:
    """The rows on the Pareto front of (mean `cost`, grouped accuracy %), cheapest first.

    A row marked `not_converged` is never ranked, so it is left off the front.
    """
    ranked = [row for row in rows if row['schemes'].get('grouped', {}).get(cost)
              and row['schemes']['grouped'].get('accuracy') and not row.get('not_converged')]
    return pareto_front(ranked, lambda row: cost_point(row, cost))


def _plot_cost(path: Path, rows: list[dict]) -> None:
    plt, figure, axes = plotting.figure(1, 2)
    markers = dict(zip(sorted({row['window'] for row in rows}), 'os^Dv', strict=False))
    plotted = [row for row in rows if row['schemes'].get('grouped', {}).get('train_s')
               and row['schemes']['grouped'].get('accuracy')]
    costs = ('train_s', 'latency_ms')
    fronts = {key: cost_front(rows, key) for key in costs}
    for row in plotted:
        colour = 'C3' if row['model'] in BASELINES else 'C0'
        for axis, key in zip(axes, costs, strict=True):
            axis.scatter(*cost_point(row, key), marker=markers[row['window']],
                         facecolors='none' if row.get('not_converged') else colour,
                         edgecolors=colour)
    for axis, key in zip(axes, costs, strict=True):
        front = [cost_point(row, key) for row in fronts[key]]
        if len(front) > 1:
            axis.step(*zip(*front, strict=True), where='post', color='k', alpha=0.5,
                      linewidth=1, label='Pareto front')
            plotting.legend_outside(axis)
    for axis, label in zip(axes, ('training time per fold (s)', 'latency of one window (ms)'),
                           strict=True):
        axis.set_xscale('log')
        plotting.plain_log_ticks(axis.xaxis)
        axis.margins(x=0.15, y=0.08)  # room for the labels of the points at the edges
        axis.set_xlabel(label)
        axis.set_ylabel('accuracy, grouped by recording (%)')
        axis.grid(alpha=0.3)
    crowded = len(plotted) > MAX_COST_LABELS
    for axis, key in zip(axes, costs, strict=True):
        named = fronts[key] if crowded else plotted
        points = [cost_point(row, key) for row in named]
        plotting.label_points(
            axis, [cost for cost, _ in points], [accuracy for _, accuracy in points],
            [f'{row["model"]} {row["window"]}'
             + (' (not converged)' if row.get('not_converged') else '') for row in named])
    axes[0].set_title('marker: window (' + ', '.join(
        f'{m} {w}' for w, m in markers.items()) + '); red: baselines; hollow: not converged, '
        'off the front' + ('\nnamed: the Pareto front only (report.md has every row)'
                          if crowded else ''),
        fontsize=8)
    plotting.save(plt, figure, path)
