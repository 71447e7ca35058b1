# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Active identification's core: the tempered update, information gain, policies, budgets.

The specification of `tactex_classify.identification`: the belief is updated in log space
with each movement's out-of-fold evidence; the next movement is the one with the largest
expected information gain per contact second (active) or the comparison policies; the
loop stops at the threshold or a budget; every choice repeats for the same seed.
"""

from dataclasses import replace
import math

import numpy as np
import pytest

from tactex_classify.identification.calibration import calibrated, fit_temperature, reliability
from tactex_classify.identification.evidence_table import EvidenceTable, MovementEvidence
from tactex_classify.identification.posterior import uniform
from tactex_classify.identification.selection import (
    Budget,
    DECIDED,
    Identification,
    MOVEMENT_BUDGET,
    NONE_LEFT,
    POLICIES,
    TIME_BUDGET,
)
from tactex_classify.identification.tempering import DISCOUNTS, fit_tempering, repeat_order


def gaussian_posteriors(labels, separation, rng, classes):
    """Exact class posteriors of Gaussian observations (means `separation` apart): calibrated."""
    means = np.eye(classes) * separation
    observed = means[labels] + rng.normal(size=(len(labels), classes))
    log_density = -0.5 * ((observed[:, None, :] - means[None]) ** 2).sum(-1)
    weights = np.exp(log_density - log_density.max(axis=1, keepdims=True))
    return weights / weights.sum(axis=1, keepdims=True)


def names(classes):
    return [f'texture {k}' for k in range(classes)]


def movement(name, seconds, rows):
    """A movement from (label, probability vector) rows."""
    labels = np.array([label for label, _ in rows])
    return MovementEvidence(name, seconds, np.array([vector for _, vector in rows], float),
                            labels)


def separating(pair, classes, sure=0.9, sweeps=2):
    """Held-out sweeps that tell the textures of `pair` apart and say nothing of the rest."""
    rows = []
    for label in range(classes):
        vector = np.full(classes, 1.0 / classes)
        if label in pair:
            vector[list(pair)] = (1.0 - sure) * 2.0 / classes
            vector[label] = sure * 2.0 / classes
        rows += [(label, vector)] * sweeps
    return rows


def brute_force_gain(classes, movements, tempering, prior, weights=None):
    """The expected entropy lost by each movement, by enumeration with plain loops.

    `weights`: per movement, the power its next sweep's update is raised to.
    """
    gains = []
    for index, mv in enumerate(movements):
        power = 1.0 if weights is None else weights[index]
        q = np.clip(mv.probabilities, 1e-12, 1.0) ** tempering
        typical = [sum(np.mean([q[j][k] for j in range(len(q)) if mv.labels[j] == c])
                       for c in range(classes)) / classes for k in range(classes)]
        start = -sum(p * math.log(p) for p in prior if p > 0)
        expected = 0.0
        for j in range(len(q)):
            texture = mv.labels[j]
            chance = prior[texture] / sum(1 for label in mv.labels if label == texture)
            odds = [prior[k] * (q[j][k] / typical[k]) ** power for k in range(classes)]
            after = [w / sum(odds) for w in odds]
            expected += chance * -sum(p * math.log(p) for p in after if p > 0)
        gains.append(start - expected)
    return np.array(gains)


def test_information_gain_matches_enumeration_for_three_textures_and_two_movements():
    rng = np.random.default_rng(1)
    labels = np.array([0, 0, 1, 1, 1, 2, 2])
    movements = [MovementEvidence('slow', 2.0, gaussian_posteriors(labels, 1.5, rng, 3), labels),
                 MovementEvidence('fast', 1.0, gaussian_posteriors(labels, 0.7, rng, 3), labels)]
    for tempering, prior in ((1.0, [1 / 3] * 3), (0.6, [0.7, 0.2, 0.1]), (2.5, [0.05, 0.05, 0.9]),
                             (1.0, [1e-250, 1e-6, 1 - 1e-6])):
        table = EvidenceTable(names(3), movements, tempering)
        assert table.information_gain(np.log(prior)) == pytest.approx(
            brute_force_gain(3, movements, tempering, prior), abs=1e-12)
        discounted = EvidenceTable(names(3), movements, tempering, repeat_discount=0.5)
        assert discounted.information_gain(np.log(prior), repeats=[2, 1]) == pytest.approx(
            brute_force_gain(3, movements, tempering, prior, weights=[1 / 2, 1 / 1.5]),
            abs=1e-12)


def test_a_movement_whose_outputs_ignore_the_texture_gains_nothing_and_moves_no_belief():
    same = np.array([0.7, 0.2, 0.1])
    rows = [(label, same) for label in (0, 1, 2) for _ in range(3)]
    table = EvidenceTable(names(3), [movement('a', 1.0, rows), movement('b', 3.0, rows)], 0.8)
    for prior in ([1 / 3] * 3, [0.6, 0.3, 0.1]):
        assert table.information_gain(np.log(prior)) == pytest.approx([0.0, 0.0], abs=1e-12)
    identification = Identification(table, 'active')
    identification.observe(0, same)
    assert identification.posterior == pytest.approx([1 / 3] * 3)


def test_identical_movements_gain_alike_and_a_sharper_one_gains_more():
    rng = np.random.default_rng(2)
    labels = np.repeat(np.arange(4), 5)
    blunt = gaussian_posteriors(labels, 1.0, rng, 4)
    table = EvidenceTable(names(4), [MovementEvidence('a', 1.0, blunt, labels),
                                     MovementEvidence('b', 1.0, blunt, labels),
                                     MovementEvidence('sharp', 1.0, gaussian_posteriors(
                                         labels, 3.0, rng, 4), labels)])
    gain = table.information_gain(uniform(4))
    assert gain[0] == pytest.approx(gain[1], abs=1e-15)
    assert gain[2] > gain[0] > 0


def test_active_asks_the_movement_that_separates_the_textures_still_likely():
    table = EvidenceTable(names(4), [movement('tells 0 from 1', 2.0, separating((0, 1), 4)),
                                     movement('tells 2 from 3', 2.0, separating((2, 3), 4))])
    for likely, expected in (((0, 1), 0), ((2, 3), 1)):
        prior = np.full(4, 0.01)
        prior[list(likely)] = 0.49
        identification = Identification(table, 'active', log_prior=np.log(prior))
        assert identification.next_movement() == expected


def test_gain_is_per_contact_second():
    """Of two equally telling movements, the shorter; a longer one must tell more per second."""
    rows = separating((0, 1), 2, sure=0.8)
    table = EvidenceTable(names(2), [movement('long', 6.0, rows), movement('short', 2.0, rows)])
    assert Identification(table, 'active').next_movement() == 1
    assert Identification(table, 'fixed').next_movement() == 1


def test_the_belief_stays_normalised_and_recovers_from_one_confidently_wrong_sweep():
    rows = separating((0, 1, 2), 3, sure=0.95)
    table = EvidenceTable(names(3), [movement('m', 1.0, rows)])
    identification = Identification(table, 'fixed', Budget(threshold=0.99))
    identification.observe(0, [0.0, 1.0, 0.0])  # true texture 0, the model certain of 1
    assert identification.posterior.sum() == pytest.approx(1.0)
    assert np.all(np.isfinite(identification.log_posterior))
    sweeps = 0
    while identification.leader != 0:
        identification.observe(0, [0.95, 0.025, 0.025])
        sweeps += 1
    # The zero is floored at 1e-12 (27.6 nats); each right sweep repays log(0.95/0.025).
    assert sweeps <= math.ceil(math.log(1e12) / math.log(0.95 / 0.025)) + 1


@pytest.mark.parametrize('policy', POLICIES)
def test_each_policy_repeats_its_choices_for_the_same_seed(policy):
    def run(seed):
        rng = np.random.default_rng(7)
        labels = np.repeat(np.arange(5), 4)
        table = EvidenceTable(names(5), [
            MovementEvidence(f'm{m}', 1.0 + m, gaussian_posteriors(labels, 0.4 + 0.3 * m, rng, 5),
                             labels) for m in range(4)])
        identification = Identification(table, policy, Budget(movements=8), seed=seed)
        draws = np.random.default_rng(seed)
        while (chosen := identification.next_movement()) is not None:
            identification.observe(chosen, draws.dirichlet(np.ones(5)))
        return identification.movements, identification.posterior
    first, again = run(3), run(3)
    assert first[0] == again[0]
    assert first[1] == pytest.approx(again[1], abs=0)
    if policy == 'random':
        assert any(run(seed)[0] != first[0] for seed in range(4, 10))


def test_round_robin_takes_the_movements_in_order_and_fixed_repeats_one():
    rows = separating((0, 1), 2, sure=0.55)
    table = EvidenceTable(names(2), [movement(name, 1.0, rows) for name in 'abc'])
    for policy, expected in (('round-robin', [0, 1, 2, 0, 1]), ('fixed', [0] * 5)):
        identification = Identification(table, policy, Budget(movements=5))
        while (chosen := identification.next_movement()) is not None:
            identification.observe(chosen, [0.5, 0.5])
        assert identification.movements == expected


def test_round_robin_passes_over_a_movement_that_cannot_run_and_keeps_its_turn():
    rows = separating((0, 1), 2, sure=0.55)
    table = EvidenceTable(names(2), [movement(name, 1.0, rows) for name in 'abc'])
    identification = Identification(table, 'round-robin', Budget(movements=4))
    runnable = np.array([False, True, True])  # 'a' is longer than the pathway
    while (chosen := identification.next_movement(runnable)) is not None:
        identification.observe(chosen, [0.5, 0.5])
    assert identification.movements == [1, 2, 1, 2]


def test_the_threshold_and_both_budgets_stop_the_loop():
    rows = separating((0, 1), 2, sure=0.7)
    table = EvidenceTable(names(2), [movement('short', 1.5, rows), movement('long', 4.0, rows)])

    def run(budget, answer):
        identification = Identification(table, 'round-robin', budget)
        while (chosen := identification.next_movement()) is not None:
            identification.observe(chosen, answer)
        return identification

    decided = run(Budget(threshold=0.9), [0.7, 0.3])
    assert decided.stop_reason() == DECIDED and decided.posterior[0] > 0.9
    counted = run(Budget(threshold=1.0, movements=3), [0.5, 0.5])
    assert counted.stop_reason() == MOVEMENT_BUDGET and len(counted.movements) == 3
    timed = run(Budget(threshold=1.0, seconds=8.0), [0.5, 0.5])
    # round-robin: 1.5 + 4.0 = 5.5 s, then only 'short' fits: 7.0 s, then nothing fits.
    assert timed.stop_reason() == TIME_BUDGET
    assert timed.movements == [0, 1, 0] and timed.contact_seconds == pytest.approx(7.0)
    assert run(Budget(threshold=1.0, seconds=1.0), [0.5, 0.5]).movements == []


def test_fitted_tempering_is_near_one_for_calibrated_independent_sweeps_and_below_for_sharpened():
    rng = np.random.default_rng(0)
    labels = np.repeat(np.arange(6), 30)
    movements = [MovementEvidence(f'm{m}', 1.0, gaussian_posteriors(labels, 1.0 + 0.5 * m, rng, 6),
                                  labels) for m in range(4)]
    calibrated_tau, discount = fit_tempering(names(6), movements)
    sharpened = [MovementEvidence(m.name, 1.0, m.probabilities ** 3 / np.sum(
        m.probabilities ** 3, axis=1, keepdims=True), labels) for m in movements]
    assert 0.75 <= calibrated_tau <= 1.3 and discount == 0.0  # independent: no discount
    assert fit_tempering(names(6), sharpened).exponent == pytest.approx(calibrated_tau / 3,
                                                                        rel=0.25)
    assert fit_tempering(names(6), movements, seed=5).exponent == pytest.approx(calibrated_tau,
                                                                                rel=0.25)


def repeating(labels, rng, classes, *, movements: int, noise: float):
    """Each movement's sweeps of a texture share one drawn mistake: repeats tell little new."""
    evidence = []
    for m in range(movements):
        shared = rng.normal(0.0, 1.5, size=(classes, classes)) + 1.5 * np.eye(classes)
        logits = shared[labels] + rng.normal(0.0, noise, size=(len(labels), classes))
        probabilities = np.exp(logits - logits.max(axis=1, keepdims=True))
        evidence.append(MovementEvidence(f'm{m}', 1.0, probabilities / probabilities.sum(
            axis=1, keepdims=True), labels))
    return evidence


