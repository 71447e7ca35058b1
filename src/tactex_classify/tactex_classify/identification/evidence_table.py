# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""What each movement tells about the texture: out-of-fold probability vectors and their gain.

For each movement the table keeps the calibrated class-probability vectors its model gave
held-out sweeps (grouped by recording), with each sweep's true texture. The update
(`posterior`) and the choice of the next movement both read these same vectors: the
expected information gain of a movement under the current belief pi is

    H(pi) - sum_c pi(c) * mean over the sweeps j of texture c of H(pi updated by q_j),

the entropy the belief is expected to lose when the next sweep of that movement is one
of its held-out sweeps of the texture drawn from pi, updated as the node would update.

Sweeps of one movement over one texture repeat its model's mistakes (the same confusion,
the same patch), so the n-th repeat of a movement tells less than its first sweep: its
update's terms are weighted by 1 / (1 + c n) (`repeat_weights`; c, the repeat discount,
is fitted with tau by `tempering`), in the update and in the gain alike.

The gain is a few matrix-vector products: with each sweep's terms shifted by their
largest (s = t - max t) and E = exp(s) kept from the start, the belief
pi' = exp(log pi - max log pi) gives each updated belief's entropy as
log(E pi') - ((E * s) pi' + E (pi' log pi')) / (E pi') (`_entropy_after_by_products`).
A movement's discounted repeat weighs its terms by w < 1, so it reads exp(w s) and
exp(w s) * w s instead, made once per movement and number of repeats and kept (up to
MAX_KEPT_REPEATS repeats). That holds to rounding while no sweep's terms span more than
PRODUCT_SPREAD nats (a texture whose belief underflows then weighs under
exp(PRODUCT_SPREAD - 745) of the leader); a wider table takes the exact row-by-row pass.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from tactex_classify.identification.posterior import (
    checked_probabilities,
    divergence,
    entropy,
    log_sum_exp,
    normalised,
    tempered_log_likelihoods,
)
from tactex_common.numbers import is_finite_number

MAX_TEMPERING = 100.0
MAX_REPEAT_DISCOUNT = 100.0
NEGLIGIBLE_MASS = 1e-9  # posterior mass left out of the expected gain (see information_gain)
PRODUCT_SPREAD = 300.0  # nats a sweep's terms may span for the gain by products
# The discounted products kept per movement (more are made each time): at most
# 2 x MAX_KEPT_REPEATS copies of the table's terms, reached only by that many repeats.
MAX_KEPT_REPEATS = 16


@dataclass(frozen=True)
class MovementEvidence:
    """One movement's out-of-fold evidence.

    Attributes:
        name: the movement's name (as in config/movements.yaml).
        contact_seconds: the edge's time in contact during one sweep of the movement.
        probabilities: (sweeps, classes) class probabilities of held-out sweeps.
        labels: (sweeps,) each sweep's true texture, an index into the classes.
        models: (sweeps,) which model judged each sweep (its inner fold), or None when
            unknown (each sweep counts as judged by a model of its own). Sweeps one model
            judged share its mistakes, as an identification's repeats of a movement do.
    """

    name: str
    contact_seconds: float
    probabilities: np.ndarray
    labels: np.ndarray
    models: np.ndarray | None = None


class EvidenceTable:
    """Every movement's out-of-fold evidence over one list of textures, ready for the loop.

    Args:
        classes: the texture names, in the models' class order.
        movements: each movement's evidence; every texture needs at least one sweep in each.
        tempering: the update's exponent tau (> 0, at most MAX_TEMPERING).
        repeat_discount: c (>= 0, at most MAX_REPEAT_DISCOUNT): a movement's sweep after n
            of its own counts 1 / (1 + c n) of its first (0: every sweep counts fully).

    Raises:
        ValueError: naming the movement, texture or value that is missing or malformed.
    """

    def __init__(self, classes: Sequence[str], movements: Sequence[MovementEvidence],
                 tempering: float = 1.0, repeat_discount: float = 0.0) -> None:
        self.classes = tuple(classes)
        if not self.classes:
            raise ValueError('no textures: the evidence needs at least one class')
        if not movements:
            raise ValueError('no movements: the evidence needs at least one')
        names = [movement.name for movement in movements]
        if len(set(names)) != len(names):
            raise ValueError(f'movement names repeat: {names}')
        if not (is_finite_number(tempering)
                and 0.0 < tempering <= MAX_TEMPERING):
            raise ValueError(f'tempering must be in (0, {MAX_TEMPERING:g}], got {tempering!r}')
        if not (is_finite_number(repeat_discount)
                and 0.0 <= repeat_discount <= MAX_REPEAT_DISCOUNT):
            raise ValueError(f'repeat_discount must be in [0, {MAX_REPEAT_DISCOUNT:g}], got '
                             f'{repeat_discount!r}')
        self.names = tuple(names)
        self.tempering = float(tempering)
        self.repeat_discount = float(repeat_discount)
        self.seconds = np.array([self._seconds(movement) for movement in movements])
        terms_of, self._labels_of, self._models_of = zip(
            *(self._rows(movement) for movement in movements), strict=True)
        self.log_typical = np.stack([
            self._log_typical(terms, labels)
            for terms, labels in zip(terms_of, self._labels_of, strict=True)])
        self._rows_of = [terms - self.log_typical[index] for index, terms in enumerate(terms_of)]
        self._stacked = np.concatenate(self._rows_of)
        self._movement_of = np.concatenate(
            [np.full(len(labels), index) for index, labels in enumerate(self._labels_of)])
        self._label_of = np.concatenate(self._labels_of)
        # Each held-out sweep's share of its texture (a texture is drawn, then its sweep).
        self._shares_of = [1.0 / np.bincount(labels, minlength=len(self.classes))[labels]
                           for labels in self._labels_of]
        self._share_of = np.concatenate(self._shares_of)
        self._shifted = self._stacked - self._stacked.max(axis=1, keepdims=True)
        self._by_products = bool(-self._shifted.min() <= PRODUCT_SPREAD)
        self._exp_shifted = np.exp(self._shifted)
        self._exp_shifted_times_shifted = self._exp_shifted * self._shifted
        self._row_ends = np.cumsum([len(labels) for labels in self._labels_of])
        self._discounted_products: dict[tuple[int, int], tuple[np.ndarray, np.ndarray]] = {}

    @staticmethod
    def _seconds(movement: MovementEvidence) -> float:
        seconds = movement.contact_seconds
        if not (is_finite_number(seconds) and seconds > 0):
            raise ValueError(f'movement {movement.name!r}: contact_seconds must be finite and '
                             f'> 0, got {seconds!r}')
        return float(seconds)

    def _rows(self, movement: MovementEvidence) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The movement's tempered log likelihood terms, labels and models, checked.

        The sweeps are put in the order of the model that judged them (stably), so that
        a texture's sweeps of one model sit together (`held_out_models`).
        """
        classes = len(self.classes)
        probabilities = np.asarray(movement.probabilities, dtype=float)
        labels = np.asarray(movement.labels)
        if probabilities.ndim != 2 or probabilities.shape[1] != classes:
            raise ValueError(f'movement {movement.name!r}: probabilities must be (sweeps, '
                             f'{classes}), got shape {probabilities.shape}')
        for row in probabilities:
            checked_probabilities(row, classes)
        if labels.shape != (len(probabilities),) or not np.issubdtype(labels.dtype, np.integer):
            raise ValueError(f'movement {movement.name!r}: labels must be one integer per '
                             f'sweep ({len(probabilities)}), got {labels!r}')
        if np.any(labels < 0) or np.any(labels >= classes):
            raise ValueError(f'movement {movement.name!r}: labels must be in [0, {classes})')
        missing = sorted(set(range(classes)) - set(labels.tolist()))
        if missing:
            raise ValueError(f'movement {movement.name!r} has no held-out sweep of '
                             f'{", ".join(self.classes[i] for i in missing)}: record and '
                             'cross-validate every texture under every movement')
        models = (np.arange(len(labels)) if movement.models is None
                  else np.asarray(movement.models))
        if models.shape != labels.shape or not np.issubdtype(models.dtype, np.integer):
            raise ValueError(f'movement {movement.name!r}: models must be one integer per '
                             f'sweep ({len(labels)}), got {movement.models!r}')
        order = np.argsort(models, kind='stable')
        return (tempered_log_likelihoods(probabilities[order], self.tempering),
                labels[order].astype(int), models[order])

    def _log_typical(self, terms: np.ndarray, labels: np.ndarray) -> np.ndarray:
        """The log of Z(k), the mean of q(k)^tau, each true texture weighted alike."""
        per_texture = np.stack([log_sum_exp(terms[labels == c], axis=0)
                                - np.log(np.sum(labels == c)) for c in range(len(self.classes))])
        return log_sum_exp(per_texture, axis=0) - np.log(len(self.classes))

    def repeat_weights(self, repeats) -> np.ndarray:
        """The weight of a sweep after `repeats` earlier sweeps of its movement."""
        return repeat_weight(self.repeat_discount, repeats)

    def log_likelihood(self, movement: int, probabilities, repeats: int = 0) -> np.ndarray:
        """The update's term for one sweep of `movement` whose model answered `probabilities`.

        `repeats`: the sweeps of `movement` already taken in this identification.

        Raises:
            ValueError: probabilities of another length, not finite, or negative.
        """
        vector = checked_probabilities(probabilities, len(self.classes))
        return self.repeat_weights(repeats) * (tempered_log_likelihoods(vector, self.tempering)
                                               - self.log_typical[movement])

    def held_out_log_likelihoods(self, movement: int, texture: int) -> np.ndarray:
        """(sweeps, classes): the update's terms of `movement`'s held-out sweeps of `texture`."""
        return self._rows_of[movement][self._labels_of[movement] == texture]

    def held_out_models(self, movement: int, texture: int) -> np.ndarray:
        """(sweeps,): which model judged each of `held_out_log_likelihoods`' rows (ascending)."""
        return self._models_of[movement][self._labels_of[movement] == texture]

    def information_gain(self, log_posterior: np.ndarray, repeats=None,
                         sweep_weights: np.ndarray | None = None) -> np.ndarray:
        """Expected entropy lost (nats) by one sweep of each movement, given the belief.

        `repeats`: per movement, its sweeps already taken, whole numbers >= 0 (default
        none): each movement's terms are weighted as its next sweep's update will be
        (`repeat_weights`).
        `sweep_weights`: each held-out sweep's chance of being the one drawn for its
        (movement, texture), one per sweep in the table's order, summing to one over each
        (default: alike, `bootstrap_weights` draws others).

        Textures whose posterior, together, is below NEGLIGIBLE_MASS are left out of the
        expectation (their sweeps would be drawn that rarely): the gain moves by at most
        that mass times log(textures) nats, and the row-by-row pass costs far less once
        the belief has narrowed.
        """
        log_posterior = normalised(np.asarray(log_posterior, dtype=float))
        posterior = np.exp(log_posterior)
        order = np.argsort(posterior)
        kept = np.ones(len(posterior), dtype=bool)
        kept[order[np.cumsum(posterior[order]) < NEGLIGIBLE_MASS]] = False
        if repeats is not None:
            repeats = self._checked_repeats(repeats)
        discounted = (repeats is not None and self.repeat_discount > 0.0
                      and np.any(repeats > 0))
        share = self._share_of if sweep_weights is None else np.asarray(sweep_weights, float)
        if share.shape != self._share_of.shape:
            raise ValueError(f'sweep_weights must be one weight per held-out sweep '
                             f'({len(self._share_of)}), got shape {share.shape}')
        if self._by_products:
            rows = slice(None)
            drawn = posterior[self._label_of] * share * kept[self._label_of]
            after = self._entropy_after_by_products(log_posterior,
                                                    repeats if discounted else None)
        else:
            rows = kept[self._label_of] if not kept.all() else slice(None)
            drawn = posterior[self._label_of[rows]] * share[rows]
            terms = self._stacked[rows]
            if discounted:
                terms = terms * self.repeat_weights(repeats)[self._movement_of[rows]][:, None]
            after = updated_entropy(log_posterior, terms)
        expected = np.bincount(self._movement_of[rows], weights=drawn * after,
                               minlength=len(self.names))
        return entropy(log_posterior) - expected

    def _checked_repeats(self, repeats) -> np.ndarray:
        """`repeats` as one whole number >= 0 per movement.

        Raises:
            ValueError: another shape, a fraction, a negative or a non-finite count.
        """
        counts = np.asarray(repeats)
        if counts.shape != (len(self.names),) or not (
                np.issubdtype(counts.dtype, np.integer)
                or (np.issubdtype(counts.dtype, np.floating) and np.all(np.isfinite(counts))
                    and np.all(counts == np.round(counts)))) or np.any(counts < 0):
            raise ValueError(f'repeats must be one whole number >= 0 per movement '
                             f'({len(self.names)}), got {repeats!r}')
        return counts.astype(int)

    def bootstrap_weights(self, rng: np.random.Generator) -> np.ndarray:
        """One Bayesian bootstrap of the held-out sweeps: Dirichlet(1) weights per cell.

        A draw of how likely each held-out sweep of a (movement, texture) cell is, given
        the few the table holds (Rubin 1981, Ann. Statist. 9:130): `information_gain`
        under it is one plausible gain of each movement, as far as the table's own
        sampling can tell.
        """
        draws = rng.exponential(size=len(self._label_of))
        cell = self._movement_of * len(self.classes) + self._label_of
        return draws / np.bincount(cell, weights=draws)[cell]

    def expected_divergence(self, log_posterior: np.ndarray, movement: int,
                            repeats: int = 0) -> float:
        """Expected KL(belief after || before) in nats from one sweep of `movement`.

        Over the movement's held-out sweeps, each drawn as in `information_gain` and
        updated as the node would update (its `repeats` earlier sweeps weigh the terms):
        the mean of what one of its sweeps moves the belief when the sweeps are like the
        held-out ones. Under a tempered, normalised update this differs from the expected
        entropy lost, so a realized KL is compared with this, not with the gain.
        """
        log_posterior = normalised(np.asarray(log_posterior, dtype=float))
        drawn = np.exp(log_posterior)[self._labels_of[movement]] * self._shares_of[movement]
        terms = self._rows_of[movement] * self.repeat_weights(repeats)
        return float(np.dot(drawn, divergence(normalised(log_posterior + terms),
                                              log_posterior)))

    def _entropy_after_by_products(self, log_posterior: np.ndarray,
                                   repeats: np.ndarray | None = None) -> np.ndarray:
        """Each held-out sweep's updated entropy from products with the belief (see top).

        `repeats`: per movement, its sweeps already taken, which discount its terms (None:
        every sweep counts fully).
        """
        relative = log_posterior - log_posterior.max()
        belief = np.exp(relative)
        belief_log = np.where(belief > 0.0, belief * relative, 0.0)
        blocks = ([(self._exp_shifted, self._exp_shifted_times_shifted)] if repeats is None
                  else [self._products(movement, int(n)) for movement, n in enumerate(repeats)])
        total = np.concatenate([exp_shifted @ belief for exp_shifted, _ in blocks])
        weighted_log = np.concatenate([times_shifted @ belief + exp_shifted @ belief_log
                                       for exp_shifted, times_shifted in blocks])
        return np.log(total) - weighted_log / total

    def _products(self, movement: int, repeats: int) -> tuple[np.ndarray, np.ndarray]:
        """exp(w s) and exp(w s) * w s over `movement`'s sweeps after `repeats` of its own."""
        rows = slice(self._row_ends[movement - 1] if movement else 0, self._row_ends[movement])
        if repeats == 0:
            return self._exp_shifted[rows], self._exp_shifted_times_shifted[rows]
        products = self._discounted_products.get((movement, repeats))
        if products is None:
            shifted = self.repeat_weights(repeats) * self._shifted[rows]
            exp_shifted = np.exp(shifted)
            products = exp_shifted, exp_shifted * shifted
            if repeats <= MAX_KEPT_REPEATS:
                self._discounted_products[movement, repeats] = products
        return products


def repeat_weight(discount: float, repeats) -> np.ndarray:
    """1 / (1 + c n): what a sweep after n earlier sweeps of its movement counts, c = discount."""
    return 1.0 / (1.0 + discount * np.asarray(repeats, dtype=float))


def updated_entropy(log_posterior: np.ndarray, log_likelihoods: np.ndarray) -> np.ndarray:
    """Entropy of the belief after each row of log likelihoods, in one exponential pass.

    With d = a - max(a) for a = log posterior + log likelihood, the updated belief is
    exp(d) / Z, whose entropy is log Z - sum(exp(d) * d) / Z.
    """
    shifted = log_posterior + log_likelihoods
    shifted -= shifted.max(axis=1, keepdims=True)
    weights = np.exp(shifted)
    total = weights.sum(axis=1)
    return np.log(total) - np.einsum('ij,ij->i', weights, shifted) / total
