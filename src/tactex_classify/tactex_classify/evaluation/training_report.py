# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A run's report: metrics.json, report.md and the plots beside them.

The plots are the confusion matrices, the learning curves and the accuracy against
touch time, with both cross-validation schemes side by side.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from tactex_classify.data.dataset import Dataset
from tactex_classify.evaluation.cross_validation import (
    confusion,
    CrossValidation,
    metrics,
    sequence_accuracy,
)
from tactex_classify.training.convergence import unconverged_because, WHAT_TO_CHANGE
from tactex_common import plotting
from tactex_common.naming import natural_key, natural_sorted

LABELS = {'grouped': 'grouped by recording (honest)',
          'stratified': 'stratified windows (leaky)'}


def convergence_notes(result: CrossValidation, classes: int, epochs: int) -> list[str]:
    """A note per fold whose deep model did not converge, saying what to change.

    Why it did not is `unconverged_because`; a baseline's fold has no history.
    """
    notes = []
    for fold, history in enumerate(result.histories, start=1):
        losses = [record['train_loss'] for record in history]
        reason = unconverged_because(losses, classes, epochs)
        if reason == 'stalled at chance':
            notes.append(f'{result.scheme} fold {fold}: not converged: its training loss never '
                         f'fell below chance ({math.log(classes):.2f}, the loss of predicting '
                         f'every class alike) in {len(losses)} epochs, so the model learned '
                         'nothing (early stopping waits while it is at chance); '
                         f'{WHAT_TO_CHANGE[reason]}')
        elif reason:
            notes.append(f'{result.scheme} fold {fold}: not converged: its training loss was '
                         f'still falling at the last of {epochs} epochs; {WHAT_TO_CHANGE[reason]}')
    return notes


# What the report says of the schemes it ran: a stratified split leaks, a grouped one not.
LEAKY = ('Overlapping windows of one recording sit on both sides of a stratified split, so '
         'its numbers are leaky')
SCHEME_NOTES = {('grouped',): 'Every recording sits on one side of a grouped split, so the '
                              'numbers are honest: what the model does on recordings it never '
                              'saw.',
                ('stratified',): f'{LEAKY}; only a grouped split (--cv grouped or both) gives '
                                 'honest ones.',
                ('grouped', 'stratified'): f'{LEAKY}; the grouped numbers are the honest ones.'}


def summarise(dataset: Dataset, results: list[CrossValidation]) -> dict:
    """Every number of the report, per scheme."""
    summary = {}
    for result in results:
        predicted = result.proba.argmax(axis=1)
        matrix = confusion(dataset.y, predicted, len(dataset.classes))
        hop_s = dataset.info.get('hop', 0) / dataset.info.get('sampling_rate_hz', 1.0)
        window_s = dataset.X.shape[1] / dataset.info.get('sampling_rate_hz', 1.0)
        sequence = sequence_accuracy(dataset, result.proba)
        summary[result.scheme] = {
            **metrics(matrix, dataset.classes), 'confusion': matrix.tolist(),
            'sequence': [{'windows': k, 'touch_s': window_s + (k - 1) * hop_s, **point}
                         for k, point in sequence.items()],
            'notes': result.notes, 'histories': result.histories}
    return summary


