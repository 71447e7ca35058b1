# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""How long choosing the next movement takes: 30 textures x 12 movements, the target 5 ms.

Builds seeded out-of-fold evidence (5, 10 and 25 held-out sweeps per texture and
movement) and times `Identification.next_movement()` after a first sweep (the choice
from the prior is computed once, at the start), with a belief as spread as the uniform
one and with one sharpened by three sweeps, for `active` and `active-sampled` (a fresh
bootstrap of the table each time), each with every sweep counting fully and with a
repeat discount (the movements already run weigh their next sweep less). Beside
`active`, two other ways to the same expected information gain, measured in the same run
on the same beliefs: one exponential pass over every held-out sweep's updated belief
(row by row) and one numpy pass per movement and texture (the straightforward way).
With a discount the table makes a movement's discounted products the first time its
number of repeats is asked and keeps them, so a repeated call times what is kept; every
choice of whole identifications on fresh tables (IDENTIFICATIONS of MOVEMENT_BUDGET
movements each, a texture's held-out sweeps as the answers; every choice after the
first, which is made from the prior when an identification starts) times the making too.
Prints the median, p99 and worst of each row, the ratios and the margin of its p99 to
the 5 ms target. Writes
bench/results/identification_choice.json, with the machine's cores and its load (the
5-minute average at the end: other work sharing the cores lengthens every time).
"""

import json
import os
from pathlib import Path
import time

import numpy as np

from tactex_classify.identification.evidence_table import (
    EvidenceTable,
    MovementEvidence,
    updated_entropy,
)
from tactex_classify.identification.posterior import entropy, normalised
from tactex_classify.identification.selection import Budget, Identification

RESULTS = Path(__file__).parent / 'results'
TEXTURES, MOVEMENTS, TARGET_MS, REPEATS = 30, 12, 5.0, 300
SETTINGS = {'default': 0.0, 'discount': 0.5}  # the repeat discount c of each
IDENTIFICATIONS, MOVEMENT_BUDGET = 5, 12


def evidence(sweeps: int, rng: np.random.Generator) -> list[MovementEvidence]:
    """Seeded held-out probability vectors, each movement telling the textures apart its way."""
    labels = np.repeat(np.arange(TEXTURES), sweeps)
    movements = []
    for index in range(MOVEMENTS):
        logits = rng.normal(size=(len(labels), TEXTURES))
        logits[np.arange(len(labels)), labels] += rng.uniform(0.5, 3.0, size=TEXTURES)[labels]
        probabilities = np.exp(logits - logits.max(axis=1, keepdims=True))
        movements.append(MovementEvidence(f'm{index}', 2.0 + index % 4,
                                          probabilities / probabilities.sum(1, keepdims=True),
                                          labels))
    return movements


def per_movement_choice(table: EvidenceTable, log_posterior: np.ndarray,
                        weights: np.ndarray) -> int:
    """The same choice, one movement at a time; `weights`: each movement's next sweep's."""
    posterior = np.exp(log_posterior)
    gains = []
    for movement in range(len(table.names)):
        expected = 0.0
        for texture in range(TEXTURES):
            terms = weights[movement] * table.held_out_log_likelihoods(movement, texture)
            expected += posterior[texture] * np.mean(entropy(normalised(log_posterior + terms)))
        gains.append((entropy(log_posterior) - expected) / table.seconds[movement])
    return int(np.argmax(gains))


def stacked_sweeps(table: EvidenceTable) -> tuple[np.ndarray, ...]:
    """Every held-out sweep's update terms, with its movement, texture and share of it."""
    terms, movement_of, texture_of, share_of = [], [], [], []
    for movement in range(len(table.names)):
        for texture in range(TEXTURES):
            rows = table.held_out_log_likelihoods(movement, texture)
            terms.append(rows)
            movement_of += [movement] * len(rows)
            texture_of += [texture] * len(rows)
            share_of += [1.0 / len(rows)] * len(rows)
    return np.concatenate(terms), np.array(movement_of), np.array(texture_of), np.array(share_of)


def row_by_row_choice(table: EvidenceTable, sweeps: tuple, log_posterior: np.ndarray,
                      weights: np.ndarray) -> int:
    """The same choice, every held-out sweep's updated belief in one exponential pass."""
    terms, movement_of, texture_of, share_of = sweeps
    drawn = np.exp(log_posterior)[texture_of] * share_of
    after = updated_entropy(log_posterior, terms * weights[movement_of][:, None])
    expected = np.bincount(movement_of, weights=drawn * after, minlength=len(table.names))
    return int(np.argmax((entropy(log_posterior) - expected) / table.seconds))


def timed_ms(choose, repeats: int = REPEATS) -> np.ndarray:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        choose()
        times.append(time.perf_counter() - start)
    return np.array(times) * 1e3


