# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Identification replayed on held-out recordings: every policy on the same folds and draws.

The recordings are split into `folds` folds grouped by recording and balanced per
(texture, movement), and with `repeats` above one dealt again from another shuffle
(repeated cross-validation: which recordings share a fold moves the figures by several
points on twenty recordings per cell, and every partition is replayed). For each fold,
every movement's model, temperature, out-of-fold evidence and the tempering exponent
come from the other folds only (nested: the evidence table's vectors are themselves out
of fold within them); the held-out recordings then give, per movement, the calibrated
sweep vectors an arm would have produced. An episode identifies one texture of the
fold: each step takes the chosen movement's next held-out sweep of that texture, never
the same sweep twice (a movement whose sweeps are used up is no longer available). Every
policy sees the same sweeps in the same order for a (repeat, fold, texture, seed), so
policies differ only by their choices (`comparison` pairs them).

`best_plans` bounds what choosing can buy: the best plan of at most k movements fixed in
advance (how many sweeps of each), picked in hindsight on those same held-out sweeps.
Fixed and round-robin run such plans, so they do not pass it while they run to k; a
policy that stops on its threshold picks how many sweeps from them, random draws its plan
per episode (on few episodes it can pass by luck), and active, which looks at each sweep,
can pass it by choosing. `tradeoff` reads every policy's accuracy and contact seconds at
lower thresholds off the same episodes.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
import itertools
import math
import time

import numpy as np

from tactex_classify.data.dataset import Dataset
from tactex_classify.evaluation.cross_validation import confusion
from tactex_classify.identification.calibration import reliability
from tactex_classify.identification.comparison import (
    against_fixed,
    contact_grid,
    GOAL_TOLERANCE,
    paired_difference,
)
from tactex_classify.identification.evidence_table import EvidenceTable
from tactex_classify.identification.movement_evidence import (
    cell_counts,
    check_cells,
    checked_movements,
    DEFAULT_MODEL,
    fit_movement,
    movement_evidence,
    MovementDataError,
    subset,
    trial_labels,
)
from tactex_classify.identification.selection import Budget, COMPARED, Identification
from tactex_classify.identification.tempering import DISCOUNTS, fit_tempering
from tactex_classify.identification.tradeoff import (
    at_equal_accuracy,
    fixed_goal,
    fixed_goal_interval,
    saving_interval,
    texture_sums,
    THRESHOLDS,
    tradeoff,
)
from tactex_classify.models.registry import BASELINES
from tactex_classify.training.deep_classifier import TrainingConfig
from tactex_classify.training.estimators import build_estimator
from tactex_description.movements import MovementSet

PLAN_MOVEMENTS = 6  # the longest plan best_plans scores by default
MAX_PLANS = 20_000  # plans of one length best_plans scores at most


@dataclass(frozen=True)
class ReplaySettings:
    """What to replay: policies, stopping rules, folds, seeds and the per-movement model."""

    policies: tuple[str, ...] = COMPARED
    budget: Budget = Budget()
    folds: int = 3
    inner_folds: int = 3
    seeds: int = 10
    training: TrainingConfig = field(default_factory=lambda: TrainingConfig(model=DEFAULT_MODEL))
    seed: int = 0  # the folds and episodes; the models' own seed is training.seed
    repeat_discount: bool = False  # True: fit the discount of a movement's repeats
    repeats: int = 1  # partitions into folds; partition r from seed + r (seeds s, s + 1 share)

    @property
    def model(self) -> str:
        """The per-movement model's name."""
        return self.training.model


@dataclass
class Episode:
    """One identification of one held-out texture by one policy."""

    policy: str
    fold: int
    seed: int
    texture: int
    repeat: int = 0  # the partition into folds
    movements: list[int] = field(default_factory=list)
    leaders: list[int] = field(default_factory=list)  # the leading texture after each step
    top_posterior: list[float] = field(default_factory=list)  # the leader's, after each step
    contact_s: list[float] = field(default_factory=list)  # cumulative, after each step
    arm_s: float = 0.0
    wall_s: float = 0.0
    stop_reason: str = ''
    decided: bool = False

    @property
    def right(self) -> bool:
        """The leader at the end is the true texture."""
        return bool(self.leaders) and self.leaders[-1] == self.texture


