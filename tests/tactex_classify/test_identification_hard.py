# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Active identification's core under any probabilities, beliefs, exponents and budgets.

Whatever a model answers (zeros, subnormals, 1e-300, ones, values above one, unnormalised),
the belief stays finite and normalised and the expected information gain finite; a NaN,
an infinity, a negative value or a wrong shape is refused with a ValueError naming it;
calibration and the tempering fit stay finite on extreme probabilities and any models
(repeats still take every sweep once); the best plans' accuracies stay shares on any
sweeps, and so do paired differences between policies on any episodes and contact
times, and every policy's trade-off at any thresholds; empty input is refused.
"""

from dataclasses import replace
import math

from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
import numpy as np
import pytest
from support.hard_values import anything, NON_FINITE

from tactex_classify.identification.calibration import calibrated, fit_temperature, reliability
from tactex_classify.identification.comparison import (
    against_fixed,
    contact_grid,
    MAX_TIMES,
    paired_difference,
)
from tactex_classify.identification.evidence_table import EvidenceTable, MovementEvidence
from tactex_classify.identification.offline import best_plans, Episode, repeat_sums
from tactex_classify.identification.pathway_part import movement_part
from tactex_classify.identification.posterior import entropy, normalised
from tactex_classify.identification.selection import Budget, Identification, POLICIES
from tactex_classify.identification.tempering import DISCOUNTS, fit_tempering, repeat_order
from tactex_classify.identification.tradeoff import (
    at_equal_accuracy,
    fixed_goal,
    fixed_goal_interval,
    mean_saving_interval,
    saving_interval,
    stop_step,
    texture_sums,
    tradeoff,
)
from tactex_description.movements import Movement

pytestmark = pytest.mark.hard_case

# What a model can answer: any non-negative finite numbers, the breaking ones often.
answers = st.one_of(st.sampled_from([0.0, -0.0, 5e-324, 1e-300, 1.0, 1e300]), st.floats(0.0, 1.0))


# Which model judged a sweep: any integers, the extremes often.
model_ids = st.one_of(st.sampled_from([-2 ** 63, -1, 0, 2 ** 63 - 1]), st.integers(0, 3))


@st.composite
def evidence(draw):
    """Texture names and 1-3 movements' evidence over them, with any answers."""
    classes = draw(st.integers(1, 4))
    movements = []
    for index in range(draw(st.integers(1, 3))):
        labels = np.array(list(range(classes)) + draw(st.lists(st.integers(0, classes - 1),
                                                                max_size=3)))
        probabilities = draw(hnp.arrays(np.float64, (len(labels), classes), elements=answers))
        seconds = draw(st.sampled_from([1e-9, 0.5, 3.0, 1e6]))
        models = draw(st.none() | hnp.arrays(np.int64, len(labels), elements=model_ids))
        movements.append(MovementEvidence(f'm{index}', seconds, probabilities, labels, models))
    return [f't{k}' for k in range(classes)], movements


@st.composite
def tables(draw):
    """An evidence table of any evidence, under an exponent from tiny to the largest."""
    return EvidenceTable(*draw(evidence()), draw(st.sampled_from([1e-6, 0.3, 1.0, 100.0])),
                         draw(st.sampled_from([0.0, 1e-9, 1.0, 100.0])))


def assert_normalised(identification):
    assert np.all(np.isfinite(identification.log_posterior))
    assert identification.posterior.sum() == pytest.approx(1.0)