def main() -> None:
    rng = np.random.default_rng(0)
    rows = []
    print(f'{"sweeps":>6}  {"belief":>15}  {"setting":>8}  {"policy":>14}  '
          f'{"p50/p99/worst ms":>24}  {"row by row p50":>14}  {"per movement p50":>16}  '
          f'{"ratios":>13}  {"target":>6}')
    for sweeps in (5, 10, 25):
        movements = evidence(sweeps, rng)
        for setting, discount in SETTINGS.items():
            def table(discount=discount, movements=movements) -> EvidenceTable:
                return EvidenceTable([f't{k}' for k in range(TEXTURES)], movements, 0.8,
                                     discount)
            rows += [{'sweeps_per_cell': sweeps, 'belief': 'identifications',
                      'setting': setting, 'policy': policy,
                      'choice_ms': in_identifications(table, movements, policy)}
                     for policy in ('active', 'active-sampled')]
            print_row(rows[-2])
            print_row(rows[-1])
            table = table()
            stacked = stacked_sweeps(table)
            start = Identification(table, 'active')
            beliefs = {'uniform': (start.log_posterior.copy(), [0])}
            for chosen in (0, 1, 2):  # three sweeps of texture 0
                start.observe(chosen, movements[chosen].probabilities[0])
            beliefs['sharpened'] = (start.log_posterior.copy(), [0, 1, 2])
            for belief, (log_posterior, run) in beliefs.items():
                for policy in ('active', 'active-sampled'):
                    rows.append(timed_row(table, policy, log_posterior, run, stacked,
                                          {'sweeps_per_cell': sweeps, 'belief': belief,
                                           'setting': setting}))
    (RESULTS / 'identification_choice.json').write_text(json.dumps(
        {'textures': TEXTURES, 'movements': MOVEMENTS, 'target_ms': TARGET_MS,
         'repeat_discount': SETTINGS['discount'], 'cores': os.cpu_count(),
         'load_average': os.getloadavg()[1], 'rows': rows}, indent=2) + '\n',
        encoding='utf-8')


def timed_row(table: EvidenceTable, policy: str, log_posterior: np.ndarray, run: list[int],
              stacked: tuple, row: dict) -> dict:
    """One policy's choice timed after the movements `run` (and the competitors for active)."""
    identification = Identification(table, policy, seed=0)
    # As after a first sweep: the choice from the prior itself is computed once, when the
    # identification starts, so timing it would time nothing.
    identification.log_posterior, identification.movements = log_posterior, list(run)
    identification.next_movement()  # makes the discounted products the timed calls keep
    times = {'choice_ms': timed_ms(identification.next_movement)}
    if policy == 'active':
        weights = table.repeat_weights(identification.repeats)
        chosen = identification.next_movement()
        assert chosen == per_movement_choice(table, log_posterior, weights)
        assert chosen == row_by_row_choice(table, stacked, log_posterior, weights)
        times['row_by_row_ms'] = timed_ms(
            lambda: row_by_row_choice(table, stacked, log_posterior, weights))
        times['per_movement_ms'] = timed_ms(
            lambda: per_movement_choice(table, log_posterior, weights), REPEATS // 10)
    row = {**row, 'policy': policy, **{key: percentiles(ms) for key, ms in times.items()}}
    print_row(row)
    return row


def in_identifications(table, movements: list[MovementEvidence], policy: str) -> list[float]:
    """Median, p99 and worst of every choice of IDENTIFICATIONS on fresh tables (`table()`)."""
    times = []
    for episode in range(IDENTIFICATIONS):
        identification = Identification(table(), policy, Budget(threshold=1.0,
                                                                movements=MOVEMENT_BUDGET),
                                        seed=episode)
        texture, answered = episode % TEXTURES, np.zeros(MOVEMENTS, dtype=int)
        while True:
            start = time.perf_counter()
            chosen = identification.next_movement()
            if chosen is None:
                break
            if identification.movements:  # the first, from the prior, was made at the start
                times.append(time.perf_counter() - start)
            sweeps = movements[chosen].probabilities[movements[chosen].labels == texture]
            identification.observe(chosen, sweeps[answered[chosen] % len(sweeps)])
            answered[chosen] += 1
    return percentiles(np.array(times) * 1e3)


def percentiles(ms: np.ndarray) -> list[float]:
    """Median, p99 and worst of some times."""
    return [float(np.median(ms)), float(np.percentile(ms, 99)), float(ms.max())]


def print_row(row: dict) -> None:
    competitors = [row[key][0] for key in ('row_by_row_ms', 'per_movement_ms') if key in row]
    print(f'{row["sweeps_per_cell"]:>6}  {row["belief"]:>15}  {row["setting"]:>8}  '
          f'{row["policy"]:>14}  {row["choice_ms"][0]:>6.2f} / {row["choice_ms"][1]:>6.2f} / '
          f'{row["choice_ms"][2]:>6.2f}' + ''.join(f'  {value:>14.2f}' for value in competitors)
          + ''.join(f'  {value / row["choice_ms"][0]:>5.1f}x' for value in competitors)
          + f'  {TARGET_MS / row["choice_ms"][1]:>5.1f}x')


if __name__ == '__main__':
    main()
