# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The demo's figures: pathway accuracy, sweep quality, live decisions, thresholds and plots.

Pure: takes numbers (contacts, sweep results, the estimates heard), returns numbers,
checks them against the thresholds stated in docs/guides/quick-start.md, and draws the PNGs.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
import math
from pathlib import Path

import numpy as np

from tactex_common import plotting
from tactex_probe.closed_loop import nearest_surface_point, true_normal
from tactex_probe.normals import angle_between
from tactex_sim.scene import Surface

# The thresholds each figure is held to (docs/guides/quick-start.md, "The demo").
MIN_CONTACT_SHARE = 0.8  # of the probe points give a contact
MAX_NORMAL_ERROR_DEG = 5.0  # mean, against the true surface
MAX_POSITION_ERROR_MM = 2.0  # mean distance of a contact to the true surface
MIN_CONTACT_FRACTION = 0.75  # mean share of a sweep's sliding spent in contact
MAX_SPEED_ERROR = 0.10  # mean |measured - commanded| / commanded sliding speed
# Accuracy, grouped by recording and live, at least this many times chance (1 / textures):
# a pipeline that loses the labels or the channels on the way scores chance. How far above
# that the textures can be told apart is the sensor's physics, not the pipeline's health
# (docs/topics/simulation.md); the figures themselves are reported.
TIMES_CHANCE = 2.0
MAX_MADGWICK_REJECTED = 0  # samples madgwick_node refused (beyond the chip's full scale)


@dataclass(frozen=True)
class Check:
    """One figure against the threshold it is held to."""

    key: str
    value: float
    limit: float
    unit: str = ''
    at_least: bool = False  # True: the figure must reach the limit; False: stay within it

    @property
    def passed(self) -> bool:
        """Whether the figure meets its threshold (NaN never does)."""
        return self.value >= self.limit if self.at_least else self.value <= self.limit

    def line(self) -> str:
        """`key value (threshold >= limit): PASS|FAIL`."""
        unit = f' {self.unit}' if self.unit else ''
        bound = '>=' if self.at_least else '<='
        return (f'{self.key} {self.value:.4g}{unit} (threshold {bound} {self.limit:.3g}{unit}): '
                f'{"PASS" if self.passed else "FAIL"}')


@dataclass(frozen=True)
class Estimate:
    """One texture/estimate: the label, whether decided, and the contact seconds behind it."""

    label: str
    decided: bool
    contact_s: float


@dataclass(frozen=True)
class LiveSweep:
    """The estimates classifier_node published during one fresh sweep of `truth`."""

    truth: str
    estimates: tuple[Estimate, ...]

    def decision(self) -> Estimate | None:
        """The first decided estimate, else the last one (decided at the sweep's end)."""
        decided = [e for e in self.estimates if e.decided]
        if decided:
            return decided[0]
        return self.estimates[-1] if self.estimates else None