def console_summary(dataset: Dataset, results: list[CrossValidation],
                    confusions: int = 3) -> list[str]:
    """Terminal lines per scheme: accuracy overall and per fold, the worst confusions.

    A confusion reads "true as predicted (windows)".
    """
    lines = []
    for result in results:
        predicted = result.proba.argmax(axis=1)
        folds = [float(np.mean(predicted[result.fold == f] == dataset.y[result.fold == f]))
                 for f in np.unique(result.fold[result.fold >= 0])]
        overall = 100 * np.mean(predicted == dataset.y)
        lines.append(f'{LABELS[result.scheme]}: accuracy {overall:.1f} % over all windows; '
                     'per fold ' + ' / '.join(f'{100 * a:.1f}' for a in folds) +
                     f' (mean {100 * np.mean(folds):.1f} ± {100 * np.std(folds):.1f} %)')
        matrix = confusion(dataset.y, predicted, len(dataset.classes))
        np.fill_diagonal(matrix, 0)
        worst = [index for index in np.argsort(matrix, axis=None)[::-1][:confusions]
                 if matrix.flat[index] > 0]
        if worst:
            lines.append('  most confused: ' + ', '.join(
                f'{dataset.classes[i // matrix.shape[1]]} as '
                f'{dataset.classes[i % matrix.shape[1]]} ({matrix.flat[i]})' for i in worst))
    return lines


def write_report(folder: Path, dataset: Dataset, results: list[CrossValidation], *,
                 title: str, settings: dict, data_name: str) -> Path:
    """Write metrics.json, report.md and the PNGs into `folder`; return report.md."""
    folder.mkdir(parents=True, exist_ok=True)
    summary = summarise(dataset, results)
    (folder / 'metrics.json').write_text(json.dumps(
        {'title': title, 'data': data_name, 'settings': settings, 'schemes': summary},
        indent=2), encoding='utf-8')
    plot_run(folder, dataset.classes, summary)
    schemes = list(summary)
    lines = [f'# {title}', '',
             f'Data: `{data_name}`: {len(dataset.X)} windows of {dataset.X.shape[1]} samples '
             f'({dataset.info.get("sampling_rate_hz", float("nan")):.0f} Hz), '
             f'{len(np.unique(dataset.trial))} recordings, {len(dataset.classes)} classes.',
             f'Settings: {json.dumps(settings)}', '',
             '| metric | ' + ' | '.join(LABELS[s] for s in schemes) + ' |',
             '|---|' + '---|' * len(schemes)]
    for key in ('accuracy', 'macro_precision', 'macro_recall', 'macro_f1'):
        lines.append(f'| {key.replace("_", " ")} | ' + ' | '.join(
            f'{100 * summary[s][key]:.1f} %' for s in schemes) + ' |')
    lines += ['', SCHEME_NOTES[tuple(sorted(schemes))], '',
              '## Per class', '',
              '| class | ' + ' | '.join(f'{s} precision | {s} recall' for s in schemes) + ' |',
              '|---|' + '---|---|' * len(schemes)]
    for name in natural_sorted(dataset.classes):
        lines.append(f'| {name} | ' + ' | '.join(
            f'{100 * summary[s]["per_class"][name]["precision"]:.1f} | '
            f'{100 * summary[s]["per_class"][name]["recall"]:.1f}' for s in schemes) + ' |')
    lines += ['', '## Accuracy against touch time (summed log-probabilities of consecutive '
              'windows of a test recording)', '',
              'A row counts the recordings of at least that many windows; one marked * has '
              'lost a class (none of its recordings is that long), so it does not compare '
              'with the rows above.', '',
              '| windows | touch time s | recordings (classes) | ' + ' | '.join(schemes) + ' |',
              '|---|---|---|' + '---|' * len(schemes)]
    first = summary[schemes[0]]['sequence']
    for row_index, row in enumerate(first):
        counts = (f'{row["recordings"]} ({row["classes"]} of {len(dataset.classes)})'
                  + (' *' if row['classes'] < len(dataset.classes) else ''))
        lines.append(f'| {row["windows"]} | {row["touch_s"]:.2f} | {counts} | ' + ' | '.join(
            f'{100 * summary[s]["sequence"][row_index]["accuracy"]:.1f} %' for s in schemes)
            + ' |')
    notes = [n for s in schemes for n in summary[s]['notes']]
    if notes:
        lines += ['', '## Notes', ''] + [f'- {n}' for n in notes]
    lines += ['', '![confusion](confusion.png)', '', '![learning curves](learning_curves.png)',
              '', '![accuracy vs time](accuracy_vs_time.png)', '']
    path = folder / 'report.md'
    path.write_text('\n'.join(lines), encoding='utf-8')
    return path