@settings(max_examples=200, deadline=None)
@given(tables(), st.sampled_from(POLICIES), st.integers(0, 2 ** 32 - 1), st.data())
def test_any_answers_keep_the_belief_finite_and_normalised(table, policy, seed, data):
    classes = len(table.classes)
    identification = Identification(table, policy, Budget(movements=6), seed=seed)
    assert np.all(np.isfinite(table.information_gain(identification.log_posterior)))
    while (chosen := identification.next_movement()) is not None:
        identification.observe(chosen, data.draw(hnp.arrays(np.float64, classes,
                                                            elements=answers)))
        assert_normalised(identification)
        assert np.all(np.isfinite(table.information_gain(identification.log_posterior,
                                                         identification.repeats)))
        assert all(0.0 <= table.expected_divergence(identification.log_posterior, index,
                                                     int(identification.repeats[index]))
                   < np.inf for index in range(len(table.names)))
        assert np.all(np.isfinite(identification.realized_trust()))


def gain_sweep_by_sweep(table, log_posterior, repeats=None):
    """The expected information gain, one held-out sweep at a time (no shortcut)."""
    log_posterior = normalised(log_posterior)
    posterior = np.exp(log_posterior)
    expected = np.zeros(len(table.names))
    for movement in range(len(table.names)):
        weight = 1.0 if repeats is None else table.repeat_weights(repeats[movement])
        for texture in range(len(table.classes)):
            terms = weight * table.held_out_log_likelihoods(movement, texture)
            expected[movement] += posterior[texture] * np.mean(
                entropy(normalised(log_posterior + terms)))
    return entropy(log_posterior) - expected


@settings(max_examples=200, deadline=None)
@given(tables(), st.data())
def test_the_gain_equals_the_sweep_by_sweep_sum_for_any_evidence_and_belief(table, data):
    log_posterior = data.draw(hnp.arrays(np.float64, len(table.classes),
                                         elements=st.floats(-1e3, 0.0)))
    # Textures below 1e-9 of belief in all may be left out: at most 1e-9 * log(4) nats.
    assert table.information_gain(log_posterior) == pytest.approx(
        gain_sweep_by_sweep(table, log_posterior), abs=1e-8)


@settings(max_examples=200, deadline=None)
@given(tables(), st.data())
def test_the_discounted_gain_equals_the_sweep_by_sweep_sum_however_often_it_is_asked(table, data):
    log_posterior = data.draw(hnp.arrays(np.float64, len(table.classes),
                                         elements=st.floats(-1e3, 0.0)))
    asked = data.draw(st.lists(hnp.arrays(np.int64, len(table.names),
                                          elements=st.integers(0, 40)), min_size=1, max_size=3))
    expected = [gain_sweep_by_sweep(table, log_posterior, repeats) for repeats in asked]
    for repeats, gain in 2 * list(zip(asked, expected, strict=True)):  # again, as kept
        assert table.information_gain(log_posterior, repeats) == pytest.approx(gain, abs=1e-8)


@pytest.mark.parametrize('repeats', [[1], [1, 0, 0], [0.5, 0], [-1, 0], [np.nan, 0],
                                     [np.inf, 0], 'ab'])
def test_repeats_that_are_not_counts_per_movement_are_refused(repeats):
    table = EvidenceTable(['a', 'b'], [MovementEvidence(name, 1.0, np.eye(2), np.arange(2))
                                       for name in ('m0', 'm1')], repeat_discount=0.5)
    with pytest.raises(ValueError, match='repeats must be one whole number'):
        table.information_gain(np.log([0.5, 0.5]), repeats)


@settings(max_examples=100, deadline=None)
@given(tables(), st.data())
def test_the_best_plans_are_shares_on_any_sweeps(table, data):
    classes, names = len(table.classes), list(table.names)
    plan_terms = []
    for repeat, fold in np.ndindex(data.draw(st.integers(1, 2)), data.draw(st.integers(1, 2))):
        for texture in range(classes):
            pools = [[data.draw(hnp.arrays(np.float64, classes, elements=answers))
                      for _ in range(data.draw(st.integers(1, 3)))] for _ in names]
            plan_terms.append((repeat, fold, texture, repeat_sums(table, pools)))
    plans = best_plans({'movements': names, 'contact_s': table.seconds.tolist(),
                        'classes': list(table.classes), 'plan_terms': plan_terms})
    assert plans and [plan['movements'] for plan in plans] == list(range(1, len(plans) + 1))
    for plan in plans:
        assert 0.0 <= plan['accuracy'] <= 1.0 and math.isfinite(plan['contact_s'])
        assert plan['chosen_elsewhere'] is None or 0.0 <= plan['chosen_elsewhere'] <= 1.0