def assign_folds(trials: dict[int, tuple[str, str]], folds: int, seed: int) -> dict[int, int]:
    """Each recording's fold: per (texture, movement) cell, a seeded shuffle dealt round-robin.

    Raises:
        MovementDataError: a cell with fewer recordings than folds.
    """
    cells: dict[tuple[str, str], list[int]] = {}
    for trial, cell in sorted(trials.items()):
        cells.setdefault(cell, []).append(trial)
    rng = np.random.default_rng(seed)
    fold_of = {}
    for cell, members in sorted(cells.items()):
        if len(members) < folds:
            raise MovementDataError(f'{cell[0]} under movement {cell[1]} has '
                                    f'{len(members)} recording(s); {folds} folds need at least '
                                    f'{folds}: record more sweeps or lower --folds')
        for index, trial in enumerate(rng.permutation(members)):
            fold_of[int(trial)] = index % folds
    return fold_of


def recordings_needed(folds: int, inner_folds: int) -> int:
    """Recordings a (texture, movement) pair needs for these folds.

    One per fold, and `inner_folds` left in the training part of every fold (the folds
    are dealt round-robin, so the largest fold holds ceil(n / folds) of n).
    """
    count = folds
    while count - math.ceil(count / folds) < inner_folds:
        count += 1
    return count


def _fold_fix(fewest: int, folds: int) -> str:
    """What folds `fewest` recordings per pair allow, as the options to give."""
    for outer in range(folds, 1, -1):
        inner = fewest - math.ceil(fewest / outer)
        if fewest >= outer and inner >= 2:
            return (f'give --folds {outer} --inner-folds {min(inner, 10)}, or record more '
                    'sweeps')
    return f'record at least {recordings_needed(2, 2)} sweeps of each (with --folds 2 ' \
           '--inner-folds 2)'


def replay(dataset: Dataset, movements: MovementSet, settings: ReplaySettings = ReplaySettings(),
           progress: Callable[[str], None] = print) -> dict:
    """Replay every policy on every fold; the episodes and what each movement's model did.

    Raises:
        MovementDataError: recordings without a movement, a movement of the dataset that
            the file does not list (or the reverse), or too few recordings for the folds.
    """
    movement_of = checked_movements(dataset, movements)
    label_of = trial_labels(dataset)
    counts = cell_counts(dataset.classes, label_of, movement_of, movements)
    needed = recordings_needed(settings.folds, settings.inner_folds)
    check_cells(counts, needed, f'--folds {settings.folds} with --inner-folds '
                f'{settings.inner_folds}', _fold_fix(min(counts.values()), settings.folds))
    names = list(movements.names)
    arm_s = _arm_seconds(dataset, movement_of, names)
    episodes: list[Episode] = []
    held_out = {name: {'labels': [], 'vectors': [], 'unconverged': []} for name in names}
    tempering, plan_terms = [], []
    cell_of = {t: (dataset.classes[label_of[t]], m) for t, m in movement_of.items()}
    own_of = {name: [t for t, m in movement_of.items() if m == name] for name in names}
    for repeat in range(settings.repeats):
        partition_seed = settings.seed + repeat
        partition = f'repeat {repeat + 1}, ' if settings.repeats > 1 else ''
        fold_of = assign_folds(cell_of, settings.folds, partition_seed)
        for fold in range(settings.folds):
            where = f'{partition}fold {fold + 1}/{settings.folds}'  # in the progress lines
            started = time.monotonic()
            fitted, test, predict_s = [], [], []
            for index, name in enumerate(names, start=1):
                own = own_of[name]
                fitting = time.monotonic()
                fit = fit_movement(name, subset(dataset, [t for t in own if fold_of[t] != fold]),
                                   lambda: build_estimator(settings.training),
                                   folds=settings.inner_folds, seed=partition_seed)
                progress(f'{where}: {name} fitted ({index}/{len(names)}, '
                         f'{time.monotonic() - fitting:.0f} s)'
                         + ('; not converged: ' + ', '.join(f'{at} ({why})' for at, why in
                                                            fit.unconverged)
                            if fit.unconverged else ''))
                began = time.perf_counter()
                trials, labels, vectors = fit.predict_sweeps(
                    subset(dataset, [t for t in own if fold_of[t] == fold]))
                predict_s.append((time.perf_counter() - began) / max(len(trials), 1))
                fitted.append(fit)
                test.append((labels, vectors))
                held_out[name]['labels'] += labels.tolist()
                held_out[name]['vectors'] += vectors.tolist()
                held_out[name]['unconverged'] += [f'{partition}fold {fold + 1}, {at}: {why}'
                                                  for at, why in fit.unconverged]
            evidence = [movement_evidence(fit, movements.by_name(fit.name).contact_s)
                        for fit in fitted]
            fitted_update = fit_tempering(
                dataset.classes, evidence, seed=partition_seed,
                discounts=DISCOUNTS if settings.repeat_discount else (0.0,))
            tempering.append(fitted_update)
            table = EvidenceTable(dataset.classes, evidence, *fitted_update)
            fold_episodes, fold_plans = _fold_episodes(table, test, settings, repeat, fold,
                                                       arm_s, predict_s)
            episodes += fold_episodes
            plan_terms += fold_plans
            progress(f'{where}: {len(names)} movements fitted, tempering '
                     f'{fitted_update.exponent:.2f}, repeat discount '
                     f'{fitted_update.repeat_discount:g}, '
                     f'{len(fold_episodes)} episodes '
                     f'({time.monotonic() - started:.0f} s)')
    return {'episodes': episodes, 'held_out': held_out, 'tempering': tempering,
            'plan_terms': plan_terms, 'arm_s': arm_s, 'movements': names,
            'classes': list(dataset.classes),
            'contact_s': [movements.by_name(name).contact_s for name in names]}