def pathway_errors(positions: np.ndarray, normals: np.ndarray, surface: Surface
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Per contact: the normal's angle to the true one (deg), the distance to the surface (mm)."""
    normal_deg, position_mm = [], []
    for position, normal in zip(positions, normals, strict=True):
        nearest = nearest_surface_point(surface, position)
        position_mm.append(1e3 * float(np.linalg.norm(position - nearest)))
        normal_deg.append(math.degrees(angle_between(normal, true_normal(surface,
                                                                         float(nearest[0])))))
    return np.array(normal_deg), np.array(position_mm)


def path_length(positions: np.ndarray) -> float:
    """Length (m) of the polyline through the probed contacts: the swept curve's, closely."""
    positions = np.asarray(positions, dtype=float).reshape(-1, 3)
    return float(np.linalg.norm(np.diff(positions, axis=0), axis=1).sum())


def live_figures(sweeps: Sequence[LiveSweep]) -> dict[str, float]:
    """Accuracy of the decisions, the median contact seconds at a decision, the counts.

    A sweep that never passed the threshold is decided at its end (its last estimate), so
    its time is the whole contact time; a sweep without any estimate is wrong and untimed.
    """
    decisions = [sweep.decision() for sweep in sweeps]
    correct = [d is not None and d.label == s.truth for d, s in zip(decisions, sweeps,
                                                                    strict=True)]
    times = [d.contact_s for d in decisions if d is not None]
    return {'live_accuracy': float(np.mean(correct)) if sweeps else math.nan,
            'time_to_decision_s': float(np.median(times)) if times else math.nan,
            'live_decided': sum(d is not None and d.decided for d in decisions),
            'live_sweeps': len(sweeps)}


def accuracy_against_contact_time(sweeps: Sequence[LiveSweep], times_s: np.ndarray
                                  ) -> np.ndarray:
    """Share of sweeps whose latest estimate with at most t s of contact is right, per t."""
    accuracy = []
    for t in times_s:
        right = 0
        for sweep in sweeps:
            heard = [e for e in sweep.estimates if e.contact_s <= t]
            right += bool(heard) and heard[-1].label == sweep.truth
        accuracy.append(right / len(sweeps) if sweeps else math.nan)
    return np.array(accuracy)


def confusion(sweeps: Sequence[LiveSweep], classes: Sequence[str]) -> np.ndarray:
    """Counts of (true, decided) class; the last column counts sweeps never estimated."""
    index = {name: i for i, name in enumerate(classes)}
    matrix = np.zeros((len(classes), len(classes) + 1), dtype=int)
    for sweep in sweeps:
        decision = sweep.decision()
        column = index.get(decision.label, len(classes)) if decision is not None \
            else len(classes)
        matrix[index[sweep.truth], column] += 1
    return matrix


def min_accuracy(textures: int) -> float:
    """The least accuracy that shows the pipeline learned: TIMES_CHANCE times chance."""
    return TIMES_CHANCE / textures


def checks(summary: dict, probe_points: int, textures: int, contact_s: float) -> list[Check]:
    """Every thresholded figure of `summary` (summary.json's keys) against its threshold.

    `textures`: how many were swept (chance is one in that many); `contact_s`: a sweep's
    sliding contact, within which the live node must decide (a sweep whose estimates
    never reach its threshold is decided at its end).
    """
    return [
        Check('contacts', summary['contacts'], math.ceil(MIN_CONTACT_SHARE * probe_points),
              at_least=True),
        Check('normal_error_deg_mean', summary['normal_error_deg_mean'], MAX_NORMAL_ERROR_DEG,
              'deg'),
        Check('position_error_mm_mean', summary['position_error_mm_mean'],
              MAX_POSITION_ERROR_MM, 'mm'),
        Check('contact_fraction', summary['contact_fraction'], MIN_CONTACT_FRACTION,
              at_least=True),
        Check('sliding_speed_error', summary['sliding_speed_error'], MAX_SPEED_ERROR),
        Check('cv_accuracy_grouped', summary['cv_accuracy_grouped'], min_accuracy(textures),
              at_least=True),
        Check('live_accuracy', summary['live_accuracy'], min_accuracy(textures), at_least=True),
        Check('time_to_decision_s', summary['time_to_decision_s'], contact_s, 's'),
        Check('madgwick_rejected', summary['madgwick_rejected'], MAX_MADGWICK_REJECTED),
    ]


def plot_pathway(path: Path, positions: np.ndarray, normals: np.ndarray,
                 surface: Surface) -> None:
    """The probed contacts and normals over the true surface profile (x-z, base_link)."""
    plt, figure, axes = plotting.figure()
    low, high = (positions[:, 0].min() - 0.01, positions[:, 0].max() + 0.01) \
        if len(positions) else (0.08, 0.22)
    xs = np.linspace(low, high, 400)
    axes.plot(1e3 * xs, 1e3 * surface.height(xs), color='0.4', label='true surface')
    scale = 6.0  # mm of arrow per unit normal
    truth = np.array([true_normal(surface, x) for x in positions[:, 0]]) if len(positions) \
        else np.zeros((0, 3))
    tips = [1e3 * positions[:, [0, 2]]]
    for normal_set, colour, name in ((truth, '0.6', 'true normal'),
                                     (normals, 'tab:red', 'probed normal')):
        axes.quiver(1e3 * positions[:, 0], 1e3 * positions[:, 2], scale * normal_set[:, 0],
                    scale * normal_set[:, 2], color=colour, angles='xy', scale_units='xy',
                    scale=1.0, width=0.004, label=name)
        tips.append(1e3 * positions[:, [0, 2]] + scale * normal_set[:, [0, 2]])
    axes.plot(1e3 * positions[:, 0], 1e3 * positions[:, 2], 'o', color='tab:red',
              label='probed contact')
    points = np.vstack(tips + [np.column_stack([1e3 * xs, 1e3 * surface.height(xs)])])
    margin = 2.0  # mm around every arrow tip, so none is clipped
    axes.update_datalim([points.min(axis=0) - margin, points.max(axis=0) + margin])
    axes.autoscale_view()
    axes.set(xlabel='x (mm, base_link)', ylabel='z (mm)', title='Pathway against the surface',
             aspect='equal', adjustable='datalim')  # the limits grown to fill the panel
    plotting.legend_outside(axes)
    plotting.save(plt, figure, path)


def plot_sweeps(path: Path, sweeps: Sequence[tuple[str, Sequence[tuple]]],
                path_length_m: float, commanded_m_s: float) -> None:
    """Sliding speed and contact of every recorded sweep against the position on the path.

    Args:
        path: the PNG to write.
        sweeps: (label, action feedback) per sweep; feedback rows are (wall s, progress
            0-1, in contact, sliding speed m/s).
        path_length_m: the pathway's length (progress x length = position on it).
        commanded_m_s: the commanded sliding speed, drawn as a line.
    """
    plt, figure, (speed, contact) = plotting.figure(2, 1, sharex=True)
    grid = np.linspace(0.0, 1e3 * path_length_m, 200)
    touching = []
    for index, (_, feedback) in enumerate(sweeps):
        data = np.array(feedback, dtype=float).reshape(-1, 4)
        if not len(data):
            continue
        position = 1e3 * path_length_m * data[:, 1]
        speed.plot(position, 1e3 * data[:, 3], color='tab:blue', alpha=0.25, linewidth=0.8,
                   label='one sweep' if index == 0 else None)
        order = np.argsort(position, kind='stable')
        touching.append(np.interp(grid, position[order], data[order, 2], left=0.0,
                                  right=0.0))
    speed.axhline(1e3 * commanded_m_s, color='k', linestyle='--', label='commanded')
    speed.set(ylabel='sliding speed (mm/s)',
              title=f'{len(sweeps)} recorded sweeps along the probed pathway')
    plotting.legend_outside(speed)
    if touching:
        contact.fill_between(grid, 0, 100 * np.mean(touching, axis=0), color='tab:green',
                             alpha=0.4, label='sweeps in contact')
    contact.set(xlabel='position along the pathway (mm)', ylabel='in contact (%)',
                ylim=(0, 105))
    plotting.legend_outside(contact)
    plotting.save(plt, figure, path)


def plot_confusion(path: Path, matrix: np.ndarray, classes: Sequence[str]) -> None:
    """The live decisions' confusion matrix (rows true, columns decided, then none)."""
    plt, figure, axes = plotting.figure(classes=max(matrix.shape))
    axes.imshow(matrix, cmap='Blues')
    for (row, column), count in np.ndenumerate(matrix):
        if count:
            axes.text(column, row, str(count), ha='center', va='center', fontsize=8)
    columns = list(classes) + ['no decision'] * (matrix.shape[1] - len(classes))
    axes.set_xticks(range(len(columns)), columns, rotation=60, ha='right', fontsize=7)
    axes.set_yticks(range(len(classes)), classes, fontsize=7)
    axes.set(xlabel='decided', ylabel='true', title='Live decisions of classifier_node')
    plotting.save(plt, figure, path)


def plot_accuracy_against_time(path: Path, times_s: np.ndarray, accuracy: np.ndarray,
                               chance: float) -> None:
    """Live accuracy against the seconds of contact behind the estimate."""
    plt, figure, axes = plotting.figure()
    axes.plot(times_s, 100 * accuracy, color='tab:purple', label='classifier_node, live')
    axes.axhline(100 * chance, color='0.5', linestyle=':', label='chance')
    axes.set(xlabel='contact time (s)', ylabel='accuracy (%)', ylim=(0, 101),
             title='Accuracy against contact time')
    plotting.legend_outside(axes)
    plotting.save(plt, figure, path)