@pytest.mark.parametrize('answer', [[0.0, 0.0, 0.0], [1e-300, 1e-300, 1.0], [1.0, 1.0, 1.0],
                                    [0.0, 1.0, 0.0], [5e-324, 0.0, 1e300]])
def test_likelihoods_of_zero_tiny_and_one_keep_the_belief_normalised(answer):
    labels = np.array([0, 1, 2])
    table = EvidenceTable(['a', 'b', 'c'], [MovementEvidence('m', 1.0, np.eye(3), labels)])
    identification = Identification(table, 'active')
    for _ in range(50):
        identification.observe(0, answer)
        assert_normalised(identification)


@given(st.lists(anything(), min_size=3, max_size=3).filter(
    lambda values: any(not math.isfinite(v) or v < 0 for v in values)))
def test_a_non_finite_or_negative_answer_is_refused_and_leaves_the_belief(answer):
    table = EvidenceTable(['a', 'b', 'c'], [MovementEvidence('m', 1.0, np.eye(3), np.arange(3))])
    identification = Identification(table, 'active')
    before = identification.log_posterior.copy()
    with pytest.raises(ValueError, match='finite and >= 0'):
        identification.observe(0, answer)
    assert np.array_equal(identification.log_posterior, before)
    assert identification.movements == []


@pytest.mark.parametrize('bad', [*NON_FINITE, -1.0])
def test_non_finite_or_negative_evidence_prior_or_budget_is_refused(bad):
    labels = np.arange(2)
    with pytest.raises(ValueError, match='finite and >= 0'):
        EvidenceTable(['a', 'b'], [MovementEvidence('m', 1.0, np.array([[bad, 1.0], [0.0, 1.0]]),
                                                    labels)])
    with pytest.raises(ValueError, match='contact_seconds'):
        EvidenceTable(['a', 'b'], [MovementEvidence('m', bad, np.eye(2), labels)])
    table = EvidenceTable(['a', 'b'], [MovementEvidence('m', 1.0, np.eye(2), labels)])
    if not math.isfinite(bad):  # a log prior may be negative, not infinite
        with pytest.raises(ValueError, match='prior'):
            Identification(table, 'active', log_prior=np.array([bad, 0.0]))
    with pytest.raises(ValueError, match='time budget'):
        Budget(seconds=bad)
    with pytest.raises(ValueError, match='tempering'):
        EvidenceTable(['a', 'b'], [MovementEvidence('m', 1.0, np.eye(2), labels)], bad)
    with pytest.raises(ValueError, match='repeat_discount'):
        EvidenceTable(['a', 'b'], [MovementEvidence('m', 1.0, np.eye(2), labels)], 1.0, bad)


def test_empty_input_is_refused():
    with pytest.raises(ValueError, match='no textures'):
        EvidenceTable([], [MovementEvidence('m', 1.0, np.zeros((0, 0)), np.zeros(0, int))])
    with pytest.raises(ValueError, match='no held-out sweep'):
        EvidenceTable(['a'], [MovementEvidence('m', 1.0, np.zeros((0, 1)), np.zeros(0, int))])
    with pytest.raises(ValueError, match='samples'):
        fit_temperature(np.zeros((0, 3)), np.zeros(0, int))
    with pytest.raises(ValueError, match='samples'):
        reliability(np.zeros((0, 3)), np.zeros(0, int))


@settings(max_examples=100, deadline=None)
@given(hnp.arrays(np.float64, st.tuples(st.integers(1, 20), st.integers(1, 4)), elements=answers),
       st.data())