def _fold_episodes(table: EvidenceTable, test: list[tuple[np.ndarray, np.ndarray]],
                   settings: ReplaySettings, repeat: int, fold: int, arm_s: list[float],
                   predict_s: list[float]) -> tuple[list[Episode], list[tuple]]:
    """Every policy's episodes on one fold's held-out sweeps, and the plans' sums on them.

    `test`: per movement, the fold's held-out (labels, sweep vectors). For every texture
    and episode seed, the pools are one seeded shuffle of each movement's held-out sweeps
    of the texture, the same for every policy.
    """
    partition_seed = settings.seed + repeat
    episodes, plan_terms = [], []
    for texture in range(len(table.classes)):
        for episode_seed in range(settings.seeds):
            order = np.random.default_rng([partition_seed, fold, texture, episode_seed])
            pools = [list(vectors[order.permutation(np.flatnonzero(labels == texture))])
                     for labels, vectors in test]
            plan_terms.append((repeat, fold, texture, repeat_sums(table, pools)))
            episodes += [_episode(table, policy, settings.budget,
                                  Episode(policy, fold, episode_seed, texture, repeat),
                                  [list(pool) for pool in pools], arm_s, predict_s,
                                  partition_seed)
                         for policy in settings.policies]
    return episodes, plan_terms


def _episode(table: EvidenceTable, policy: str, budget: Budget, episode: Episode,
             pools: list[list[np.ndarray]], arm_s: list[float], predict_s: list[float],
             base_seed: int) -> Episode:
    """`episode`'s texture identified by `policy` from its fold's held-out sweeps.

    The random policy draws from its own stream per (run seed + repeat, fold, texture,
    seed), so its episodes do not all repeat one sequence of movements.
    """
    stream = int(np.random.SeedSequence(
        [base_seed, episode.fold, episode.texture, episode.seed]).generate_state(1)[0])
    identification = Identification(table, policy, budget, seed=stream)
    began = time.perf_counter()
    while (chosen := identification.next_movement(
            np.array([bool(pool) for pool in pools]))) is not None:
        identification.observe(chosen, pools[chosen].pop())
        episode.movements.append(chosen)
        episode.leaders.append(identification.leader)
        episode.top_posterior.append(float(identification.posterior[identification.leader]))
        episode.contact_s.append(identification.contact_seconds)
        episode.arm_s += arm_s[chosen]
        episode.wall_s += arm_s[chosen] + predict_s[chosen]
    episode.wall_s += time.perf_counter() - began
    episode.stop_reason = identification.stop_reason(np.array([bool(p) for p in pools]))
    episode.decided = episode.stop_reason == 'decided'
    return episode


def repeat_sums(table: EvidenceTable, pools: list[list[np.ndarray]]) -> list[np.ndarray]:
    """Per movement, (sweeps + 1, classes): the update's sum over its first n pooled sweeps.

    In the order an episode takes them (from the end of the pool), each weighted as its
    repeat (`EvidenceTable.log_likelihood`).
    """
    sums = []
    for movement, pool in enumerate(pools):
        terms = [table.log_likelihood(movement, vector, repeats=n)
                 for n, vector in enumerate(reversed(pool))]
        sums.append(np.cumsum([np.zeros(len(table.classes)), *terms], axis=0))
    return sums


