# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Which movement next, and when to stop: the policies and one identification's state.

Policies (`POLICIES`):
- `active`: the movement with the largest expected information gain per contact second
  under the current belief (`EvidenceTable.information_gain`), as Fishel and Loeb's
  Bayesian exploration chose each next movement (Fishel & Loeb 2012, Front. Neurorobot.
  6:4);
- `fixed`: the one movement with the largest gain per second from the starting belief,
  repeated;
- `random`: a movement drawn uniformly from the generator seeded by `seed`;
- `round-robin`: the movements in their file's order, again and again (one that cannot
  run is passed over, and the turn goes on after the last one run);
- `active-realized`: `active`, each movement's gain scaled by how much of what the table
  expected its sweeps have delivered in this identification (`realized_trust`): a sweep's
  realized KL(belief after || belief before) against the KL the table expects of that
  movement's sweep under the belief it met (`EvidenceTable.expected_divergence`), so
  while the table describes the sweeps the scale stays near one; a movement whose sweeps
  barely move the belief (its model out of its depth on these sweeps, live) is asked
  less, where `active` would repeat it for as long as the belief stays where it was;
- `active-rounds`: `active` among the movements run fewest times so far: every movement
  once, in the order of their gain under the belief as it stands, before any a second
  time, and so on. Sweeps of one movement share its model's mistakes (one model judges
  them all), while each movement has a model of its own, so a repeat adds less than the
  table's gain (drawn as if independent) says and a belief built on one or two movements
  is surer than its accuracy (stopped at 0.9, active is right less often than random on
  seven of the eight fresh seeds' default reports, bench/results/identification_seeds/);
  rounds keep the evidence spread over independent models, as round-robin does, and keep
  active's order within each round;
- `active-sampled`: `active` on one Bayesian bootstrap of the table's held-out sweeps,
  drawn afresh for each choice (`EvidenceTable.bootstrap_weights`), as Thompson sampling
  chooses (Russo et al. 2018, Found. Trends Mach. Learn. 11:1): a movement is chosen about
  as often as the table's few sweeps leave it the most informative. With ten or so
  sweeps per texture and movement, which movement best tells two given textures apart is
  itself uncertain; `active` takes the movement whose estimate happens to be highest and
  repeats it, the sample spreads the choice over those the table cannot tell apart. The
  bootstrap weighs a cell's sweeps independently (those one model judged are not drawn
  together): it samples what the table knows of each cell, not how repeats depend.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from tactex_classify.identification.evidence_table import EvidenceTable
from tactex_classify.identification.posterior import divergence, normalised, uniform, updated
from tactex_common.numbers import is_finite_number

POLICIES = ('active', 'random', 'fixed', 'round-robin', 'active-realized', 'active-rounds',
            'active-sampled')
# The policies that choose by the table's gain.
GAIN_POLICIES = ('active', 'active-realized', 'active-rounds', 'active-sampled')
COMPARED = POLICIES[:4]  # the comparison: what a report replays by default
# What a live goal chooses by unless told (Identify.action's literal, `tactex identify`,
# the demo): active-rounds, as its declared test in bench_identification_seeds.py passed.
LIVE_DEFAULT = 'active-rounds'
DECIDED, MOVEMENT_BUDGET, TIME_BUDGET = 'decided', 'movement budget', 'time budget'
NONE_LEFT = 'no movement left'
MIN_EXPECTED_NATS = 1e-12  # below it a movement's trust stays one (no ratio of rounding)


def check_threshold(threshold: float, classes: int) -> None:
    """Refuse a threshold the uniform starting belief over `classes` textures reaches.

    Below 1, a threshold at or below 1/classes (the uniform belief) would decide on the
    first movement whatever it measured. 1 (never decide) is kept, and so is any threshold
    for one texture (every belief is right).

    Raises:
        ValueError: naming the threshold and the least sensible value.
    """
    if classes > 1 and threshold < 1.0 and threshold <= 1.0 / classes:
        raise ValueError(f'threshold {threshold:g} is at or below 1/{classes} = '
                         f'{1.0 / classes:.3g}, the starting belief over {classes} textures: '
                         f'give more than {1.0 / classes:.3g} (e.g. 0.99)')


