# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""How long choosing the next movement takes: 30 textures x 12 movements, the target 5 ms.

Builds seeded out-of-fold evidence (5, 10 and 25 held-out sweeps per texture and
movement) and times `Identification.next_movement()` of the `active` policy after a
first sweep (the choice from the prior is computed once, at the start), with a belief as
spread as the uniform one and with one sharpened by three sweeps, against two other ways
to the same expected information gain, measured in the same run on the same beliefs:
one exponential pass over every held-out sweep's updated belief (row by row, what the
table does when a repeat discount applies), and one numpy pass per movement and texture
(the straightforward way). Prints the median and p99 of each, the ratios and the margin
to the 5 ms target. Writes bench/results/identification_choice.json.
"""

import json
from pathlib import Path
import time

import numpy as np

from tactex_classify.identification.evidence_table import (
    EvidenceTable,
    MovementEvidence,
    updated_entropy,
)
from tactex_classify.identification.posterior import entropy, normalised
from tactex_classify.identification.selection import Identification

RESULTS = Path(__file__).parent / 'results'
TEXTURES, MOVEMENTS, TARGET_MS, REPEATS = 30, 12, 5.0, 300


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


def per_movement_choice(table: EvidenceTable, log_posterior: np.ndarray) -> int:
    """The same choice, one movement at a time."""
    posterior = np.exp(log_posterior)
    gains = []
    for movement in range(len(table.names)):
        expected = 0.0
        for texture in range(TEXTURES):
            terms = table.held_out_log_likelihoods(movement, texture)
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


def row_by_row_choice(table: EvidenceTable, sweeps: tuple, log_posterior: np.ndarray) -> int:
    """The same choice, every held-out sweep's updated belief in one exponential pass."""
    terms, movement_of, texture_of, share_of = sweeps
    drawn = np.exp(log_posterior)[texture_of] * share_of
    expected = np.bincount(movement_of, weights=drawn * updated_entropy(log_posterior, terms),
                           minlength=len(table.names))
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
    print(f'{"sweeps per cell":>15}  {"belief":>9}  {"products p50/p99 ms":>19}  '
          f'{"row by row p50/p99":>19}  {"per movement p50/p99":>21}  {"ratios":>13}  '
          f'{"target":>7}')
    for sweeps in (5, 10, 25):
        movements = evidence(sweeps, rng)
        table = EvidenceTable([f't{k}' for k in range(TEXTURES)], movements, 0.8)
        stacked = stacked_sweeps(table)
        identification = Identification(table, 'active')
        beliefs = {'uniform': identification.log_posterior.copy()}
        for chosen in (0, 1, 2):  # three sweeps of texture 0
            identification.observe(chosen, movements[chosen].probabilities[0])
        beliefs['sharpened'] = identification.log_posterior.copy()
        for belief, log_posterior in beliefs.items():
            identification.log_posterior = log_posterior
            # As after a first sweep: the choice from the prior itself is computed once,
            # when the identification starts, so timing it would time nothing.
            identification.movements = [0]
            chosen = identification.next_movement()
            assert chosen == per_movement_choice(table, log_posterior)
            assert chosen == row_by_row_choice(table, stacked, log_posterior)
            times = {
                'products_ms': timed_ms(identification.next_movement),
                'row_by_row_ms': timed_ms(
                    lambda t=table, s=stacked, b=log_posterior: row_by_row_choice(t, s, b)),
                'per_movement_ms': timed_ms(
                    lambda t=table, b=log_posterior: per_movement_choice(t, b), REPEATS // 10)}
            row = {'sweeps_per_cell': sweeps, 'belief': belief, **{
                key: [float(np.median(ms)), float(np.percentile(ms, 99))]
                for key, ms in times.items()}}
            rows.append(row)
            print(f'{sweeps:>15}  {belief:>9}  ' + '  '.join(
                f'{row[key][0]:>8.2f} / {row[key][1]:>8.2f}' for key in times) + '  '
                f'{row["row_by_row_ms"][0] / row["products_ms"][0]:>5.1f}x '
                f'{row["per_movement_ms"][0] / row["products_ms"][0]:>6.1f}x  '
                f'{TARGET_MS / row["products_ms"][1]:>6.1f}x')
    (RESULTS / 'identification_choice.json').write_text(json.dumps(
        {'textures': TEXTURES, 'movements': MOVEMENTS, 'target_ms': TARGET_MS,
         'rows': rows}, indent=2) + '\n', encoding='utf-8')


if __name__ == '__main__':
    main()
