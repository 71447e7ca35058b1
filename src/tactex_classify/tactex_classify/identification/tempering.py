# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""The update's exponent tau and repeat discount c, fitted so the belief is as sure as allowed.

Sweeps of one texture are not quite independent given the texture (the same model, the
same patch of surface), so multiplying their likelihoods makes the belief overconfident.
One exponent tau scales every log likelihood, and a movement's sweep after n of its own
counts 1 / (1 + c n) of its first (`EvidenceTable.repeat_weights`): repeats of one
movement share its model's mistakes more than sweeps of different movements do. Both are
fitted on the out-of-fold vectors themselves: for every texture, replayed episodes draw
movements uniformly and, for each, one of its held-out sweeps of that texture (a
movement drawn again takes another, never the same one while others are left, and first
those the same cross-validation model judged: an identification's repeats of a movement
all meet one model, the final one, so they share its mistakes); (tau, c) minimises the
mean negative log posterior of the true texture over every step of every episode (a
proper scoring rule, so neither overconfidence nor timidity pays). The draws are made
once from `seed` and shared by every candidate: tau on a logarithmic grid, c among the
discounts asked for (ties: the smaller c, then the smaller tau). By default c is 0
(every sweep counts fully) and fitted only on request (DISCOUNTS): on held-out sweeps of
fresh scene seeds the fitted discount kept `active` from falling behind `random` late,
but made it decide no sooner than random (docs/topics/identification-measured.md).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from tactex_classify.identification.evidence_table import (
    EvidenceTable,
    MovementEvidence,
    repeat_weight,
)
from tactex_classify.identification.posterior import normalised

CANDIDATES = np.geomspace(0.05, 4.0, 41)
DISCOUNTS = (0.0, 0.25, 0.5, 1.0, 2.0, 4.0)


class Tempering(NamedTuple):
    """The update's fitted exponent tau and repeat discount c."""

    exponent: float
    repeat_discount: float


def replayed_terms(table: EvidenceTable, draws: list[tuple[int, list[tuple[int, int]]]]
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(episodes x steps x classes update terms, episodes x steps repeats, true textures).

    `draws`: (true texture, [(movement, a random integer), ...]) per episode, every episode
    as long; a movement's first integer in an episode picks its first held-out sweep of the
    texture, and each repeat takes the next in `repeat_order`: the sweeps the same model
    judged first, as an identification's repeats of a movement all meet one model.
    """
    terms = np.empty((len(draws), len(draws[0][1]), len(table.classes)))
    repeats = np.zeros(terms.shape[:2], dtype=int)
    for episode, (texture, steps) in enumerate(draws):
        orders: dict[int, np.ndarray] = {}
        taken = np.zeros(len(table.names), dtype=int)
        for step, (movement, draw) in enumerate(steps):
            held_out = table.held_out_log_likelihoods(movement, texture)
            if movement not in orders:
                models = table.held_out_models(movement, texture)
                orders[movement] = repeat_order(models, draw % len(models))
            order = orders[movement]
            terms[episode, step] = held_out[order[taken[movement] % len(order)]]
            repeats[episode, step] = taken[movement]
            taken[movement] += 1
    return terms, repeats, np.array([texture for texture, _ in draws])


def repeat_order(models: np.ndarray, first: int) -> np.ndarray:
    """The order in which repeats take sweeps, from sweep `first`, given ascending `models`.

    First the sweeps of `first`'s model, from `first` on and round to its block's start;
    then the other models' sweeps, from the next block on, round. With every sweep a model
    of its own, that is every sweep from `first` on, round.
    """
    count = len(models)
    start = int(np.searchsorted(models, models[first], side='left'))
    stop = int(np.searchsorted(models, models[first], side='right'))
    block = np.r_[first:stop, start:first]
    rest = np.r_[stop:count, 0:start]
    return np.concatenate([block, rest]).astype(int)


def discount_loss(terms: np.ndarray, repeats: np.ndarray, truth: np.ndarray,
                  discount: float) -> float:
    """Mean -log posterior of the true texture after each replayed step, under discount c.

    The update is a sum of the steps' weighted terms, so every step's belief is a cumulative
    sum, normalised.
    """
    summed = np.cumsum(terms * repeat_weight(discount, repeats)[..., None], axis=1)
    log_posterior = normalised(summed)  # the uniform prior cancels
    return float(-np.mean(log_posterior[np.arange(len(truth)), :, truth]))


def fit_tempering(classes: Sequence[str], movements: Sequence[MovementEvidence], *,
                  episodes_per_texture: int = 20, steps: int | None = None,
                  seed: int = 0, discounts: Sequence[float] = (0.0,)) -> Tempering:
    """The (tau in CANDIDATES, c in `discounts`) with the smallest replay loss.

    Args:
        classes: the texture names.
        movements: the movements' out-of-fold evidence.
        episodes_per_texture: replayed episodes for each texture.
        steps: movements per episode (default: twice the movements, at least 3, so that
            movements repeat as they do in an identification).
        seed: the draws' seed.
        discounts: the repeat discounts tried (default (0,): every sweep counts fully;
            DISCOUNTS fits c).
    """
    rng = np.random.default_rng(seed)
    steps = steps or max(3, 2 * len(movements))
    draws = [(texture, [(int(rng.integers(len(movements))), int(rng.integers(2 ** 31)))
                        for _ in range(steps)])
             for texture in range(len(classes)) for _ in range(episodes_per_texture)]
    replays = [replayed_terms(EvidenceTable(classes, movements, tempering), draws)
               for tempering in CANDIDATES]
    losses = np.array([[discount_loss(*replay, discount) for replay in replays]
                       for discount in discounts])
    best_discount, best_exponent = np.unravel_index(int(np.argmin(losses)), losses.shape)
    return Tempering(float(CANDIDATES[best_exponent]), float(discounts[best_discount]))