def test_sweeps_that_repeat_their_movements_mistake_are_discounted_and_independent_ones_not():
    rng = np.random.default_rng(2)
    labels = np.repeat(np.arange(6), 20)
    shared = repeating(labels, rng, 6, movements=4, noise=0.1)
    assert fit_tempering(names(6), shared).repeat_discount == 0.0  # fitted on request only
    assert fit_tempering(names(6), shared, discounts=DISCOUNTS).repeat_discount >= 1.0
    fresh = [MovementEvidence(f'm{m}', 1.0, gaussian_posteriors(labels, 1.5, rng, 6), labels)
             for m in range(4)]
    assert fit_tempering(names(6), fresh, discounts=DISCOUNTS).repeat_discount == 0.0


def test_repeats_take_the_sweeps_their_first_sweeps_model_judged_then_the_other_models():
    models = np.array([0, 0, 1, 1, 1, 2])
    assert list(repeat_order(models, 3)) == [3, 4, 2, 5, 0, 1]
    assert list(repeat_order(models, 5)) == [5, 0, 1, 2, 3, 4]
    assert list(repeat_order(np.arange(4), 2)) == [2, 3, 0, 1]  # a model per sweep: round


def judged_by_three_models(name, wrong_shift, rng, rounds=6):
    """Interleaved sweeps of three models; model m says the next texture for texture m + shift."""
    rows, labels, models = [], [], []
    for texture in range(3):
        for _ in range(rounds):
            for model in range(3):
                said = (texture + 1) % 3 if (model + wrong_shift) % 3 == texture else texture
                vector = np.full(3, 0.1) * np.exp(rng.normal(0.0, 0.1, 3))
                vector[said] = 0.8
                rows.append(vector / vector.sum())
                labels.append(texture)
                models.append(model)
    return MovementEvidence(name, 1.0, np.array(rows), np.array(labels), np.array(models))


