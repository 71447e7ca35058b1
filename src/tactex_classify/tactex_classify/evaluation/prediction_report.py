# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What `tactex predict` writes: per recording and per window CSVs, a summary, a confusion.

recordings.csv: per recording its label, first decision, when (seconds from its first
sample), how many decisions, windows, and the last estimate's probabilities.
windows.csv: per classified window its recording, start and end (s) and probabilities.
summary.json: the checkpoint, the settings, and with labels the accuracy grouped by
recording (a recording without a decision counts as wrong) and each class's recall.
confusion.png: true class x first decision, with a 'no decision' column.
"""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np

from tactex_classify.evaluation.training_report import draw_confusion
from tactex_classify.online.replay import Replayed
from tactex_common import plotting

NO_DECISION = 'no decision'


def scores(results: list[Replayed], classes: list[str]) -> dict | None:
    """Accuracy grouped by recording, per-class recall and the confusion (None: no labels)."""
    labelled = [r for r in results if r.label is not None]
    if not labelled:
        return None
    true_names = list(classes) + sorted({r.label for r in labelled} - set(classes))
    columns = list(classes) + [NO_DECISION]
    matrix = np.zeros((len(true_names), len(columns)), dtype=int)
    for result in labelled:
        matrix[true_names.index(result.label), columns.index(result.decision or NO_DECISION)] += 1
    correct = sum(r.decision == r.label for r in labelled)
    # A label the model does not know is never decided: its recall is 0, not unknown; a
    # class of the model's without a labelled recording has no recall (None).
    recall = {name: (float(matrix[i, columns.index(name)] / matrix[i].sum())
                     if name in columns else 0.0) if matrix[i].sum() else None
              for i, name in enumerate(true_names)}
    decided = [r for r in labelled if r.decision is not None]
    return {'recordings': len(labelled), 'accuracy': correct / len(labelled),
            'labels_not_in_model': true_names[len(classes):],
            'undecided': len(labelled) - len(decided),
            'accuracy_of_decided': (sum(r.decision == r.label for r in decided) / len(decided)
                                    if decided else None),
            'recall': recall, 'confusion': {'true': true_names, 'predicted': columns,
                                            'counts': matrix.tolist()}}


def write_report(folder: Path, results: list[Replayed], classes: list[str],
                 settings: dict) -> dict:
    """Write the files into `folder`; return the summary."""
    with open(folder / 'recordings.csv', 'w', newline='') as stream:
        out = csv.writer(stream)
        out.writerow(['recording', 'label', 'decision', 'decided_s', 'decisions', 'windows',
                      *[f'p_{c}' for c in classes]])
        for r in results:
            final = r.final if r.final is not None else np.full(len(classes), np.nan)
            out.writerow([r.name, r.label or '', r.decision or '',
                          '' if r.decided_s is None else f'{r.decided_s:.3f}',
                          len(r.decisions), len(r.windows), *[f'{p:.6f}' for p in final]])
    with open(folder / 'windows.csv', 'w', newline='') as stream:
        out = csv.writer(stream)
        out.writerow(['recording', 'start_s', 'end_s', *[f'p_{c}' for c in classes]])
        for r in results:
            for start, end, proba in r.windows:
                out.writerow([r.name, f'{(start - r.start_ns) / 1e9:.4f}',
                              f'{(end - r.start_ns) / 1e9:.4f}', *[f'{p:.6f}' for p in proba]])
    summary = {**settings, 'classes': list(classes), 'scores': scores(results, classes),
               'recordings': [{'recording': r.name, 'label': r.label, 'decision': r.decision,
                               'decided_s': r.decided_s,
                               'decisions': [[(t - r.start_ns) / 1e9, c] for t, c in r.decisions],
                               'windows': len(r.windows), 'faults': r.faults}
                              for r in results]}
    (folder / 'summary.json').write_text(json.dumps(summary, indent=1, default=_plain))
    if summary['scores'] is not None:
        _plot(folder / 'confusion.png', summary['scores'])
    return summary


def _plain(value):
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(f'{type(value).__name__} is not JSON')


def _plot(path: Path, scores_: dict) -> None:
    confusion = scores_['confusion']
    matrix = np.array(confusion['counts'], dtype=float)
    classes = max(len(confusion['true']), len(confusion['predicted']))
    plt, figure, axis = plotting.figure(classes=classes)
    draw_confusion(axis, matrix, confusion['true'], confusion['predicted'],
                   f'first decision per recording: {100 * scores_["accuracy"]:.1f} % of '
                   f'{scores_["recordings"]} ({scores_["undecided"]} undecided)')
    plotting.save(plt, figure, path)
