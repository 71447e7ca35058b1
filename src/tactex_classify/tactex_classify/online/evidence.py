# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Evidence about the texture over consecutive windows, a decision rule and change detection.

Each window's class probabilities add their logarithms to the evidence (the windows are
taken as independent, as `evaluate.sequence_accuracy` does); the posterior is the
softmax of the sums. A decision is made when the posterior's largest value exceeds the
threshold with at least `min_windows` windows; from then on the estimate stands (its
label, probabilities and contact time) until the evidence is reset.

A texture change is found with Page's CUSUM on the per-window log-likelihood ratio of
each other class against the leading one: S_c = max(0, S_c + log p_c - log p_lead).
When some S_c exceeds `change_nats`, the evidence restarts from the windows of that
class's run (those since S_c last left 0), so the new texture's evidence is kept. A
single window that favours another class by `change_nats` (default 5: e.g. 0.995
against 0.005, 5.3 nats) restarts it on its own: the reset comes within one window of
the change.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
import math

import numpy as np

LOG_FLOOR = 1e-12  # probabilities are clipped here before the logarithm
KEPT_AFTER_DECISION = 256  # windows kept for change detection once a decision stands


def log_probabilities(proba: np.ndarray) -> np.ndarray:
    """Log of probabilities clipped to [LOG_FLOOR, 1] (a zero does not veto a class)."""
    return np.log(np.clip(proba, LOG_FLOOR, 1.0))


def union_seconds(spans_ns: Sequence[tuple[int, int]]) -> float:
    """Seconds covered by [start, end) spans, overlaps counted once (an inverted span: none)."""
    total, reach = 0, None
    for start, end in sorted((start, max(start, end)) for start, end in spans_ns):
        if reach is None or start > reach:
            total += end - start
            reach = end
        elif end > reach:
            total += end - reach
            reach = end
    return total * 1e-9


@dataclass(frozen=True)
class EvidenceSettings:
    """The decision and change rules.

    Attributes:
        threshold: decide when the largest posterior probability exceeds this (0..1;
            1 never decides, so the evidence grows over the whole contact).
        min_windows: windows needed before a decision.
        change_nats: CUSUM threshold for a texture change (nats of log-likelihood ratio).
    """

    threshold: float = 0.99
    min_windows: int = 1
    change_nats: float = 5.0

    def __post_init__(self) -> None:
        """Check the ranges.

        Raises:
            ValueError: naming the setting and its range.
        """
        if not 0.0 <= self.threshold <= 1.0:
            raise ValueError(f'threshold must be in [0, 1], got {self.threshold!r}')
        if not isinstance(self.min_windows, int) or self.min_windows < 1:
            raise ValueError(f'min_windows must be an integer >= 1, got {self.min_windows!r}')
        if not (math.isfinite(self.change_nats) and self.change_nats > 0):
            raise ValueError(f'change_nats must be finite and > 0, got {self.change_nats!r}')


@dataclass(frozen=True)
class Estimate:
    """The belief after one window.

    Attributes:
        class_id: the leading (or decided) class.
        probabilities: posterior over the classes.
        decided: the decision rule was met (the estimate stands until a reset).
        contact_seconds: signal behind the estimate (windows' union).
        spans_ns: (start, end) stamps of the first and last sample of each window used.
        stamp_ns: end of the newest window seen.
        restarted: why the evidence restarted at this window ('' if it did not).
    """

    class_id: int
    probabilities: np.ndarray
    decided: bool
    contact_seconds: float
    spans_ns: tuple[tuple[int, int], ...]
    stamp_ns: int
    restarted: str = ''


class Evidence:
    """Summed log-probabilities of consecutive windows, with decision and reset rules.

    Args:
        classes: number of classes.
        period_ns: one sample period (a window covers its first to its last sample plus
            one period, so contact time counts every sample once).
        settings: the decision and change rules.
    """

    def __init__(self, classes: int, period_ns: int,
                 settings: EvidenceSettings = EvidenceSettings()) -> None:
        self.classes = classes
        self.period_ns = int(period_ns)
        self.settings = settings
        self.reset()

    def reset(self) -> None:
        """Forget every window (contact lost, sweep ended)."""
        self._logs: list[np.ndarray] = []
        self._spans: list[tuple[int, int]] = []
        self._decided: Estimate | None = None
        self._cusum = np.zeros(self.classes)
        self._run_start = np.zeros(self.classes, dtype=int)

    @property
    def windows(self) -> int:
        """Windows in the evidence now."""
        return len(self._logs)

    @property
    def decided(self) -> bool:
        """A decision stands."""
        return self._decided is not None

    def add(self, proba: np.ndarray, start_ns: int, end_ns: int) -> Estimate:
        """Add one window's probabilities (classes,) and return the estimate after it.

        Raises:
            ValueError: `proba` is not `classes` finite, non-negative values (nothing is
                added: the evidence stays as it was).
        """
        proba = np.asarray(proba, dtype=np.float64)
        if proba.shape != (self.classes,) or not np.all(np.isfinite(proba) & (proba >= 0)):
            raise ValueError(f'a window needs {self.classes} finite, non-negative '
                             f'probabilities, got {proba!r}')
        log = log_probabilities(proba)
        restarted = ''
        if self._logs:
            lead = self._decided.class_id if self._decided else int(np.argmax(
                np.sum(self._logs, axis=0)))
            starting = self._cusum == 0.0
            self._cusum = np.maximum(0.0, self._cusum + log - log[lead])
            self._cusum[lead] = 0.0
            self._run_start[starting & (self._cusum > 0)] = len(self._logs)
            rival = int(np.argmax(self._cusum))
            if self._cusum[rival] > self.settings.change_nats:
                kept = int(self._run_start[rival])
                logs, spans = self._logs[kept:], self._spans[kept:]
                self.reset()
                self._logs, self._spans = logs, spans
                restarted = 'texture change'
        self._logs.append(log)
        self._spans.append((int(start_ns), int(end_ns)))
        if self._decided is not None:
            surplus = len(self._logs) - KEPT_AFTER_DECISION
            if surplus > 0:
                del self._logs[:surplus], self._spans[:surplus]
                self._run_start = np.maximum(0, self._run_start - surplus)
            return Estimate(self._decided.class_id, self._decided.probabilities, True,
                            self._decided.contact_seconds, self._decided.spans_ns,
                            int(end_ns), restarted)
        total = np.sum(self._logs, axis=0)
        posterior = np.exp(total - total.max())
        posterior /= posterior.sum()
        leader = int(np.argmax(posterior))
        # Python types, not numpy's: a ROS message's bool field refuses numpy.bool_ (the
        # generated C code asserts PyBool_Check, and a colcon build keeps the assertion).
        decided = bool(posterior[leader] > self.settings.threshold
                       and len(self._logs) >= self.settings.min_windows)
        estimate = Estimate(leader, posterior, decided, union_seconds(
            [(s, e + self.period_ns) for s, e in self._spans]), tuple(self._spans),
            int(end_ns), restarted)
        if decided:
            self._decided = estimate
        return estimate