def test_repeats_judged_by_one_model_share_its_mistakes_so_the_fit_trusts_them_less():
    rng = np.random.default_rng(0)
    judged = [judged_by_three_models('a', 0, rng), judged_by_three_models('b', 1, rng)]
    unknown = [replace(movement, models=None) for movement in judged]  # a model per sweep
    assert (fit_tempering(names(3), judged).exponent
            < 0.6 * fit_tempering(names(3), unknown).exponent)
    assert fit_tempering(names(3), judged, discounts=DISCOUNTS).repeat_discount > 0.0
    assert fit_tempering(names(3), unknown, discounts=DISCOUNTS).repeat_discount == 0.0


def test_a_discounted_repeat_moves_the_belief_less_and_active_turns_to_another_movement():
    rows = separating((0, 1), 2, sure=0.8)
    table = EvidenceTable(names(2), [movement('first', 1.0, rows),
                                     movement('second', 1.0, rows)], 1.0, repeat_discount=1.0)
    assert table.repeat_weights([0, 1, 3]) == pytest.approx([1.0, 0.5, 0.25])
    first = table.log_likelihood(0, [0.8, 0.2])
    assert table.log_likelihood(0, [0.8, 0.2], repeats=2) == pytest.approx(first / 3)
    gain = table.information_gain(uniform(2), repeats=[1, 0])
    assert gain[1] > gain[0] > 0.0
    identification = Identification(table, 'active', Budget(threshold=1.0, movements=4))
    while (chosen := identification.next_movement()) is not None:
        identification.observe(chosen, [0.8, 0.2])
    assert identification.movements == [0, 1, 0, 1]