@dataclass(frozen=True)
class Budget:
    """When an identification stops.

    Attributes:
        threshold: stop when the leading posterior exceeds this (0..1; 1 never decides).
        movements: at most this many movements (None: no limit).
        seconds: at most this many contact seconds (None: no limit).
    """

    threshold: float = 0.99
    movements: int | None = None
    seconds: float | None = None

    def __post_init__(self) -> None:
        """Check the ranges.

        Raises:
            ValueError: naming the setting and its range.
        """
        if not (isinstance(self.threshold, (int, float)) and 0.0 <= self.threshold <= 1.0):
            raise ValueError(f'threshold must be in [0, 1], got {self.threshold!r}')
        if self.movements is not None and not (
                isinstance(self.movements, int) and self.movements >= 1):
            raise ValueError(f'the movement budget must be an integer >= 1, got '
                             f'{self.movements!r}')
        if self.seconds is not None and not (
                is_finite_number(self.seconds) and self.seconds > 0):
            raise ValueError(f'the time budget must be finite and > 0 s, got {self.seconds!r}')


class Identification:
    """One identification: the belief, the movements run, the next choice and the stop.

    Args:
        table: the movements' out-of-fold evidence.
        policy: one of POLICIES.
        budget: threshold and budgets.
        seed: the draws of random and active-sampled (the others ignore it).
        log_prior: the starting belief's log (default: uniform over the textures).

    Raises:
        ValueError: an unknown policy, a prior that is not a finite log belief, or a
            threshold the uniform belief reaches (`check_threshold`).
    """

    def __init__(self, table: EvidenceTable, policy: str, budget: Budget = Budget(),
                 seed: int = 0, log_prior: np.ndarray | None = None) -> None:
        if policy not in POLICIES:
            raise ValueError(f'unknown policy {policy!r}; known: {", ".join(POLICIES)}')
        classes = len(table.classes)
        check_threshold(budget.threshold, classes)
        prior = uniform(classes) if log_prior is None else np.asarray(log_prior, dtype=float)
        if prior.shape != (classes,) or not np.all(np.isfinite(prior)):
            raise ValueError(f'the prior must be {classes} finite log probabilities')
        self.table, self.policy, self.budget = table, policy, budget
        self.log_posterior = normalised(prior)
        self.movements: list[int] = []
        self.contact_seconds = 0.0
        self._rng = np.random.default_rng(seed)
        self._gain_at_prior = table.information_gain(self.log_posterior) / table.seconds
        self._fixed = int(np.argmax(self._gain_at_prior))
        # active-realized: per movement, the KL its sweeps were expected to and did move.
        self._expected_at_prior = np.array([
            table.expected_divergence(self.log_posterior, index)
            for index in range(len(table.names))]) if policy == 'active-realized' else None
        self.expected_nats = np.zeros(len(table.names))
        self.realized_nats = np.zeros(len(table.names))

    @property
    def posterior(self) -> np.ndarray:
        """The belief over the textures (sums to one)."""
        return np.exp(self.log_posterior)

    @property
    def repeats(self) -> np.ndarray:
        """Per movement, how many of its sweeps were taken."""
        return np.bincount(np.asarray(self.movements, dtype=int), minlength=len(self.table.names))

    @property
    def leader(self) -> int:
        """The most probable texture now."""
        return int(np.argmax(self.log_posterior))

    def stop_reason(self, available: np.ndarray | None = None) -> str:
        """Why the loop stops now (DECIDED, MOVEMENT_BUDGET, TIME_BUDGET, NONE_LEFT), or ''.

        Args:
            available: which movements can still be run (default: all); NONE_LEFT when
                the policy's candidates are all unavailable.
        """
        if self.movements and self.posterior[self.leader] > self.budget.threshold:
            return DECIDED
        if self.budget.movements is not None and len(self.movements) >= self.budget.movements:
            return MOVEMENT_BUDGET
        if not np.any(self._candidates()):
            return TIME_BUDGET
        if available is not None and not np.any(self._candidates() & available):
            return NONE_LEFT
        return ''

    def _candidates(self) -> np.ndarray:
        """Which movements the policy may choose: those that fit the contact seconds left."""
        if self.budget.seconds is None:
            fits = np.ones(len(self.table.names), dtype=bool)
        else:  # a movement that uses the budget up to rounding still fits
            fits = self.contact_seconds + self.table.seconds <= self.budget.seconds * (1 + 1e-9)
        if self.policy == 'fixed':
            fits &= np.arange(len(fits)) == self._fixed
        return fits

    def next_movement(self, available: np.ndarray | None = None) -> int | None:
        """The movement to run next (its index in the table), or None once stopped.

        Args:
            available: which movements can still be run (default: all), e.g. the held-out
                sweeps an offline replay has left.
        """
        if self.stop_reason(available):
            return None
        fits = self._candidates() & (True if available is None else np.asarray(available))
        candidates = np.flatnonzero(fits)
        if self.policy == 'active-rounds':  # the movements this round has not run yet
            runs = self.repeats[candidates]
            candidates = candidates[runs == runs.min()]
        if self.policy in GAIN_POLICIES:
            if self.policy == 'active-sampled':  # a fresh sample of the table each time
                gain = self.table.information_gain(
                    self.log_posterior, self.repeats,
                    self.table.bootstrap_weights(self._rng)) / self.table.seconds
            elif not self.movements:  # the first from the prior, computed once
                gain = self._gain_at_prior
            else:
                gain = self.table.information_gain(self.log_posterior,
                                                   self.repeats) / self.table.seconds
            if self.policy == 'active-realized':  # a negative gain is not made less so
                gain = np.where(gain > 0.0, gain * self.realized_trust(), gain)
            return int(candidates[np.argmax(gain[candidates])])
        if self.policy == 'random':
            return int(self._rng.choice(candidates))
        after_last = self.movements[-1] + 1 if self.movements else 0  # round-robin's turn
        order = np.roll(np.arange(len(fits)), -after_last)
        return int(next(index for index in order if fits[index]))

    def realized_trust(self) -> np.ndarray:
        """Per movement, (w + realized) / (w + expected) nats of KL over its sweeps so far.

        w, the KL one sweep of the movement was expected to move the starting belief, is
        one sweep's worth of trust in the table before any sweep of it: a movement not run
        yet scores one, one sweep that moved nothing about a half, two about a third. A
        movement the table expects nothing of keeps one. Tracked for `active-realized` only
        (ones for the other policies).
        """
        if self._expected_at_prior is None:
            return np.ones(len(self.table.names))
        prior_nats = self._expected_at_prior
        expected = prior_nats + self.expected_nats
        telling = expected > MIN_EXPECTED_NATS
        return np.where(telling, (prior_nats + self.realized_nats)
                        / np.where(telling, expected, 1.0), 1.0)

    def observe(self, movement: int, probabilities) -> np.ndarray:
        """Take one sweep of `movement` whose model answered `probabilities`; the new belief.

        Raises:
            ValueError: an unknown movement index, or probabilities that are not a finite
                non-negative vector over the textures.
        """
        if not (isinstance(movement, (int, np.integer)) and 0 <= movement < len(self.table.names)):
            raise ValueError(f'movement must be an index below {len(self.table.names)}, got '
                             f'{movement!r}')
        before = self.log_posterior
        repeats = self.repeats
        self.log_posterior = updated(before, self.table.log_likelihood(
            int(movement), probabilities, repeats=int(repeats[movement])))
        if self.policy == 'active-realized':
            self.expected_nats[movement] += self.table.expected_divergence(
                before, int(movement), int(repeats[movement]))
            self.realized_nats[movement] += float(divergence(self.log_posterior, before))
        self.movements.append(int(movement))
        self.contact_seconds += float(self.table.seconds[movement])
        return self.posterior