def plot_run(folder: Path, classes: list[str], summary: dict) -> None:
    """The run's three PNGs from its per-scheme summary (as metrics.json keeps it)."""
    _plot_confusions(folder / 'confusion.png', classes, summary)
    _plot_learning(folder / 'learning_curves.png', summary)
    _plot_sequence(folder / 'accuracy_vs_time.png', summary)


def _plot_confusions(path: Path, classes: list[str], summary: dict) -> None:
    plt, figure, axes = plotting.figure(1, len(summary), classes=len(classes), squeeze=False)
    order = sorted(range(len(classes)), key=lambda i: natural_key(classes[i]))
    classes = [classes[i] for i in order]
    for axis, (scheme, values) in zip(axes[0], summary.items(), strict=True):
        matrix = np.array(values['confusion'], dtype=float)[np.ix_(order, order)]
        draw_confusion(axis, matrix, classes, classes,
                       f'{LABELS[scheme]}: {100 * values["accuracy"]:.1f} %')
    plotting.save(plt, figure, path)


def draw_confusion(axis, matrix: np.ndarray, true: list[str], predicted: list[str],
                   title: str) -> None:
    """Counts (true rows x predicted columns), each row shaded by its share."""
    rows = matrix / np.maximum(matrix.sum(axis=1, keepdims=True), 1)
    axis.imshow(rows, cmap='Blues', vmin=0, vmax=1)
    for (i, j), count in np.ndenumerate(matrix):
        if count:
            axis.text(j, i, int(count), ha='center', va='center', fontsize=7,
                      color='white' if rows[i, j] > 0.5 else 'black')
    axis.set_xticks(range(len(predicted)), predicted, rotation=60, ha='right', fontsize=7)
    axis.set_yticks(range(len(true)), true, fontsize=7)
    axis.set_xlabel('predicted')
    axis.set_ylabel('true')
    axis.set_title(title)


def _plot_learning(path: Path, summary: dict) -> None:
    plt, figure, axes = plotting.figure(1, 2)
    drawn = 0  # one colour per fold, the same in both panels
    for scheme, values in summary.items():
        for fold, history in enumerate(values['histories']):
            if not history:
                continue
            colour, drawn = f'C{drawn % 10}', drawn + 1
            epochs = [h['epoch'] for h in history]
            label = f'{scheme} fold {fold + 1}'
            axes[0].plot(epochs, [h['train_loss'] for h in history], label=label, lw=1,
                         color=colour)
            axes[1].plot(epochs, [h['train_accuracy'] for h in history], lw=1, color=colour)
            if 'val_accuracy' in history[0]:
                axes[1].plot(epochs, [h['val_accuracy'] for h in history], '--', lw=1,
                             color=colour)
    axes[0].set_xlabel('epoch')
    axes[0].set_ylabel('training loss')
    axes[1].set_xlabel('epoch')
    axes[1].set_ylabel('accuracy (dashed: early-stopping split)')
    if drawn:
        plotting.legend_outside(axes[1], source=axes[0])
    else:
        axes[0].text(0.5, 0.5, 'no epochs: not an iteratively trained model',
                     ha='center', transform=axes[0].transAxes)
    plotting.save(plt, figure, path)


def _plot_sequence(path: Path, summary: dict) -> None:
    plt, figure, axis = plotting.figure()
    for scheme, values in summary.items():
        axis.plot([r['touch_s'] for r in values['sequence']],
                  [100 * r['accuracy'] for r in values['sequence']], 'o-', label=LABELS[scheme])
    axis.set_xlabel('touch time (s)')
    axis.set_ylabel('accuracy (%)')
    axis.set_xlim(left=0)
    plotting.legend_outside(axis)
    axis.grid(alpha=0.3)
    plotting.save(plt, figure, path)