def test_active_realized_turns_from_a_movement_whose_sweeps_move_nothing_where_active_repeats_it():
    """Live, a model out of its depth answers flat vectors: active asks its movement again."""
    rows = separating((0, 1, 2, 3), 4, sure=0.9)
    table = EvidenceTable(names(4), [movement('sharp', 1.0, rows),
                                     movement('weaker', 1.0, separating((0, 1, 2, 3), 4, 0.8))])
    flat = np.full(4, 0.25)
    chosen_by = {}
    for policy in ('active', 'active-realized'):
        identification = Identification(table, policy, Budget(threshold=1.0, movements=4))
        while (chosen := identification.next_movement()) is not None:
            identification.observe(chosen, flat if chosen == 0 else [0.8, 0.2 / 3, 0.2 / 3,
                                                                     0.2 / 3])
        chosen_by[policy] = identification.movements
    assert chosen_by['active'] == [0, 0, 0, 0]
    assert chosen_by['active-realized'][0] == 0 and 1 in chosen_by['active-realized'][1:3]


def telling(classes, sure, sweeps=2):
    """Held-out sweeps that give their true texture `sure` and share the rest evenly."""
    rows = []
    for label in range(classes):
        vector = np.full(classes, (1.0 - sure) / (classes - 1))
        vector[label] = sure
        rows += [(label, vector)] * sweeps
    return rows