def test_calibration_stays_finite_on_any_answers(probabilities, data):
    labels = np.array(data.draw(st.lists(st.integers(0, probabilities.shape[1] - 1),
                                         min_size=len(probabilities),
                                         max_size=len(probabilities))))
    temperature = fit_temperature(probabilities, labels)
    assert 0.05 <= temperature <= 20.0
    scaled = calibrated(probabilities, temperature)
    assert np.all(np.isfinite(scaled)) and scaled.sum(axis=1) == pytest.approx(1.0)
    assert 0.0 <= reliability(probabilities, labels).error <= 1.0


@settings(max_examples=30, deadline=None)
@given(evidence())
def test_the_tempering_fit_stays_on_its_grid_for_any_answers(drawn):
    exponent, discount = fit_tempering(*drawn, episodes_per_texture=2, discounts=DISCOUNTS)
    assert 0.05 <= exponent <= 4.0 and discount in DISCOUNTS


@settings(max_examples=200, deadline=None)
@given(hnp.arrays(np.int64, st.integers(1, 12), elements=model_ids), st.data())
def test_repeats_take_every_sweep_once_starting_from_the_drawn_one(models, data):
    models = np.sort(models)
    first = data.draw(st.integers(0, len(models) - 1))
    order = repeat_order(models, first)
    assert order[0] == first and sorted(order) == list(range(len(models)))


@settings(max_examples=200, deadline=None)
@given(hnp.arrays(np.float64, st.tuples(st.integers(0, 5), st.just(3)), elements=anything()),
       hnp.arrays(np.float64, st.tuples(st.integers(0, 5), st.just(3)), elements=anything()),
       anything(), st.floats(1e-3, 1.0), st.sampled_from(['forward', 'backward']))
def test_a_movement_part_is_refused_or_finite_and_starts_on_the_pathway(
        points, normals, acceleration, contact_m, direction):
    wanted = Movement('m', 0.02, 0.002, 0.5, direction, contact_m)
    try:
        part, part_normals = movement_part(points, normals, wanted, acceleration)
    except ValueError:
        return
    assert np.all(np.isfinite(part)) and np.all(np.isfinite(part_normals))
    assert part.shape == part_normals.shape and len(part) >= 2
    assert np.array_equal(part[0], points[0 if direction == 'forward' else -1])


@settings(max_examples=100, deadline=None)
@given(st.data())
def test_the_paired_difference_stays_a_difference_of_shares_on_any_episodes(data):
    textures = data.draw(st.integers(1, 4))
    episodes = []
    for key in range(data.draw(st.integers(0, 6))):
        texture, steps = key % textures, data.draw(st.integers(0, 4))
        seconds = np.cumsum(data.draw(st.lists(st.sampled_from([1e-9, 2.5, 1e6]),
                                               min_size=steps, max_size=steps))).tolist()
        for policy in ('active', 'random'):
            leaders = data.draw(st.lists(st.integers(0, textures - 1), min_size=steps,
                                         max_size=steps))
            episodes.append(Episode(policy, 0, key, texture, movements=[0] * steps,
                                    leaders=leaders, contact_s=seconds))
    grid = contact_grid(episodes, data.draw(st.sampled_from([0.0, -1.0, 1e-9, 2.5, math.inf,
                                                             math.nan])))
    assert len(grid) <= MAX_TIMES and np.all(np.isfinite(grid))
    against = paired_difference(episodes, 'active', 'random', grid, resamples=50)
    assert against['pairs'] == len(episodes) // 2
    goal = against_fixed([replace(e, policy='fixed') if e.policy == 'random' else e
                          for e in episodes], resamples=50)
    if goal:
        assert math.isfinite(goal['goal_contact_s']) and goal['goal_contact_s'] >= 0.0
        assert -1.0 <= goal['low'] <= goal['margin'] + 1e-12
        assert goal['margin'] <= goal['high'] + 1e-12 <= 1.01 + 1e-12
    for name in ('difference', 'low', 'high'):
        assert len(against[name]) == len(grid)
    if against['pairs']:
        low, high = np.array(against['low']), np.array(against['high'])
        assert np.all((-1.0 <= low) & (low <= high + 1e-12) & (high <= 1.0))
        assert np.all(np.abs(against['difference']) <= 1.0)