def best_plans(result: dict, most: int = PLAN_MOVEMENTS) -> list[dict]:
    """Per k in 1..most, the plan of at most k sweeps (per movement how many) right most often.

    A plan's answer in an episode is the leader after its sweeps, taken from the same
    held-out pools the policies drew from; its `accuracy` is the mean over every (repeat,
    fold, texture, seed). A movement is repeated at most as often as every pool allows. At most
    k, as a policy's accuracy after k keeps the leader of an episode that stopped
    earlier. That plan is picked on the held-out sweeps it is scored on: optimistic, not
    a policy, and the more plans there are the more it flatters; it bounds only plans
    fixed in advance for every episode (random draws one per episode, and a policy that
    stops on its threshold chooses how many sweeps from them, so either may pass it).
    `chosen_elsewhere` takes the selection's luck out: each fold's episodes scored with
    the plan best on the other folds' of the same partition (None with one fold). The
    list ends before a k with more than MAX_PLANS plans of k sweeps, and is empty when no
    episode was replayed.
    """
    plan_terms: list[tuple[int, int, int, list[np.ndarray]]] = result['plan_terms']
    if not plan_terms:
        return []
    names, seconds = result['movements'], np.asarray(result['contact_s'], dtype=float)
    deepest = np.array([min(len(own[m]) for *_, own in plan_terms) - 1
                        for m in range(len(names))])
    sums = np.zeros((len(plan_terms), len(names), deepest.max() + 1,
                     len(result['classes'])))
    for episode, (*_, own) in enumerate(plan_terms):
        for movement, depth in enumerate(deepest):
            sums[episode, movement, :depth + 1] = own[movement][:depth + 1]
    repeat = np.array([repeat for repeat, *_ in plan_terms])
    fold = np.array([fold for _, fold, *_ in plan_terms])
    held_out_sets = sorted(set(zip(repeat.tolist(), fold.tolist(), strict=True)))
    truth = np.array([texture for _, _, texture, _ in plan_terms])
    every = np.arange(len(names))
    best, plans, rows = [], [], []
    for k in range(1, min(most, int(deepest.sum())) + 1):
        if math.comb(len(names) + k - 1, k) > MAX_PLANS:
            break
        longest = [counts for chosen in itertools.combinations_with_replacement(every, k)
                   if np.all((counts := np.bincount(chosen, minlength=len(names))) <= deepest)]
        plans += longest
        rows += [sums[:, every, counts].sum(axis=1).argmax(axis=1) == truth
                 for counts in longest]
        right = np.array(rows)  # (plans of 1..k sweeps, episodes)
        shares = right.mean(axis=1)
        top = plans[int(np.argmax(shares))]
        elsewhere = [right[np.argmax(right[:, (repeat == r) & (fold != f)].mean(axis=1)),
                           (repeat == r) & (fold == f)]
                     for r, f in held_out_sets] if len(np.unique(fold)) > 1 else None
        best.append({'movements': k, 'accuracy': float(shares.max()),
                     'chosen_elsewhere': None if elsewhere is None
                     else float(np.concatenate(elsewhere).mean()),
                     'contact_s': float(top @ seconds),
                     'plan': {names[m]: int(c) for m, c in enumerate(top) if c}})
    return best


def _arm_seconds(dataset: Dataset, movement_of: dict[int, str], names: list[str]) -> list[float]:
    """Median seconds the arm spends on one sweep of each movement (its whole recording)."""
    rows = {int(row['trial']): row for row in dataset.info.get('recordings', [])}
    seconds = []
    for name in names:
        spans = [rows[t]['samples'] / rows[t]['rate_hz'] for t, m in movement_of.items()
                 if m == name and t in rows and rows[t].get('rate_hz')]
        seconds.append(float(np.median(spans)) if spans else float('nan'))
    return seconds


def training_settings(config: TrainingConfig) -> dict:
    """How a deep per-movement model trained (profile, epochs, scaling, patience, start).

    A baseline: {}.
    """
    if config.model in BASELINES:
        return {}
    return {'profile': config.profile, 'epochs': config.epochs, 'scaling': config.scaling,
            'early_stopping': config.early_stopping, 'pretrained': config.pretrained}