def test_active_rounds_runs_every_movement_once_in_the_order_of_gain_before_any_twice():
    """One model judges all of a movement's sweeps: rounds spread the evidence over models."""
    table = EvidenceTable(names(4), [movement('weak', 1.0, telling(4, 0.4)),
                                     movement('sharp', 1.0, telling(4, 0.9)),
                                     movement('middling', 1.0, telling(4, 0.6))])
    said = [0.4, 0.2, 0.2, 0.2]  # each sweep leans a little to texture 0
    chosen_by = {}
    for policy in ('active', 'active-rounds'):
        identification = Identification(table, policy, Budget(threshold=1.0, movements=7))
        while (chosen := identification.next_movement()) is not None:
            identification.observe(chosen, said)
        chosen_by[policy] = identification.movements
    assert chosen_by['active'] == [1] * 7
    assert chosen_by['active-rounds'] == [1, 2, 0, 1, 2, 0, 1]


def test_active_rounds_counts_a_round_over_the_movements_it_can_still_run():
    """A movement out of sweeps (or of the time left) does not hold the round open."""
    table = EvidenceTable(names(3), [movement('sharp', 1.0, telling(3, 0.9)),
                                     movement('spent', 1.0, telling(3, 0.9)),
                                     movement('long', 5.0, telling(3, 0.9)),
                                     movement('weak', 1.0, telling(3, 0.5))])
    identification = Identification(table, 'active-rounds', Budget(threshold=1.0, seconds=4.0))
    available = np.array([True, False, True, True])
    while (chosen := identification.next_movement(available)) is not None:
        identification.observe(chosen, [0.5, 0.3, 0.2])
    assert identification.movements == [0, 3, 0, 3]  # 'long' never fits the 4 s


