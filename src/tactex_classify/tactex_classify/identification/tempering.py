# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The update's exponent tau: fitted so that the belief is as sure as the sweeps allow.

Sweeps of one texture are not quite independent given the texture (the same model, the
same patch of surface), so multiplying their likelihoods makes the belief overconfident.
One exponent tau scales every log likelihood. It is fitted on the out-of-fold vectors
themselves: for every texture, replayed episodes draw movements uniformly and, for each,
one of its held-out sweeps of that texture; tau minimises the mean negative log posterior
of the true texture over every step of every episode (a proper scoring rule, so neither
overconfidence nor timidity pays). The draws are made once from `seed` and shared by
every candidate tau, which are searched on a logarithmic grid.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from tactex_classify.identification.evidence_table import EvidenceTable, MovementEvidence
from tactex_classify.identification.posterior import uniform, updated

CANDIDATES = np.geomspace(0.05, 4.0, 41)


def replay_loss(table: EvidenceTable, draws: list[tuple[int, list[tuple[int, int]]]]) -> float:
    """Mean -log posterior of the true texture after each step of the replayed episodes.

    Args:
        table: the evidence under the candidate exponent.
        draws: (true texture, [(movement, index of one of its held-out sweeps), ...]) per
            episode.
    """
    losses = []
    for texture, steps in draws:
        log_posterior = uniform(len(table.classes))
        for movement, sweep in steps:
            terms = table.held_out_log_likelihoods(movement, texture)
            log_posterior = updated(log_posterior, terms[sweep % len(terms)])
            losses.append(-log_posterior[texture])
    return float(np.mean(losses))


def fit_tempering(classes: Sequence[str], movements: Sequence[MovementEvidence], *,
                  episodes_per_texture: int = 20, steps: int | None = None,
                  seed: int = 0) -> float:
    """The exponent in CANDIDATES with the smallest replay loss (ties: the smaller).

    Args:
        classes: the texture names.
        movements: the movements' out-of-fold evidence.
        episodes_per_texture: replayed episodes for each texture.
        steps: movements per episode (default: as many as there are movements, at least 3).
        seed: the draws' seed.
    """
    rng = np.random.default_rng(seed)
    steps = steps or max(3, len(movements))
    draws = [(texture, [(int(rng.integers(len(movements))), int(rng.integers(2 ** 31)))
                        for _ in range(steps)])
             for texture in range(len(classes)) for _ in range(episodes_per_texture)]
    losses = [replay_loss(EvidenceTable(classes, movements, tempering), draws)
              for tempering in CANDIDATES]
    return float(CANDIDATES[int(np.argmin(losses))])