def summary(result: dict, settings: ReplaySettings) -> dict:
    """identification.json: per policy accuracy, contact seconds, movements, by step."""
    episodes: list[Episode] = result['episodes']
    longest = max((len(e.movements) for e in episodes), default=0)
    policies = {}
    for policy in settings.policies:
        own = [e for e in episodes if e.policy == policy]
        contact = np.array([e.contact_s[-1] if e.contact_s else 0.0 for e in own])
        moves = np.array([len(e.movements) for e in own])
        after = [float(np.mean([e.leaders[min(k, len(e.leaders)) - 1] == e.texture
                                if e.leaders else False for e in own]))
                 for k in range(1, longest + 1)]
        stops, first = {}, [0] * len(result['movements'])
        for e in own:
            stops[e.stop_reason] = stops.get(e.stop_reason, 0) + 1
            for movement in e.movements[:3]:
                first[movement] += 1
        policies[policy] = {
            'accuracy': float(np.mean([e.right for e in own])),
            'decided': float(np.mean([e.decided for e in own])),
            'median_contact_s': float(np.median(contact)),
            'p90_contact_s': float(np.percentile(contact, 90)),
            'median_movements': float(np.median(moves)),
            'median_arm_s': float(np.median([e.arm_s for e in own])),
            'median_wall_s': float(np.median([e.wall_s for e in own])),
            'accuracy_after_k': after, 'stops': stops,
            'first_three_movements': dict(zip(result['movements'], first, strict=True))}
    per_movement = {}
    for name, held in result['held_out'].items():
        labels, vectors = np.array(held['labels']), np.array(held['vectors'])
        calibration = reliability(vectors, labels)
        per_movement[name] = {
            'sweep_accuracy': float(np.mean(vectors.argmax(axis=1) == labels)),
            'calibration_error': calibration.error,
            'sweeps': int(len(labels)) // settings.repeats,  # each held out once a repeat
            'unconverged': held['unconverged'],
            'confusion': confusion(labels, vectors.argmax(axis=1),
                                   len(result['classes'])).tolist()}
    return {'policies': policies, 'episodes': len(episodes) // max(len(settings.policies), 1),
            'movements': per_movement,
            'tempering': [update.exponent for update in result['tempering']],
            'repeat_discount': [update.repeat_discount for update in result['tempering']],
            'classes': result['classes'], 'movement_names': result['movements'],
            'contact_s': result['contact_s'], 'arm_s': result['arm_s'],
            'best_plans': best_plans(result),
            'active_against': active_against(result, settings),
            'tradeoff': policy_tradeoffs(result['episodes'], len(result['classes']), settings),
            'against_fixed': against_fixed(result['episodes'], seed=settings.seed),
            'settings': {'folds': settings.folds, 'inner_folds': settings.inner_folds,
                         'seeds': settings.seeds, 'model': settings.model,
                         **training_settings(settings.training),
                         'threshold': settings.budget.threshold,
                         'budget_movements': settings.budget.movements,
                         'budget_seconds': settings.budget.seconds,
                         'repeat_discount': settings.repeat_discount,
                         'repeats': settings.repeats}}


def policy_tradeoffs(episodes: list[Episode], classes: int, settings: ReplaySettings) -> dict:
    """Every policy's accuracy and contact seconds at the thresholds up to the replay's.

    {'curves': {policy: rows}, 'at_equal_accuracy': {other: rows}, 'fixed_goal': the goal
    against fixed read on active's trade-off, 'fixed_goal_interval': the same as a share
    of fixed's mean contact with an interval over the textures, 'textures': {policy:
    per-texture sums}, 'active_saving': {other: the seconds active saves at equal accuracy,
    with intervals}} (`tradeoff`).
    """
    threshold = settings.budget.threshold  # those the uniform belief passes cannot be run
    thresholds = sorted({t for t in THRESHOLDS if 1.0 / classes < t < threshold} | {threshold})
    curves = {policy: tradeoff(episodes, policy, thresholds) for policy in settings.policies}
    sums = {policy: texture_sums(episodes, policy, thresholds, classes)
            for policy in settings.policies}
    return {'curves': curves, 'at_equal_accuracy': at_equal_accuracy(curves),
            'fixed_goal': fixed_goal(curves, GOAL_TOLERANCE),
            'fixed_goal_interval': fixed_goal_interval(sums['active'], sums['fixed'],
                                                       GOAL_TOLERANCE, seed=settings.seed)
            if {'active', 'fixed'} <= set(sums) else {}, 'textures': sums,
            'active_saving': {other: saving_interval(sums['active'], sums[other],
                                                     seed=settings.seed)
                              for other in settings.policies
                              if other != 'active' and 'active' in sums}}


def active_against(result: dict, settings: ReplaySettings) -> dict:
    """Per other policy replayed, active minus it by contact time (`paired_difference`).

    The times step by the shortest movement's contact; {} when active was not replayed.
    """
    if 'active' not in settings.policies:
        return {}
    grid = contact_grid(result['episodes'], min(result['contact_s'], default=0.0))
    return {other: paired_difference(result['episodes'], 'active', other, grid,
                                     seed=settings.seed)
            for other in settings.policies if other != 'active'}