def test_a_bootstrap_of_the_table_weighs_each_cells_sweeps_to_one_and_alike_is_the_gain():
    rng = np.random.default_rng(3)
    labels = np.repeat(np.arange(3), 6)
    table = EvidenceTable(names(3), [
        MovementEvidence(f'm{k}', 1.0, gaussian_posteriors(labels, 1.5, rng, 3), labels)
        for k in range(2)])
    weights = table.bootstrap_weights(np.random.default_rng(0))
    assert np.all(weights > 0.0) and weights.shape == (36,)
    assert np.bincount(np.repeat(np.arange(6), 6), weights=weights) == pytest.approx(np.ones(6))
    belief = np.log([0.5, 0.3, 0.2])
    assert table.information_gain(belief, sweep_weights=np.full(36, 1 / 6)) == pytest.approx(
        table.information_gain(belief))
    assert not np.allclose(table.information_gain(belief, sweep_weights=weights),
                           table.information_gain(belief))
    with pytest.raises(ValueError, match='one weight per held-out sweep'):
        table.information_gain(belief, sweep_weights=np.ones(5))


def test_active_sampled_shares_its_choice_between_movements_the_table_cannot_tell_apart():
    """Two movements with the same held-out sweeps: active takes the first, the sample either."""
    rng = np.random.default_rng(2)
    labels = np.repeat(np.arange(3), 10)
    alike = gaussian_posteriors(labels, 2.0, rng, 3)
    table = EvidenceTable(names(3), [
        MovementEvidence('alike', 1.0, alike, labels),
        MovementEvidence('alike again', 1.0, alike, labels),
        MovementEvidence('weak', 1.0, gaussian_posteriors(labels, 0.2, rng, 3), labels)])
    first = {policy: [Identification(table, policy, seed=seed).next_movement()
                      for seed in range(200)] for policy in ('active', 'active-sampled')}
    assert set(first['active']) == {0}  # a tie goes to the movement listed first
    counts = np.bincount(first['active-sampled'], minlength=3)
    assert min(counts[:2]) > 60 and counts[2] < 5, counts  # about 100 each, 7 apart by chance


def test_realized_trust_is_one_before_a_sweep_and_halves_after_a_sweep_that_moved_nothing():
    rows = separating((0, 1), 2, sure=0.8)
    table = EvidenceTable(names(2), [movement('a', 1.0, rows), movement('b', 1.0, rows)])
    identification = Identification(table, 'active-realized', Budget(threshold=1.0))
    assert identification.realized_trust() == pytest.approx([1.0, 1.0])
    identification.observe(0, [0.5, 0.5])  # moved nothing: trust w / 2w
    assert identification.realized_trust() == pytest.approx([0.5, 1.0])
    assert Identification(table, 'active').realized_trust() == pytest.approx([1.0, 1.0])


def test_realized_trust_stays_near_one_on_sweeps_like_the_held_out_ones():
    """Tempered, normalised updates of biased models: realized KL against expected KL."""
    rng = np.random.default_rng(1)
    labels = np.repeat(np.arange(8), 10)
    movements = []
    for index in range(4):
        vectors = gaussian_posteriors(labels, 0.8 + 0.4 * index, rng, 8)
        vectors[:, 0] += 0.2  # every model favours texture 0
        movements.append(MovementEvidence(f'm{index}', 1.0, vectors / vectors.sum(1)[:, None],
                                          labels))
    table = EvidenceTable(names(8), movements, tempering=0.62)
    trusts = []
    for episode in range(200):
        truth = episode % 8
        identification = Identification(table, 'active-realized', Budget(movements=6))
        while (chosen := identification.next_movement()) is not None:
            own = movements[chosen].probabilities[labels == truth]
            identification.observe(chosen, own[rng.integers(len(own))])
        trusts += list(identification.realized_trust()[identification.repeats > 0])
    assert 0.85 < np.median(trusts) < 1.15