@settings(max_examples=60, deadline=None)
@given(st.data())
def test_the_tradeoff_stays_shares_and_spent_seconds_on_any_episodes_and_thresholds(data):
    episodes = []
    for key in range(data.draw(st.integers(0, 5))):
        steps = data.draw(st.integers(0, 4))
        seconds = np.cumsum(data.draw(st.lists(st.sampled_from([1e-9, 2.5, 1e6]),
                                               min_size=steps, max_size=steps))).tolist()
        for policy in ('active', 'fixed'):
            tops = data.draw(st.lists(st.sampled_from([0.0, 0.5, 0.99, 1.0, math.nan]),
                                      min_size=steps, max_size=steps))
            leaders = data.draw(st.lists(st.integers(0, 2), min_size=steps, max_size=steps))
            episodes.append(Episode(policy, 0, key, key % 2, movements=[0] * steps,
                                    leaders=leaders, top_posterior=tops, contact_s=seconds))
    thresholds = data.draw(st.lists(st.sampled_from([-1.0, 0.0, 0.5, 0.99, 1.0, math.nan,
                                                     math.inf]), max_size=4))
    curves = {policy: tradeoff(episodes, policy, thresholds) for policy in ('active', 'fixed')}
    for policy, curve in curves.items():
        assert len(curve) in (0, len(thresholds))
        for row, threshold in zip(curve, thresholds, strict=False):  # each episode cut once
            cut = [e for e in episodes if e.policy == policy]
            steps = [stop_step(e.top_posterior, threshold) for e in cut]
            assert row['accuracy'] == pytest.approx(np.mean(
                [s >= 0 and e.leaders[s] == e.texture for e, s in zip(cut, steps, strict=True)]))
        for row in curve:
            assert 0.0 <= row['accuracy'] <= 1.0 and 0.0 <= row['decided'] <= 1.0
            assert 0.0 <= row['median_contact_s'] < math.inf
            assert 0.0 <= row['mean_contact_s'] < math.inf
    for rows in at_equal_accuracy(curves).values():
        for row in rows:
            assert row['other_seconds'] is None or 0.0 <= row['other_seconds'] < math.inf
            assert row['other_at_most'] in (True, False)
    goal = fixed_goal(curves, 0.01)
    if goal and goal['active_mean_contact_s'] is not None:
        assert 0.0 <= goal['active_mean_contact_s'] < math.inf
    sums = [texture_sums(episodes, policy, thresholds, 2) for policy in ('active', 'fixed')]
    for row in saving_interval(*sums, resamples=50):  # the seconds saved, with an interval
        for seconds in (row['saving_s'], row['low'], row['high']):
            assert seconds is None or -math.inf < seconds < math.inf
        assert 0.0 <= row['never_share'] <= 1.0 and 0.0 <= row['at_most_share'] <= 1.0
    mean = mean_saving_interval(*sums, list(dict.fromkeys(sums[0]['thresholds'])),
                                resamples=50)  # one for them all, each once
    for seconds in (mean.get('saving_s'), mean.get('low'), mean.get('high')):
        assert seconds is None or -math.inf < seconds < math.inf
    assert all(0.0 <= mean[share] <= 1.0 for share in ('never_share', 'at_most_share')
               if share in mean)
    goal = fixed_goal_interval(*sums, 0.01, resamples=50)  # and the goal against fixed
    for share in (goal.get(key) for key in ('seconds', 'seconds_low', 'seconds_high', 'share',
                                             'low', 'high')):
        assert share is None or 0.0 <= share < math.inf
