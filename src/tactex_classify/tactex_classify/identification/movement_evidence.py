# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Per-movement evidence from a dataset: one model per movement, sweep probabilities, calibrated.

Each recording of a dataset made with `tactex sim collect --movements` (or recorded
live under a named movement) belongs to one movement (the sidecar's `recordings`). For
each movement, a model of its own (default: MiniRocket, the best deployable baseline at
the movement file's window) classifies the movement's windows; one sweep's probability
vector is the normalised geometric mean of its windows' probabilities (the evidence the
live node sums, per window, divided by the window count: the windows overlap, so their
product would be overconfident); one temperature per movement (`calibration`) then
calibrates the sweep vectors. Every vector that later enters the evidence table is out
of fold: grouped by recording, no sweep is judged by a model that saw it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from tactex_classify.data.dataset import Dataset
from tactex_classify.evaluation.cross_validation import cross_validate
from tactex_classify.identification.calibration import calibrated, fit_temperature
from tactex_classify.identification.evidence_table import MovementEvidence
from tactex_classify.identification.posterior import normalised
from tactex_classify.online.evidence import log_probabilities
from tactex_classify.training.convergence import unconverged_because
from tactex_description.movements import MovementSet

DEFAULT_MODEL = 'minirocket'


class MovementDataError(ValueError):
    """A dataset that cannot give per-movement evidence, naming what is missing."""


def trial_movements(dataset: Dataset) -> dict[int, str]:
    """Each recording's movement, from the dataset's sidecar.

    Raises:
        MovementDataError: a recording names no movement.
    """
    movements = {int(row['trial']): row.get('movement') for row in
                 dataset.info.get('recordings', []) if isinstance(row, dict) and 'trial' in row}
    unnamed = sorted(trial for trial in np.unique(dataset.trial).tolist()
                     if not isinstance(movements.get(trial), str))
    if unnamed:
        raise MovementDataError(
            f'{len(unnamed)} recording(s) name no movement (trials {unnamed[:5]}'
            f'{"..." if len(unnamed) > 5 else ""}): record them with `tactex sim collect '
            "--movements`, or name each recording's movement in its recording/metadata")
    return {trial: movements[trial] for trial in np.unique(dataset.trial).tolist()}


def checked_movements(dataset: Dataset, movements: MovementSet) -> dict[int, str]:
    """Each recording's movement, every one of them in `movements` and every movement recorded.

    Raises:
        MovementDataError: recordings without a movement, or the dataset and the movement
            file disagree (both differences named).
    """
    movement_of = trial_movements(dataset)
    unknown = sorted(set(movement_of.values()) - set(movements.names))
    missing = sorted(set(movements.names) - set(movement_of.values()))
    if unknown or missing:
        raise MovementDataError(
            'the dataset and the movement file disagree: ' + '; '.join(part for part in (
                f'recorded under movements the file lacks: {", ".join(unknown)}' if unknown
                else '', f'no recording of {", ".join(missing)}' if missing else '') if part))
    check_recorded_parameters(dataset, movement_of, movements)
    return movement_of


# How far the median of a movement's recorded sweeps may sit from the file's value: the
# simulator draws each sweep around it (a few % in speed, tenths of a mm, hundredths of
# a radian), and a file that differs by more describes other sweeps.
PARAMETER_TOLERANCE = {'speed_m_s': ('relative', 0.10), 'press_depth_m': ('absolute', 5e-4),
                       'edge_tilt_rad': ('absolute', 0.1)}


def check_recorded_parameters(dataset: Dataset, movement_of: dict[int, str],
                              movements: MovementSet) -> None:
    """Refuse a movement file whose speed, depth or tilt are not what its recordings ran at.

    Compares each movement's value with the median of its recordings' (the sidecar's
    `sweep`, where convert found one); recordings that do not say are not compared.

    Raises:
        MovementDataError: naming the movement, both values and the fix.
    """
    swept = {int(row['trial']): row['sweep'] for row in dataset.info.get('recordings', [])
             if isinstance(row, dict) and isinstance(row.get('sweep'), dict)
             and isinstance(row.get('trial'), int)}
    for movement in movements.movements:
        rows = [swept[trial] for trial, name in movement_of.items()
                if name == movement.name and trial in swept]
        for key, (kind, tolerance) in PARAMETER_TOLERANCE.items():
            values = [row[key] for row in rows if isinstance(row.get(key), (int, float))]
            if not values:
                continue
            recorded, stated = float(np.median(values)), float(getattr(movement, key))
            off = abs(recorded - stated) / (abs(stated) if kind == 'relative' else 1.0)
            if off > tolerance:
                raise MovementDataError(
                    f'movement {movement.name}: its {len(values)} recordings ran at {key} '
                    f'{recorded:.4g} (median), the movement file says {stated:.4g}: give the '
                    'movement file the recordings were made with')


def trial_labels(dataset: Dataset) -> dict[int, int]:
    """Each recording's texture (a class index), from its first window."""
    trials, first = np.unique(dataset.trial, return_index=True)
    return dict(zip(trials.tolist(), dataset.y[first].tolist(), strict=True))


def cell_counts(classes: Sequence[str], label_of: dict[int, int], movement_of: dict[int, str],
                movements: MovementSet) -> dict[tuple[str, str], int]:
    """Recordings per (texture, movement), every texture under every movement (0 too)."""
    counts = {(texture, name): 0 for texture in classes for name in movements.names}
    for trial, name in movement_of.items():
        counts[(classes[label_of[trial]], name)] += 1
    return counts


def check_cells(counts: dict[tuple[str, str], int], needed: int, settings: str,
                fix: str) -> None:
    """Refuse, before any training, a (texture, movement) cell with fewer than `needed`.

    Args:
        counts: `cell_counts`.
        needed: recordings every cell needs for the folds asked.
        settings: the options that need them, e.g. '--folds 5'.
        fix: what to change when every cell has some but too few.

    Raises:
        MovementDataError: naming the empty cells (record them), else the short ones, the
            count they have and `fix`.
    """
    empty = [cell for cell, count in counts.items() if count == 0]
    if empty:
        raise MovementDataError(
            f'{len(empty)} texture and movement pair(s) have no recording ('
            + ', '.join(f'{texture} under {name}' for texture, name in empty[:4])
            + (', ...' if len(empty) > 4 else '') + '): record every texture under every '
            'movement (tactex sim collect --movements, or sweeps on the arm)')
    short = {cell: count for cell, count in counts.items() if count < needed}
    if short:
        (texture, name), fewest = min(short.items(), key=lambda item: item[1])
        raise MovementDataError(
            f'{settings} need at least {needed} recordings of every texture under every '
            f'movement; {len(short)} pair(s) have fewer ({texture} under {name}: {fewest}): '
            f'{fix}')


def subset(dataset: Dataset, trials: Sequence[int]) -> Dataset:
    """The windows of the recordings `trials`, every class kept."""
    return dataset.select(np.isin(dataset.trial, np.asarray(list(trials))))


def sweep_vector(window_proba: np.ndarray) -> np.ndarray:
    """One sweep's vector: the normalised geometric mean of its windows' probabilities."""
    return np.exp(normalised(log_probabilities(window_proba).mean(axis=0)))


def sweep_vectors(dataset: Dataset, window_proba: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(trials, labels, vectors): each recording's `sweep_vector`."""
    trials = np.unique(dataset.trial)
    vectors = np.stack([sweep_vector(window_proba[dataset.trial == trial])
                        for trial in trials])
    labels = np.array([dataset.y[dataset.trial == trial][0] for trial in trials])
    return trials, labels, vectors


@dataclass(frozen=True)
class FittedMovement:
    """One movement's model and its calibrated out-of-fold sweep vectors."""

    name: str
    temperature: float
    trials: np.ndarray
    labels: np.ndarray
    raw: np.ndarray  # out-of-fold sweep vectors before calibration
    estimator: object  # fitted on every window of the movement
    unconverged: tuple[tuple[str, str], ...] = ()  # ('inner fold 2', 'still falling'), ...
    folds: np.ndarray | None = None  # the inner fold (so the model) that judged each sweep

    @property
    def vectors(self) -> np.ndarray:
        """The calibrated out-of-fold sweep vectors."""
        return calibrated(self.raw, self.temperature)

    def predict_sweeps(self, dataset: Dataset) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(trials, labels, calibrated vectors) of another dataset's recordings."""
        trials, labels, raw = sweep_vectors(dataset, self.estimator.predict_proba(dataset.X))
        return trials, labels, calibrated(raw, self.temperature)


def fit_movement(name: str, dataset: Dataset, make: Callable[[], object], *, folds: int = 3,
                 seed: int = 0) -> FittedMovement:
    """One movement's out-of-fold sweep vectors (grouped `folds`-fold), temperature and model.

    Args:
        name: the movement.
        dataset: its recordings' windows.
        make: a constructor of fresh, unfitted estimators (`build_estimator` of a config).
        folds: grouped folds for the out-of-fold vectors.
        seed: the folds' shuffle.

    Raises:
        MovementDataError: a texture with fewer recordings than folds under this movement.
    """
    trials = np.unique(dataset.trial)
    labels = np.array([dataset.y[dataset.trial == trial][0] for trial in trials])
    counts = np.bincount(labels, minlength=len(dataset.classes))
    if np.any(counts < folds):
        short = [dataset.classes[c] for c in np.flatnonzero(counts < folds)]
        raise MovementDataError(f'movement {name}: {", ".join(short)} recorded fewer than '
                                f'{folds} times; record more sweeps or lower the folds')
    out_of_fold = cross_validate(dataset, make, 'grouped', folds=folds, seed=seed)
    trials, labels, raw = sweep_vectors(dataset, out_of_fold.proba)
    _, first_windows = np.unique(dataset.trial, return_index=True)  # in `trials`' order
    final = make()
    final.fit(dataset.X, dataset.y, dataset.classes, groups=dataset.trial,
              channels=dataset.channels)
    return FittedMovement(name, fit_temperature(raw, labels), trials, labels, raw, final,
                          unconverged(out_of_fold.histories, final, len(dataset.classes)),
                          out_of_fold.fold[first_windows])


def unconverged(histories: list[list[dict]], final: object, classes: int
                ) -> tuple[tuple[str, str], ...]:
    """(training, reason) of each of a movement's deep trainings that did not converge.

    The out-of-fold ones judged from their `histories` against the final model's epochs
    (`unconverged_because`), the final one by itself; a baseline has none.
    """
    if not hasattr(final, 'unconverged_reason'):  # a baseline: nothing to converge
        return ()
    reasons = [(f'inner fold {fold}', unconverged_because(
        [record['train_loss'] for record in history], classes, final.config.epochs))
        for fold, history in enumerate(histories, start=1)]
    reasons.append(('final model', final.unconverged_reason()))
    return tuple((where, why) for where, why in reasons if why)


def movement_evidence(fitted: FittedMovement, contact_seconds: float) -> MovementEvidence:
    """The evidence table's row of a fitted movement."""
    return MovementEvidence(fitted.name, contact_seconds, fitted.vectors, fitted.labels,
                            fitted.folds)
