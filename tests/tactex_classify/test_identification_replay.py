# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex report identification`: every policy replayed on the same held-out recordings.

Nested and grouped: each fold's evidence comes from the other folds only; an episode
never takes the same held-out sweep twice; the same inputs give the same report; the
report holds the issue's JSON, a markdown table and its plots; a dataset without
movements, or one that disagrees with the movement file, is refused naming why. The best
plan of k movements in hindsight is found by enumeration and bounds every policy that
fixes its movements in advance.
"""

from dataclasses import replace
import json
import math
import re

import numpy as np
import pytest
from support.movement_data import (
    movement_dataset,
    movement_file,
    MOVEMENTS,
    RECORDINGS,
    TEXTURES,
    WINDOW,
)

from tactex.cli import main
from tactex_classify.evaluation.cross_validation import cross_validate
from tactex_classify.identification.comparison import (
    against_fixed,
    contact_grid,
    paired_difference,
    right_by,
)
from tactex_classify.identification.movement_evidence import (
    checked_movements,
    fit_movement,
    movement_evidence,
    MovementDataError,
)
from tactex_classify.identification.offline import (
    best_plans,
    Episode,
    recordings_needed,
    replay,
    ReplaySettings,
    summary,
)
from tactex_classify.identification.report import accuracy_curves, PLOTS, write_report
from tactex_classify.identification.selection import Budget, POLICIES
from tactex_classify.identification.tempering import DISCOUNTS
from tactex_classify.identification.tradeoff import (
    fixed_goal,
    fixed_goal_interval,
    leans_on_upper_bounds,
    mean_saving_interval,
    pooled_sums,
    saves_clearly,
    saving_interval,
    seconds_for,
    stop_step,
    texture_sums,
    tradeoff,
)
from tactex_classify.training.deep_classifier import TrainingConfig
from tactex_classify.training.estimators import build_estimator
from tactex_description.movements import load_movements

SETTINGS = ReplaySettings(policies=POLICIES, folds=2, inner_folds=2, seeds=3,
                          training=TrainingConfig(model='extratrees'),
                          budget=Budget(threshold=0.99, movements=6))


@pytest.fixture(scope='module')
def replayed(tmp_path_factory):
    folder = tmp_path_factory.mktemp('replay')
    return replay(movement_dataset(folder), load_movements(movement_file(folder)), SETTINGS,
                  progress=lambda line: None)


def test_an_episode_never_takes_the_same_held_out_sweep_twice(replayed):
    held_out_per_fold = RECORDINGS // SETTINGS.folds
    for episode in replayed['episodes']:
        for movement in set(episode.movements):
            assert episode.movements.count(movement) <= held_out_per_fold
    assert {e.stop_reason for e in replayed['episodes']} <= {
        'decided', 'movement budget', 'no movement left'}


def test_every_policy_identifies_every_texture_of_every_fold_for_every_seed(replayed):
    episodes = replayed['episodes']
    assert len(episodes) == len(POLICIES) * SETTINGS.folds * len(TEXTURES) * SETTINGS.seeds
    for movement, held in replayed['held_out'].items():
        assert len(held['labels']) == len(TEXTURES) * RECORDINGS, movement


def test_active_never_starts_with_the_movement_that_tells_nothing(replayed):
    nothing = list(MOVEMENTS).index('tells_nothing')
    firsts = [e.movements[0] for e in replayed['episodes'] if e.policy == 'active']
    assert firsts and nothing not in firsts
    table = summary(replayed, SETTINGS)
    assert table['movements']['tells_all']['sweep_accuracy'] > 0.9
    assert table['movements']['tells_nothing']['sweep_accuracy'] < 0.7


def test_repeated_partitions_replay_each_and_the_first_is_the_unrepeated_replay(tmp_path,
                                                                               replayed):
    settings = replace(SETTINGS, policies=('active', 'random'), repeats=2)
    again = replay(movement_dataset(tmp_path), load_movements(movement_file(tmp_path)),
                   settings, progress=lambda line: None)
    episodes = again['episodes']
    assert len(episodes) == 2 * 2 * SETTINGS.folds * len(TEXTURES) * SETTINGS.seeds
    first = [(e.policy, e.fold, e.texture, e.seed, e.movements, e.leaders)
             for e in episodes if e.repeat == 0]
    assert first == [(e.policy, e.fold, e.texture, e.seed, e.movements, e.leaders)
                     for e in replayed['episodes'] if e.policy in settings.policies]
    assert len(again['tempering']) == 2 * SETTINGS.folds
    dealt = {repeat: [(e.fold, e.texture, e.seed, e.movements, e.leaders) for e in episodes
                      if e.repeat == repeat and e.policy == 'random'] for repeat in (0, 1)}
    assert dealt[0] != dealt[1]  # the second partition is dealt from its own shuffle
    table = summary(again, settings)
    assert table['settings']['repeats'] == 2 and table['episodes'] == len(episodes) // 2
    assert table['movements']['tells_all']['sweeps'] == len(TEXTURES) * RECORDINGS


def test_active_is_compared_with_every_other_policy_paired_at_equal_contact_time(replayed):
    against = summary(replayed, SETTINGS)['active_against']
    assert list(against) == [policy for policy in POLICIES if policy != 'active']
    for other, row in against.items():
        assert row['pairs'] == SETTINGS.folds * len(TEXTURES) * SETTINGS.seeds, other
        assert row['textures'] == len(TEXTURES)
        assert row['contact_s'][0] == pytest.approx(min(replayed['contact_s']))
        grid = np.array(row['contact_s'])
        assert row['difference'] == pytest.approx(  # textures hold as many pairs each
            accuracy_curves(replayed['episodes'], 'active', grid)[0]
            - accuracy_curves(replayed['episodes'], other, grid)[0])


def test_a_policy_right_where_another_is_wrong_differs_by_one_with_no_doubt():
    def episode(policy, texture, leader):
        return Episode(policy, 0, 0, texture, movements=[0, 0], leaders=[leader, leader],
                       contact_s=[2.5, 5.0])

    episodes = [episode('active', texture, texture) for texture in range(3)] + [
        episode('random', texture, (texture + 1) % 3) for texture in range(3)]
    grid = contact_grid(episodes, 2.5)
    assert grid.tolist() == [2.5, 5.0]
    right = paired_difference(episodes, 'active', 'random', grid)
    assert right['difference'] == right['low'] == right['high'] == [1.0, 1.0]
    assert paired_difference(episodes, 'active', 'active', grid)['difference'] == [0.0, 0.0]
    half = episodes[:3] + [episode('random', 0, 0), *episodes[4:]]  # one texture found by both
    mixed = paired_difference(half, 'active', 'random', grid)
    assert mixed['difference'] == pytest.approx([2 / 3, 2 / 3])
    assert mixed['low'][0] < 2 / 3 < mixed['high'][0] == 1.0


def test_the_goal_against_fixed_is_active_at_sixty_percent_of_its_median_against_its_final(
        replayed):
    table = summary(replayed, SETTINGS)
    goal = table['against_fixed']
    fixed = table['policies']['fixed']
    assert goal['pairs'] == SETTINGS.folds * len(TEXTURES) * SETTINGS.seeds
    assert goal['fixed_median_contact_s'] == fixed['median_contact_s']
    assert goal['goal_contact_s'] == pytest.approx(0.6 * fixed['median_contact_s'])
    assert goal['fixed_accuracy'] == pytest.approx(fixed['accuracy'])
    assert goal['accuracy'] == pytest.approx(accuracy_curves(
        replayed['episodes'], 'active', np.array([goal['goal_contact_s']]))[0][0])
    assert goal['margin'] == pytest.approx(goal['accuracy'] - goal['fixed_accuracy'] + 0.01)
    assert goal['low'] <= goal['margin'] <= goal['high']
    assert sum(goal['texture_pairs']) == goal['pairs']


def test_the_goal_against_fixed_is_met_by_deciding_as_right_in_well_under_its_time():
    def episode(policy, texture, leaders, seconds=2.5):
        return Episode(policy, 0, 0, texture, movements=[0] * len(leaders), leaders=leaders,
                       contact_s=(seconds * np.arange(1, len(leaders) + 1)).tolist())

    fixed = [episode('fixed', texture, [texture] * 5) for texture in range(3)]  # right, 12.5 s
    quick = against_fixed(fixed + [episode('active', t, [t]) for t in range(3)])
    assert quick['goal_contact_s'] == pytest.approx(7.5)
    assert quick['margin'] == quick['low'] == quick['high'] == pytest.approx(0.01)
    slow = against_fixed(fixed + [episode('active', t, [(t + 1) % 3] * 3 + [t]) for t in range(3)])
    assert slow['accuracy'] == 0.0 and slow['margin'] == pytest.approx(-0.99)
    assert against_fixed(fixed) == {} and against_fixed([]) == {}
    broken = [episode('fixed', 0, [0], seconds=math.nan), episode('active', 0, [0])]
    assert against_fixed(broken) == {}


def test_an_episode_cut_at_a_lower_threshold_is_the_one_a_replay_at_that_threshold_makes(
        tmp_path, replayed):
    lower = replace(SETTINGS, budget=replace(SETTINGS.budget, threshold=0.8))
    again = replay(movement_dataset(tmp_path), load_movements(movement_file(tmp_path)), lower,
                   progress=lambda line: None)
    for cut, whole in zip(again['episodes'], replayed['episodes'], strict=True):
        step = stop_step(whole.top_posterior, 0.8)
        assert (cut.movements, cut.leaders, cut.contact_s) == (
            whole.movements[:step + 1], whole.leaders[:step + 1], whole.contact_s[:step + 1])
    for policy in POLICIES:
        assert tradeoff(replayed['episodes'], policy, [0.8]) == tradeoff(
            again['episodes'], policy, [0.8])
        assert tradeoff(again['episodes'], policy, [0.8])[0]['accuracy'] == pytest.approx(
            summary(again, lower)['policies'][policy]['accuracy'])


def test_every_policy_pays_more_contact_for_a_higher_threshold_up_to_the_replays(replayed):
    trade = summary(replayed, SETTINGS)['tradeoff']
    assert list(trade['curves']) == list(POLICIES)
    for policy, curve in trade['curves'].items():
        assert [row['threshold'] for row in curve] == [0.5, 0.7, 0.8, 0.9, 0.95, 0.98, 0.99]
        seconds = [row['mean_contact_s'] for row in curve]
        assert seconds == sorted(seconds) and seconds[0] > 0, policy
        assert curve[-1]['accuracy'] == pytest.approx(
            summary(replayed, SETTINGS)['policies'][policy]['accuracy'])
    assert list(trade['at_equal_accuracy']) == [p for p in POLICIES if p != 'active']
    fixed = summary(replayed, SETTINGS)['policies']['fixed']
    goal = trade['fixed_goal']  # the goal against fixed, active stopped by a lower threshold
    assert goal['accuracy'] == pytest.approx(fixed['accuracy'] - 0.01)
    assert goal['fixed_median_contact_s'] == fixed['median_contact_s']
    assert goal['fixed_mean_contact_s'] == pytest.approx(np.mean(
        [e.contact_s[-1] for e in replayed['episodes'] if e.policy == 'fixed']))
    active = trade['curves']['active']
    reached = [row for row in active if row['accuracy'] >= goal['accuracy']]
    if reached and reached[0] is active[0]:  # even the lowest threshold reaches it
        assert goal['at_most'] and goal['active_mean_contact_s'] == active[0]['mean_contact_s']
    elif reached:
        assert not goal['at_most']
        assert active[0]['mean_contact_s'] < goal['active_mean_contact_s'] <= reached[0][
            'mean_contact_s']
    assert fixed_goal({'active': active}, 0.01) == {}


def test_the_seconds_for_an_accuracy_are_read_between_the_thresholds_that_first_reach_it():
    curve = [{'accuracy': 0.6, 'mean_contact_s': 10.0}, {'accuracy': 0.8, 'mean_contact_s': 20.0},
             {'accuracy': 0.7, 'mean_contact_s': 30.0}]
    assert seconds_for(curve, 0.7) == (pytest.approx(15.0), False)
    assert seconds_for(curve, 0.8) == (20.0, False)
    assert seconds_for(curve, 0.5) == (10.0, True)  # the lowest threshold: an upper bound
    assert seconds_for(curve, 0.9) == (None, False) == seconds_for([], 0.5)
    assert seconds_for(curve, math.nan) == (None, False)
    assert stop_step([], 0.5) == -1 and stop_step([0.4, 0.6, 0.9], 0.6) == 2
    assert tradeoff([], 'active', [0.5]) == []


def test_a_movement_ending_on_a_contact_time_within_rounding_has_finished_by_it():
    ends = np.cumsum([0.7, 0.3, 0.3, 0.1, 0.1])  # 1.5000000000000002
    assert right_by(ends.tolist(), [1, 1, 1, 1, 0], 0, np.array([1.4, 1.5])).tolist() == [
        False, True]
    moved = Episode('active', 0, 0, 0, leaders=[0], contact_s=[2.0])
    for broken in (math.nan, math.inf):  # wherever the broken episode sits
        for episodes in ([Episode('active', 0, 1, 0, leaders=[0], contact_s=[broken]), moved],
                         [moved, Episode('active', 0, 1, 0, leaders=[0], contact_s=[broken])]):
            assert contact_grid(episodes, 1.0).size == 0


def test_the_same_inputs_give_the_same_report(tmp_path, replayed):
    again = replay(movement_dataset(tmp_path), load_movements(movement_file(tmp_path)),
                   SETTINGS, progress=lambda line: None)
    first, second = summary(replayed, SETTINGS), summary(again, SETTINGS)
    for policy in POLICIES:
        for key in ('accuracy', 'median_contact_s', 'accuracy_after_k'):
            assert first['policies'][policy][key] == second['policies'][policy][key]


def test_the_report_holds_the_json_the_markdown_and_every_plot(tmp_path, replayed):
    table = write_report(tmp_path / 'report', replayed, SETTINGS)
    kept = json.loads((tmp_path / 'report' / 'identification.json').read_text())
    assert kept['episodes'] == SETTINGS.folds * len(TEXTURES) * SETTINGS.seeds
    for policy in POLICIES:
        row = kept['policies'][policy]
        assert set(row) >= {'accuracy', 'median_contact_s', 'p90_contact_s',
                            'median_movements', 'accuracy_after_k'}
        assert 0.0 <= row['accuracy'] <= 1.0
        assert list(row['first_three_movements']) == list(MOVEMENTS)
    assert table['policies'] == kept['policies']
    text = (tmp_path / 'report' / 'identification.md').read_text()
    assert '| active |' in text and '| tells_nothing |' in text
    assert 'What accuracy costs in contact time' in text and '| threshold | accuracy |' in text
    assert 'The goal against fixed read the same way' in text
    assert '| saved (s) [95 %] |' in text
    for name in PLOTS:
        assert (tmp_path / 'report' / name).stat().st_size > 1000, name



def test_without_active_there_is_no_plot_of_its_choices(tmp_path, replayed):
    settings = replace(SETTINGS, policies=('fixed', 'random'))
    without = {**replayed, 'episodes': [e for e in replayed['episodes']
                                        if e.policy in settings.policies]}
    write_report(tmp_path / 'report', without, settings)
    text = (tmp_path / 'report' / 'identification.md').read_text()
    assert not (tmp_path / 'report' / 'active_choices.png').exists()
    assert 'active_choices.png' not in text and '![time.png](time.png)' in text

def test_no_plan_fixed_in_advance_beats_the_best_plan_in_hindsight(tmp_path):
    settings = replace(SETTINGS, budget=Budget(threshold=1.0))  # never decides
    result = replay(movement_dataset(tmp_path), load_movements(movement_file(tmp_path)),
                    settings, progress=lambda line: None)
    table = write_report(tmp_path / 'report', result, settings)
    plans = table['best_plans']
    assert [plan['movements'] for plan in plans] == list(range(1, len(plans) + 1))
    assert len(plans) >= 3 and plans[0]['plan'] != {'tells_nothing': 1}
    for shorter, plan in zip([None, *plans], plans, strict=False):  # the best of at most k sweeps
        assert sum(plan['plan'].values()) <= plan['movements']
        assert shorter is None or plan['accuracy'] >= shorter['accuracy']
        for policy in ('fixed', 'round-robin'):  # plans themselves, stopped or not
            after = table['policies'][policy]['accuracy_after_k'][plan['movements'] - 1]
            assert after <= plan['accuracy'] + 1e-12, (policy, plan)
    assert '| best plan (hindsight) |' in (tmp_path / 'report' / 'identification.md').read_text()


def test_the_best_plan_is_found_by_enumeration_and_repeats_a_movement_only_as_pools_allow():
    def steps(*toward):  # one sweep's update per texture index it points at, +size
        return [np.eye(2)[texture] * size for texture, size in toward]

    def sums(terms):
        return np.cumsum([np.zeros(2), *terms], axis=0)

    result = {'movements': ['sharp', 'weak'], 'contact_s': [2.0, 3.0], 'classes': ['a', 'b'],
              'plan_terms': [  # sharp is right once then misleads; weak always says a
                  (0, 0, 0, [sums(steps((0, 2), (1, 3))), sums(steps((0, 1), (0, 1), (0, 1)))]),
                  (0, 1, 1, [sums(steps((1, 2), (0, 3))), sums(steps((0, 1), (0, 1)))])]}
    plans = best_plans(result)
    assert [plan['movements'] for plan in plans] == [1, 2, 3, 4]  # weak: 2 sweeps in every pool
    assert plans[0] == {'movements': 1, 'accuracy': 1.0, 'chosen_elsewhere': 1.0,
                        'contact_s': 2.0, 'plan': {'sharp': 1}}
    # At most k: sharp alone stays best (sharp + weak ties it, the shorter plan goes first;
    # every 3- and 4-sweep plan is right only half the time).
    assert plans[1:] == [{**plans[0], 'movements': k} for k in (2, 3, 4)]
    assert best_plans({**result, 'plan_terms': []}) == []


def test_a_plan_chosen_on_the_other_folds_loses_the_luck_of_choosing_on_its_own_sweeps():
    def sums(texture):  # one sweep pointing at `texture`
        return np.cumsum([np.zeros(2), np.eye(2)[texture]], axis=0)

    result = {'movements': ['left', 'right'], 'contact_s': [1.0, 1.0], 'classes': ['a', 'b'],
              'plan_terms': [(0, 0, 0, [sums(0), sums(1)]),  # fold 0: left is right
                             (0, 1, 1, [sums(0), sums(1)])]}  # fold 1: right is right
    single = best_plans(result)[0]
    assert single['accuracy'] == 0.5 and single['chosen_elsewhere'] == 0.0
    alone = {**result, 'plan_terms': result['plan_terms'][:1]}
    assert best_plans(alone)[0]['chosen_elsewhere'] is None  # one fold: nothing elsewhere
    # Another partition deals the same recordings again: its folds are not elsewhere.
    dealt_again = {**result, 'plan_terms': [*result['plan_terms'],
                                            (1, 0, 1, [sums(0), sums(1)]),
                                            (1, 1, 0, [sums(0), sums(1)])]}
    assert best_plans(dealt_again)[0]['chosen_elsewhere'] == 0.0


def test_recordings_without_a_movement_or_another_movement_file_are_refused(tmp_path):
    with pytest.raises(MovementDataError, match='name no movement'):
        replay(movement_dataset(tmp_path, named=False), load_movements(movement_file(tmp_path)),
               SETTINGS, progress=lambda line: None)
    other = tmp_path / 'other.yaml'
    other.write_text('window: 32\nmovements:\n  - {name: tells_all, speed: 0.02, press_depth: '
                     '0.002, edge_tilt: 0.5, direction: forward, contact_length: 0.04}\n'
                     '  - {name: sprint, speed: 0.04, press_depth: 0.002, edge_tilt: 0.5, '
                     'direction: forward, contact_length: 0.08}\n')
    with pytest.raises(MovementDataError, match='lacks: tells_nothing, tells_wood; no '
                                                'recording of sprint'):
        replay(movement_dataset(tmp_path), load_movements(other), SETTINGS,
               progress=lambda line: None)
    with pytest.raises(MovementDataError, match='--folds 5 with --inner-folds 3 need at least '
                                                r'5 recordings .* \(\w+ under tells_all: 4\): '
                                                'give --folds 4 --inner-folds 3'):
        replay(movement_dataset(tmp_path), load_movements(movement_file(tmp_path)),
               ReplaySettings(folds=5), progress=lambda line: None)



def test_a_movement_file_unlike_what_the_recordings_ran_at_is_refused(tmp_path):
    data = movement_dataset(tmp_path)
    for row in data.info['recordings']:  # as convert keeps them: speed as the file says
        row['sweep'] = {'speed_m_s': 0.0205, 'press_depth_m': 0.0021, 'edge_tilt_rad': 0.49}
    path = movement_file(tmp_path)
    assert checked_movements(data, load_movements(path))  # within the draws' spread
    path.write_text(path.read_text().replace('speed: 0.02', 'speed: 0.024', 1))
    with pytest.raises(MovementDataError, match=r'movement \w+: its \d+ recordings ran at '
                       r'speed_m_s 0.0205 \(median\), the movement file says 0.024'):
        replay(data, load_movements(path), SETTINGS, progress=lambda line: None)

def test_the_folds_are_checked_against_every_pair_before_any_training(tmp_path):
    data = movement_dataset(tmp_path)
    movements = load_movements(movement_file(tmp_path))
    wood = data.classes.index('wood')
    first = int(np.unique(data.trial[data.y == wood])[0])
    fitted = []
    with pytest.raises(MovementDataError, match=r'pair\(s\) have no recording \(wood under'):
        replay(data.select(~((data.y == wood) & (data.trial != first))), movements, SETTINGS,
               progress=fitted.append)
    assert not fitted  # refused up front, not after fitting the other movements
    assert recordings_needed(2, 2) == 4 and recordings_needed(3, 3) == 5


def test_the_command_writes_the_report_and_prints_each_policy(tmp_path, capsys):
    movement_dataset(tmp_path)  # writes tmp_path/data.npz and its sidecar
    assert main(['report', 'identification', str(tmp_path / 'data.npz'), '--out',
                 str(tmp_path / 'out'), '--movements', str(movement_file(tmp_path)),
                 '--folds', '2', '--inner-folds', '2', '--seeds', '2', '--model',
                 'extratrees', '--policies', 'active,fixed', '--budget-movements', '4',
                 '--repeats', '2']) == 0
    printed = capsys.readouterr().out
    assert 'active' in printed and 'fixed' in printed and 'random' not in printed
    assert 'repeat 2, fold 2/2: tells_all fitted' in printed
    kept = json.loads((tmp_path / 'out' / 'identification.json').read_text())
    assert list(kept['policies']) == ['active', 'fixed']
    assert kept['settings']['budget_movements'] == 4 and kept['settings']['repeats'] == 2
    assert list(kept['active_against']) == ['fixed']
    assert not kept['settings']['repeat_discount'] and set(kept['repeat_discount']) == {0.0}


def test_asked_for_the_discount_the_report_fits_one_per_fold(tmp_path):
    movement_dataset(tmp_path)
    assert main(['report', 'identification', str(tmp_path / 'data.npz'), '--out',
                 str(tmp_path / 'out'), '--movements', str(movement_file(tmp_path)),
                 '--folds', '2', '--inner-folds', '2', '--seeds', '1', '--model',
                 'extratrees', '--policies', 'active', '--repeat-discount']) == 0
    kept = json.loads((tmp_path / 'out' / 'identification.json').read_text())
    assert kept['settings']['repeat_discount'] and len(kept['repeat_discount']) == 2
    assert set(kept['repeat_discount']) <= set(DISCOUNTS)


def test_the_command_refuses_a_movement_file_of_another_window_as_train_does(tmp_path, capsys):
    movement_dataset(tmp_path)
    path = movement_file(tmp_path)
    path.write_text(path.read_text().replace(f'window: {WINDOW}', f'window: {2 * WINDOW}'))
    assert main(['report', 'identification', str(tmp_path / 'data.npz'), '--out',
                 str(tmp_path / 'out'), '--movements', str(path)]) == 1
    error = capsys.readouterr().err.strip()
    assert error.startswith(f'error: --movements {path} gives window {2 * WINDOW}, DATA ')
    assert f'holds {WINDOW}-sample windows' in error and '\n' not in error
    assert not (tmp_path / 'out').exists()


def test_a_deep_model_trains_as_train_would_and_a_training_cut_short_is_marked(tmp_path, capsys):
    movement_dataset(tmp_path)
    assert main(['report', 'identification', str(tmp_path / 'data.npz'), '--out',
                 str(tmp_path / 'out'), '--movements', str(movement_file(tmp_path)),
                 '--folds', '2', '--inner-folds', '2', '--seeds', '1', '--model', 'cnn_2',
                 '--profile', 'modern', '--epochs', '2', '--scaling', 'window',
                 '--early-stopping', '0', '--policies', 'active']) == 0
    printed = capsys.readouterr().out
    assert 'fold 1/2: tells_all fitted (1/3, ' in printed
    assert re.search(r'not converged: inner fold 1 \((still falling|stalled at chance)\)',
                     printed)
    kept = json.loads((tmp_path / 'out' / 'identification.json').read_text())
    assert {key: kept['settings'][key] for key in ('model', 'profile', 'epochs', 'scaling',
                                                   'early_stopping')} == {
        'model': 'cnn_2', 'profile': 'modern', 'epochs': 2, 'scaling': 'window',
        'early_stopping': 0}
    # two outer folds x (two inner folds + the final model), every one cut short at 2 epochs
    assert all(len(row['unconverged']) == 6 for row in kept['movements'].values())
    text = (tmp_path / 'out' / 'identification.md').read_text()
    assert 'cnn_2 (modern profile, at most 2 epochs, window scaling)' in text
    assert '| tells_all (not converged) |' in text and 'raise --epochs' in text
    assert 'tells_all: fold 1, inner fold 1: ' in text


def test_each_out_of_fold_sweep_names_the_inner_model_that_judged_it(tmp_path):
    dataset = movement_dataset(tmp_path)
    fitted = fit_movement('all', dataset, lambda: build_estimator(SETTINGS.training), folds=2)
    judged = cross_validate(dataset, lambda: build_estimator(SETTINGS.training), 'grouped',
                            folds=2)
    assert [set(judged.fold[dataset.trial == trial]) for trial in fitted.trials] == [
        {fold} for fold in fitted.folds]
    assert list(movement_evidence(fitted, 1.0).models) == list(fitted.folds)


def test_a_baseline_has_nothing_to_converge(replayed):
    assert all(not movement['unconverged'] for movement in replayed['held_out'].values())


def test_the_seconds_saved_at_equal_accuracy_are_the_tradeoffs_with_an_interval(replayed):
    trade = summary(replayed, SETTINGS)['tradeoff']
    assert list(trade['active_saving']) == [p for p in POLICIES if p != 'active']
    active = [e for e in replayed['episodes'] if e.policy == 'active']
    assert sum(trade['textures']['active']['episodes']) == len(active)
    for other, rows in trade['active_saving'].items():
        for row, plain in zip(rows, trade['at_equal_accuracy'][other], strict=True):
            assert row['accuracy'] == pytest.approx(plain['accuracy'])
            assert row['seconds'] == pytest.approx(plain['seconds'])
            assert row['never'] == (plain['other_seconds'] is None)
            if plain['other_seconds'] is not None:
                assert row['saving_s'] == pytest.approx(plain['other_seconds'] - plain['seconds'])
                assert row['at_most'] == plain['other_at_most']
            assert 0.0 <= row['never_share'] <= 1.0 and 0.0 <= row['at_most_share'] <= 1.0
            assert row['low'] is None or row['low'] <= row['high']
        thresholds = [row['threshold'] for row in rows]  # and averaged over them, one interval
        mean = mean_saving_interval(trade['textures']['active'], trade['textures'][other],
                                    thresholds)
        assert mean['saving_s'] == pytest.approx(np.mean([
            row['saving_s'] if row['saving_s'] is not None else np.nan for row in rows]),
            nan_ok=True)
        assert mean['low'] is None or mean['low'] <= mean['high']


def _deciding(policy: str, tops: list[float], right_from: int, textures: int = 3) -> list:
    """Ten episodes per texture: the leader right from step `right_from`, 2.5 s a step."""
    return [Episode(policy, 0, seed, texture, movements=[0] * len(tops), top_posterior=tops,
                    leaders=[texture if step >= right_from else texture + 1
                             for step in range(len(tops))],
                    contact_s=[2.5 * (step + 1) for step in range(len(tops))])
            for texture in range(textures) for seed in range(10)]


def test_a_policy_as_right_in_fewer_seconds_saves_them_in_every_resample_and_pooled():
    episodes = (_deciding('active', [0.6, 0.995], right_from=0)
                + _deciding('random', [0.6, 0.8, 0.9, 0.995], right_from=2))
    sums = {policy: texture_sums(episodes, policy, (0.5, 0.99), 3)
            for policy in ('active', 'random')}
    rows = saving_interval(sums['active'], sums['random'])
    # random is right only when cut at 0.99, after 10 s: active saves 7.5 s, then 5 s
    assert [row['saving_s'] for row in rows] == [pytest.approx(7.5), pytest.approx(5.0)]
    assert [(row['low'], row['high']) for row in rows] == [
        (pytest.approx(7.5), pytest.approx(7.5)), (pytest.approx(5.0), pytest.approx(5.0))]
    with_empty = {policy: texture_sums(episodes, policy, (0.5, 0.99), 4) for policy in sums}
    assert saving_interval(with_empty['active'], with_empty['random']) == rows  # left out
    pooled = {policy: pooled_sums([sums[policy], sums[policy]]) for policy in sums}
    assert len(pooled['active']['episodes']) == 6
    assert saving_interval(pooled['active'], pooled['random']) == rows
    with pytest.raises(ValueError, match='different thresholds'):
        pooled_sums([sums['active'], texture_sums(episodes, 'active', (0.5,), 3)])
    never = saving_interval(sums['active'], texture_sums(
        _deciding('random', [0.6, 0.995], right_from=5), 'random', (0.5, 0.99), 3))
    assert [row['never'] for row in never] == [True, True]  # random is never right:
    assert [row['never_share'] for row in never] == [1.0, 1.0]  # its longest contact stands in
    assert [row['saving_s'] for row in never] == [pytest.approx(5.0 - 2.5), pytest.approx(0.0)]
    assert [row['low'] for row in never] == [pytest.approx(5.0 - 2.5), pytest.approx(0.0)]
    assert saving_interval(texture_sums([], 'active', (0.5,), 3), sums['random']) == []
    assert saves_clearly(rows[0]) and not saves_clearly({**rows[0], 'at_most': True})
    assert not saves_clearly({**rows[0], 'at_most_share': 0.5})  # the low end on upper bounds
    assert leans_on_upper_bounds({**rows[0], 'at_most_share': 0.03})  # past the 2.5 % tail
    assert not leans_on_upper_bounds({**rows[0], 'at_most_share': 0.025})
    assert saves_clearly(never[0]) and not saves_clearly(never[1])  # lower bounds: 2.5, 0


def test_one_interval_answers_for_a_stretch_of_thresholds_as_the_mean_of_their_savings():
    episodes = (_deciding('active', [0.6, 0.995], right_from=0)
                + _deciding('random', [0.6, 0.8, 0.9, 0.995], right_from=2))
    sums = {policy: texture_sums(episodes, policy, (0.5, 0.99), 3)
            for policy in ('active', 'random')}
    both = mean_saving_interval(sums['active'], sums['random'], (0.5, 0.99))
    assert both['saving_s'] == pytest.approx((7.5 + 5.0) / 2)  # saving_interval's, averaged
    assert both['low'] == pytest.approx(6.25) == pytest.approx(both['high'])
    assert both['thresholds'] == [0.5, 0.99] and saves_clearly(both)
    assert mean_saving_interval(sums['active'], sums['random'], (0.99,))['saving_s'] == (
        pytest.approx(5.0))
    never = mean_saving_interval(sums['active'], texture_sums(
        _deciding('random', [0.6, 0.995], right_from=5), 'random', (0.5, 0.99), 3), (0.5, 0.99))
    assert never['never'] and never['never_share'] == 1.0  # a lower bound, as per threshold
    assert never['saving_s'] == pytest.approx((2.5 + 0.0) / 2)
    at_once = mean_saving_interval(sums['active'], texture_sums(  # random right at its first
        _deciding('random', [0.6, 0.995], right_from=0), 'random', (0.5, 0.99), 3), (0.5, 0.99))
    assert at_once['at_most'] and at_once['at_most_share'] == 1.0 and not saves_clearly(at_once)
    with pytest.raises(ValueError, match=r'not cut at \[0.7\]'):
        mean_saving_interval(sums['active'], sums['random'], (0.5, 0.7))
    with pytest.raises(ValueError, match='twice'):  # one threshold would weigh double
        mean_saving_interval(sums['active'], sums['random'], (0.5, 0.5, 0.99))
    assert mean_saving_interval(sums['active'], sums['random'], ()) == {}
    assert mean_saving_interval(texture_sums([], 'active', (0.5,), 3), sums['random'],
                                (0.5,)) == {}


def test_the_goal_against_fixed_on_the_tradeoff_is_a_share_of_fixeds_contact_with_an_interval():
    episodes = (_deciding('active', [0.6, 0.995], right_from=1)
                + _deciding('fixed', [0.6, 0.8, 0.9, 0.995], right_from=0))
    sums = {policy: texture_sums(episodes, policy, (0.5, 0.99), 3)
            for policy in ('active', 'fixed')}
    # fixed is right after 10 s at 0.99; active reaches 99 % of that between its 2.5 and 5 s
    goal = fixed_goal_interval(sums['active'], sums['fixed'], 0.01)
    assert goal['seconds'] == pytest.approx(2.5 + 0.99 * 2.5)
    assert goal['share'] == pytest.approx((2.5 + 0.99 * 2.5) / 10.0)
    assert goal['low'] == pytest.approx(goal['share']) == pytest.approx(goal['high'])
    assert goal['seconds_low'] == pytest.approx(goal['seconds']) == pytest.approx(
        goal['seconds_high'])
    assert not goal['never'] and goal['never_share'] == 0.0
    never = fixed_goal_interval(texture_sums(  # a policy never right never gets there
        _deciding('active', [0.6, 0.995], right_from=5), 'active', (0.5, 0.99), 3),
        sums['fixed'], 0.01)
    assert never['share'] is None is never['seconds'] and never['seconds_high'] is None
    assert never['never'] and never['never_share'] == 1.0
    assert fixed_goal_interval(texture_sums([], 'active', (0.5,), 3), sums['fixed'], 0.01) == {}