def test_temperature_scaling_undoes_overconfidence_and_lowers_the_calibration_error():
    rng = np.random.default_rng(4)
    labels = np.repeat(np.arange(5), 200)
    honest = gaussian_posteriors(labels, 2.0, rng, 5)
    overconfident = calibrated(honest, 1 / 3)
    assert fit_temperature(honest, labels) == pytest.approx(1.0, abs=0.15)
    temperature = fit_temperature(overconfident, labels)
    assert temperature == pytest.approx(3.0, rel=0.15)
    before, after = (reliability(p, labels) for p in (overconfident,
                                                      calibrated(overconfident, temperature)))
    assert after.error < before.error / 2
    assert after.counts.sum() == len(labels) and len(after.edges) == 11


def test_malformed_evidence_is_refused_naming_what_is_wrong():
    rows = separating((0, 1), 3)
    with pytest.raises(ValueError, match='no held-out sweep of texture 2'):
        EvidenceTable(names(3), [movement('m', 1.0, [r for r in rows if r[0] != 2])])
    with pytest.raises(ValueError, match='repeat'):
        EvidenceTable(names(3), [movement('m', 1.0, rows), movement('m', 2.0, rows)])
    with pytest.raises(ValueError, match='contact_seconds'):
        EvidenceTable(names(3), [movement('m', 0.0, rows)])
    with pytest.raises(ValueError, match=r'probabilities must be \(sweeps, 3\)'):
        EvidenceTable(names(3), [MovementEvidence('m', 1.0, np.ones((6, 2)), np.zeros(6, int))])
    with pytest.raises(ValueError, match='models must be one integer per sweep'):
        EvidenceTable(names(3), [replace(movement('m', 1.0, rows), models=np.zeros(6))])
    with pytest.raises(ValueError, match='no movements'):
        EvidenceTable(names(3), [])
    with pytest.raises(ValueError, match='tempering'):
        EvidenceTable(names(3), [movement('m', 1.0, rows)], tempering=0.0)
    table = EvidenceTable(names(3), [movement('m', 1.0, rows)])
    with pytest.raises(ValueError, match='unknown policy'):
        Identification(table, 'greedy')
    with pytest.raises(ValueError, match='movement must be an index'):
        Identification(table, 'active').observe(1, [1, 0, 0])
    with pytest.raises(ValueError, match='finite'):
        Identification(table, 'active').observe(0, [math.nan, 0, 1])
    with pytest.raises(ValueError, match='movement budget'):
        Budget(movements=0)


def test_only_available_movements_are_chosen_and_none_left_stops_the_loop():
    rows = separating((0, 1), 2, sure=0.55)
    table = EvidenceTable(names(2), [movement(name, 1.0, rows) for name in 'abc'])
    for policy in POLICIES:
        identification = Identification(table, policy, Budget(threshold=1.0))
        chosen = identification.next_movement(np.array([False, True, False]))
        assert chosen == (1 if policy != 'fixed' else None)
        assert identification.stop_reason(np.zeros(3, dtype=bool)) == NONE_LEFT


def test_a_leader_above_the_threshold_from_the_start_decides_only_after_one_movement():
    rows = separating((0, 1), 2, sure=0.7)
    table = EvidenceTable(names(2), [movement('a', 1.0, rows)])
    identification = Identification(table, 'active', Budget(threshold=0.8),
                                     log_prior=np.log([0.9, 0.1]))
    assert identification.stop_reason() == '' and identification.next_movement() == 0
    identification.observe(0, [0.7, 0.3])
    assert identification.stop_reason() == DECIDED


@pytest.mark.parametrize('threshold', [0.0, 0.3, 0.5])
def test_a_threshold_the_uniform_belief_reaches_is_refused_naming_the_least_value(threshold):
    table = EvidenceTable(names(2), [movement('a', 1.0, separating((0, 1), 2))])
    with pytest.raises(ValueError, match=f'threshold {threshold:g} is at or below 1/2 = 0.5, '
                                         'the starting belief over 2 textures: give more than '
                                         '0.5'):
        Identification(table, 'active', Budget(threshold=threshold))
    assert Identification(table, 'active', Budget(threshold=1.0)).next_movement() == 0
    assert Identification(table, 'active', Budget(threshold=0.51)).next_movement() == 0
