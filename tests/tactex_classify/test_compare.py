# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex compare`: cells kept whole, resumed without recomputing, summarised as a table."""

import json
import math
import os
from pathlib import Path
import re
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from tactex_classify.data.dataset import Dataset
from tactex_classify.evaluation.grid_report import (
    cell_unconverged_because,
    cost_front,
    fold_notes,
    pareto_front,
    summarise,
    table,
    write_report,
)
from tactex_classify.evaluation.model_grid import (
    Cell,
    grid_cells,
    GridError,
    GridSettings,
    GridStore,
    run_cell,
)
from tactex_classify.training.convergence import stalled_at_chance, still_falling
from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig

TACTEX = Path(sys.executable).parent / 'tactex'


def toy(window: int = 64, classes: int = 3, recordings: int = 4, per: int = 6) -> Dataset:
    """Separable windows: class k is noise shifted by k / 2."""
    rng = np.random.default_rng(window)
    count = classes * recordings * per
    y = np.repeat(np.arange(classes), recordings * per)
    X = (rng.normal(size=(count, window, 10)) + 0.5 * y[:, None, None]).astype(np.float32)
    return Dataset(X, y, np.repeat(np.arange(classes * recordings), per),
                   np.tile(np.arange(per, dtype=float), classes * recordings),
                   [f'texture{k}' for k in range(classes)],
                   {'sampling_rate_hz': 100.0, 'hop': window // 2})


def test_grid_has_every_cell_once_and_each_fold_round_covers_every_model():
    cells = grid_cells(['cnn_1', 'extratrees'], [128, 256], seeds=2, folds=3)
    assert len(cells) == len(set(cells)) == 2 * 2 * 2 * 3 * 2
    first_round = cells[:8]
    assert {(c.seed, c.fold) for c in first_round} == {(0, 1)}
    assert {(c.model, c.window, c.scheme) for c in first_round} == {
        (m, w, s) for m in ('cnn_1', 'extratrees') for w in (128, 256)
        for s in ('grouped', 'stratified')}


def test_a_saved_cell_loads_back_and_a_torn_or_foreign_file_counts_as_not_run(tmp_path):
    store = GridStore(tmp_path / 'grid')
    store.open(GridSettings(folds=2, epochs=1), {64: toy()}, {64: 'toy'})
    cell = Cell(0, 1, 'grouped', 64, 'extratrees')
    assert store.load(cell) is None
    store.save(cell, {'cell': {'seed': 0, 'fold': 1, 'scheme': 'grouped', 'window': 64,
                               'model': 'extratrees'}, 'accuracy': 0.5})
    assert store.load(cell)['accuracy'] == 0.5
    path = tmp_path / 'grid' / 'cells' / cell.relative_path
    path.write_text(path.read_text()[:20])  # torn
    assert store.load(cell) is None
    other = Cell(0, 2, 'grouped', 64, 'extratrees')
    path.write_text(json.dumps({'cell': {'seed': 0, 'fold': 2, 'scheme': 'grouped',
                                         'window': 64, 'model': 'extratrees'}}))
    assert store.load(cell) is None and store.load(other) is None
    assert not list((tmp_path / 'grid').rglob('*.partial'))


def test_a_grid_resumes_only_with_its_settings_and_its_data(tmp_path):
    store = GridStore(tmp_path / 'grid')
    store.open(GridSettings(folds=2, epochs=3), {64: toy()}, {64: 'toy'})
    store.open(GridSettings(folds=2, epochs=3), {64: toy(), 32: toy(32)}, {64: 'toy', 32: 't'})
    assert set(store.manifest()['data']) == {'64', '32'}
    with pytest.raises(GridError, match=r'epochs 3 \(now 5\); give the same settings'):
        store.open(GridSettings(folds=2, epochs=5), {64: toy()}, {64: 'toy'})
    changed = toy()
    changed.X[0, 0, 0] += 1.0
    assert changed.digest() != toy().digest()
    with pytest.raises(GridError, match='other data for window 64'):
        store.open(GridSettings(folds=2, epochs=3), {64: changed}, {64: 'toy'})
    (tmp_path / 'other').mkdir()
    (tmp_path / 'other' / 'notes.txt').write_text('mine')
    with pytest.raises(GridError, match='holds files but no grid.json'):
        GridStore(tmp_path / 'other').open(GridSettings(), {64: toy()}, {64: 'toy'})


def test_a_grid_begun_before_a_setting_existed_resumes_with_its_default(tmp_path):
    store = GridStore(tmp_path / 'grid')
    store.open(GridSettings(folds=2, epochs=3), {64: toy()}, {64: 'toy'})
    manifest = json.loads(store.manifest_path.read_text())
    del manifest['settings']['profile']  # as written before training profiles
    store.manifest_path.write_text(json.dumps(manifest))
    store.open(GridSettings(folds=2, epochs=3), {64: toy()}, {64: 'toy'})
    with pytest.raises(GridError, match="profile 'original' \\(now 'modern'\\)"):
        store.open(GridSettings(folds=2, epochs=3, profile='modern'), {64: toy()},
                   {64: 'toy'})


def test_a_cell_trains_a_deep_model_with_the_grids_profile():
    cell = Cell(0, 1, 'grouped', 64, 'cnn_2')
    result = run_cell({64: toy()}, cell, GridSettings(folds=2, epochs=2, profile='modern'),
                      1, 'cpu')
    assert result['config']['profile'] == 'modern'
    assert result['config']['optimizer'] == 'adamw'


class Stopped(Exception):
    """A kill right after a kept epoch."""


def test_a_deep_cell_stopped_part_way_resumes_from_its_last_kept_epoch(tmp_path, monkeypatch):
    import torch

    from tactex_classify.training.training_state import TrainingState
    cell, settings = Cell(0, 1, 'grouped', 64, 'cnn_2'), GridSettings(folds=2, epochs=4)
    straight = run_cell({64: toy()}, cell, settings, 1, 'cpu')
    save = TrainingState.save

    def save_then_stop(keeper, state):
        save(keeper, state)
        if state['epoch'] == 2:
            raise Stopped
    monkeypatch.setattr(TrainingState, 'due', lambda keeper: True)
    monkeypatch.setattr(TrainingState, 'save', save_then_stop)
    with pytest.raises(Stopped):
        run_cell({64: toy()}, cell, settings, 1, 'cpu', tmp_path)
    monkeypatch.undo()
    kept = tmp_path / 'cnn_2' / 'w64' / 'seed0-grouped-fold1.pt'
    trained_before = torch.load(kept, weights_only=True)['seconds']
    resumed = run_cell({64: toy()}, cell, settings, 1, 'cpu', tmp_path)
    assert resumed['train_losses'] == straight['train_losses']  # epochs 3-4 as if never stopped
    assert resumed['y_pred'] == straight['y_pred']
    assert resumed['train_s'] > trained_before > 0
    assert resumed['notes'] == []
    assert torch.load(kept, weights_only=True)['finished']  # until the grid saves the result


def test_a_cell_says_why_its_kept_state_was_set_aside(tmp_path):
    cell, settings = Cell(0, 1, 'grouped', 64, 'cnn_2'), GridSettings(folds=2, epochs=2)
    kept = tmp_path / cell.state_name
    kept.parent.mkdir(parents=True)
    kept.write_bytes(b'torn')
    result = run_cell({64: toy()}, cell, settings, 1, 'cpu', tmp_path)
    assert len(result['notes']) == 1 and 'is not a training state' in result['notes'][0]


@pytest.mark.parametrize('model', ['extratrees', 'cnn_2'])
def test_a_cell_scores_its_own_test_fold_and_reports_its_cost(model):
    dataset = toy()
    cell = Cell(0, 2, 'grouped', 64, model)
    result = run_cell({64: dataset}, cell, GridSettings(folds=2, epochs=2), 1, 'cpu')
    assert result['cell'] == {'seed': 0, 'fold': 2, 'scheme': 'grouped', 'window': 64,
                              'model': model}
    assert result['test_windows'] == len(result['y_pred']) == len(result['y_true'])
    assert result['train_windows'] + result['test_windows'] == len(dataset.y)
    hits = np.mean(np.array(result['y_true']) == np.array(result['y_pred']))
    assert result['accuracy'] == pytest.approx(hits)
    assert result['train_s'] > 0 and result['latency_ms'] > 0
    deep = model != 'extratrees'
    assert (result['epochs_run'] == 2) if deep else result['epochs_run'] is None
    assert (result['train_accuracy'] is not None) == deep


def test_a_class_with_one_recording_is_named_where_a_fold_trained_without_it(tmp_path):
    dataset = toy(recordings=4)
    alone = dataset.trial == 0  # texture0 keeps only its first recording
    keep = ~(dataset.y == 0) | alone
    dataset = Dataset(dataset.X[keep], dataset.y[keep], dataset.trial[keep], dataset.t0[keep],
                      dataset.classes, dataset.info)
    results = [run_cell({64: dataset}, Cell(0, fold, 'grouped', 64, 'extratrees'),
                        GridSettings(folds=2), 1, 'cpu') for fold in (1, 2)]
    missing = [result['absent_from_training'] for result in results]
    assert sorted(missing) == [[], ['texture0']]  # the fold that held it out
    fold = 1 + missing.index(['texture0'])
    assert fold_notes(results + results) == [f'window 64, grouped fold {fold}, seed 0: '
                                             'texture0']  # every model shares the folds
    manifest = {'settings': {'folds': 2, 'epochs': 4, 'early_stopping': 0},
                'data': {'64': {'classes': dataset.classes, 'windows': len(dataset.y),
                                'recordings': 9}}}
    report = write_report(tmp_path, results, manifest).read_text(encoding='utf-8')
    assert "absent from a fold's training windows" in report
    assert f'- window 64, grouped fold {fold}, seed 0: texture0' in report


def test_early_stopping_reports_the_chosen_epoch():
    settings = GridSettings(folds=2, epochs=6, early_stopping=1, validation_fraction=0.25)
    result = run_cell({64: toy()}, Cell(0, 1, 'grouped', 64, 'cnn_2'), settings, 1, 'cpu')
    assert 1 <= result['chosen_epoch'] <= result['epochs_run'] <= 6


def fake_result(model, scheme, fold, accuracy, train_s=10.0):
    right = int(round(10 * accuracy))
    return {'cell': {'seed': 0, 'fold': fold, 'scheme': scheme, 'window': 64, 'model': model},
            'accuracy': accuracy, 'macro_precision': accuracy, 'macro_recall': accuracy,
            'macro_f1': accuracy, 'train_accuracy': 0.9, 'train_s': train_s,
            'latency_ms': 1.0, 'throughput_ms': 0.1, 'epochs_per_s': 1.0, 'chosen_epoch': 4,
            'y_true': [0] * 10, 'y_pred': [0] * right + [1] * (10 - right)}


def test_the_table_gives_mean_and_sd_over_cells_best_honest_model_first(tmp_path):
    results = [fake_result('cnn_1', 'grouped', 1, 0.6), fake_result('cnn_1', 'grouped', 2, 0.8),
               fake_result('cnn_1', 'stratified', 1, 0.9),
               fake_result('cnn_3', 'grouped', 1, 0.9), fake_result('cnn_3', 'grouped', 2, 0.9)]
    rows = summarise(results, {64: ['a', 'b']})
    assert [row['model'] for row in rows] == ['cnn_3', 'cnn_1']
    cnn_1 = rows[1]['schemes']['grouped']
    assert cnn_1['accuracy']['mean'] == pytest.approx(0.7)
    assert cnn_1['accuracy']['sd'] == pytest.approx(np.std([0.6, 0.8], ddof=1))
    assert cnn_1['pooled']['accuracy'] == pytest.approx(0.7)  # 14 of 20 windows
    text = table(rows, expected_cells=4)
    assert '| 64 | cnn_1 | 4 | 90.0 ± 0.0 | 70.0 ± 14.1 |' in text
    assert text.splitlines()[2].startswith('| 64 | cnn_3 |') and '| 3 of 4 |' in text
    manifest = {'settings': {'folds': 2, 'epochs': 4, 'early_stopping': 0},
                'data': {'64': {'classes': ['a', 'b'], 'windows': 20, 'recordings': 4}}}
    write_report(tmp_path, results, manifest)
    for name in ('report.md', 'summary.json', 'accuracy.png', 'cost.png'):
        assert (tmp_path / name).stat().st_size > 0


def trained(result: dict, losses: list[float], epochs: int) -> dict:
    """A fake deep cell: its training losses per epoch, of at most `epochs`."""
    return {**result, 'train_losses': losses, 'config': {'epochs': epochs}}


def test_a_row_whose_loss_was_still_falling_is_marked_and_ranked_after_converged_ones():
    falling_losses = [0.6 - 0.02 * epoch for epoch in range(10)]  # all 10 epochs, falling
    falling = [trained(fake_result('cnn_1', 'grouped', fold, 0.95),
                       falling_losses if fold == 2 else [0.3] * 10, epochs=10)
               for fold in (1, 2)]
    converged = [trained(fake_result('cnn_3', 'grouped', fold, 0.6), [0.3] * 10, epochs=10)
                 for fold in (1, 2)]
    rows = summarise(falling + converged, {64: ['a', 'b']})
    assert [(row['model'], row['not_converged']) for row in rows] == [
        ('cnn_3', False), ('cnn_1', True)]
    assert '| 64 | cnn_1 (not converged) |' in table(rows)
    front = cost_front(rows, 'train_s')  # cnn_1 is more accurate, yet never on the front
    assert [row['model'] for row in front] == ['cnn_3']


def test_a_row_whose_training_never_left_chance_is_not_converged_and_off_the_front(tmp_path):
    chance = math.log(2)  # the uniform prediction's loss over the two classes
    stalled = [trained(fake_result('bilstm_2', 'grouped', fold, 0.5, train_s=1.0),
                       [1.1 * chance] + [chance] * 30, epochs=100)  # early stopping ended it
               for fold in (1, 2)]
    learned = [trained(fake_result('cnn_3', 'grouped', fold, 0.45, train_s=5.0),
                       [chance] + [0.5 * chance] * 30, epochs=100) for fold in (1, 2)]
    rows = summarise(stalled + learned, {64: ['a', 'b']})
    assert [(row['model'], row['not_converged']) for row in rows] == [
        ('cnn_3', False), ('bilstm_2', True)]  # ranked after, though cheaper and better
    assert [row['model'] for row in cost_front(rows, 'train_s')] == ['cnn_3']
    assert [cell_unconverged_because(cell, 2) for cell in (stalled[0], learned[0])] == [
        'stalled at chance', None]
    manifest = {'settings': {'folds': 2, 'epochs': 31, 'early_stopping': 30},
                'data': {'64': {'classes': ['a', 'b'], 'windows': 20, 'recordings': 4}}}
    report = write_report(tmp_path, stalled + learned, manifest).read_text(encoding='utf-8')
    assert '| 64 | bilstm_2 (not converged) |' in report
    assert 'never fell below chance' in report  # the report says what the mark means


def test_a_training_that_never_left_the_uniform_predictions_loss_stalled_at_chance():
    chance = math.log(12)
    assert stalled_at_chance([2.8, 2.6] + [chance] * 30, 12)
    assert not stalled_at_chance([2.8, 2.6, 0.9 * chance], 12)
    assert not stalled_at_chance([], 12) and not stalled_at_chance([0.5, 0.4], 1)
    assert stalled_at_chance([math.nan, math.inf], 12)  # no finite loss: learned nothing
    assert not stalled_at_chance([math.nan, 1.0], 12)
    import torch  # the premise: the uniform prediction's loss is ln(classes) for any target
    uniform, labels = torch.zeros(4, 12), torch.tensor([0, 3, 7, 11])
    for smoothing in (0.0, 0.1, 0.5):
        loss = torch.nn.CrossEntropyLoss(label_smoothing=smoothing)(uniform, labels)
        assert float(loss) == pytest.approx(chance)
    mixed = torch.softmax(torch.randn(4, 12), dim=1)  # a mixup batch's blended targets
    assert float(torch.nn.functional.cross_entropy(uniform, mixed)) == pytest.approx(chance)


def test_a_training_knows_whether_its_loss_was_still_falling():
    assert still_falling([1.0] * 5 + [0.5] * 5)
    assert not still_falling([0.5] * 10) and not still_falling([0.6] * 5 + [0.595] * 5)
    assert still_falling([0.5] * 3)  # too short to tell
    data = toy()
    settings = TrainingConfig('cnn_2', epochs=3, seed=1)
    assert DeepClassifier(settings).fit(data.X, data.y, data.classes).still_falling_


def cell_files(folder: Path) -> dict[str, bytes]:
    return {str(path.relative_to(folder)): path.read_bytes()
            for path in sorted((folder / 'cells').rglob('*.json'))}


@pytest.mark.slow
def test_a_grid_killed_midway_resumes_without_recomputing_finished_cells(tmp_path):
    """2 models x 1 window x 2 folds (x 2 schemes) on a local Ray instance of one core."""
    toy().save(tmp_path / 'toy.npz')
    out = tmp_path / 'grid'
    argv = [str(TACTEX), 'compare', str(tmp_path / 'toy.npz'), '--models', 'cnn_2,extratrees',
            '--folds', '2', '--epochs', '10', '--cpus', '1', '--out', str(out)]
    first = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             stdin=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.monotonic() + 240
        while not cell_files(out) and first.poll() is None and time.monotonic() < deadline:
            time.sleep(0.1)
        assert first.poll() is None, first.stdout.read().decode()
        os.kill(first.pid, signal.SIGKILL)
        first.wait(timeout=30)
    finally:
        try:
            os.killpg(first.pid, signal.SIGTERM)  # Ray helpers of the killed driver
        except ProcessLookupError:
            pass
    kept = cell_files(out)
    assert 0 < len(kept) < 8, first.stdout.read().decode()
    second = subprocess.run(argv, capture_output=True, text=True, timeout=300,
                            stdin=subprocess.DEVNULL)
    assert second.returncode == 0, second.stdout + second.stderr
    assert f'{len(kept)} of 8 cells finished before; {8 - len(kept)} to run' in second.stdout
    assert second.stdout.count('] [') == 8 - len(kept)  # one progress line per cell run
    final = cell_files(out)
    assert len(final) == 8
    assert {name: final[name] for name in kept} == kept  # never recomputed
    report = (out / 'report.md').read_text()
    # 10 epochs on the toy set may end with the loss still falling: the row says so.
    assert re.search(r'\| cnn_2( \(not converged\))? \|', report)
    assert '| extratrees (baseline) |' in report
    assert (out / 'accuracy.png').is_file() and (out / 'cost.png').is_file()
    assert not [path for path in (out / 'training_state').rglob('*') if path.is_file()]


def test_each_deep_row_gives_its_paired_difference_to_the_best_baseline_with_a_95_interval():
    results = [fake_result('cnn_3', 'grouped', fold, accuracy)
               for fold, accuracy in ((1, 0.9), (2, 0.8), (3, 0.7))]
    results += [fake_result('minirocket', 'grouped', fold, accuracy)
                for fold, accuracy in ((1, 0.8), (2, 0.75), (3, 0.5))]
    results += [fake_result('extratrees', 'grouped', fold, 0.4) for fold in (1, 2, 3)]
    rows = {row['model']: row for row in summarise(results, {64: ['a', 'b']})}
    versus = rows['cnn_3']['vs_best_baseline']
    differences = [0.1, 0.05, 0.2]  # fold by fold against minirocket, the best baseline
    half = 4.302653 * np.std(differences, ddof=1) / np.sqrt(3)  # t(0.975, 2 dof)
    assert versus['baseline'] == 'minirocket' and versus['n'] == 3
    assert versus['mean'] == pytest.approx(np.mean(differences))
    assert (versus['low'], versus['high']) == pytest.approx(
        (np.mean(differences) - half, np.mean(differences) + half), rel=1e-5)
    assert 'vs_best_baseline' not in rows['minirocket']
    assert '| +11.7 [-7.3, +30.6] vs minirocket |' in table(list(rows.values()))


def test_the_interval_of_few_pairs_stays_within_what_two_accuracies_can_differ_by():
    results = [fake_result('cnn_3', 'grouped', fold, accuracy)
               for fold, accuracy in ((1, 0.05), (2, 0.0))]
    results += [fake_result('minirocket', 'grouped', fold, 1.0) for fold in (1, 2)]
    rows = {row['model']: row for row in summarise(results, {64: ['a', 'b']})}
    versus = rows['cnn_3']['vs_best_baseline']  # t(0.975, 1 dof) = 12.7 reached -129
    assert (versus['low'], versus['high']) == pytest.approx((-1.0, -0.6573), abs=1e-4)
    assert '| -97.5 [-100.0, -65.7] vs minirocket |' in table(list(rows.values()))


def test_a_single_pair_gives_a_difference_but_no_interval():
    results = [fake_result('cnn_3', 'grouped', 1, 0.9),
               fake_result('minirocket', 'grouped', 1, 0.6),
               fake_result('minirocket', 'grouped', 2, 0.7)]
    rows = {row['model']: row for row in summarise(results, {64: ['a', 'b']})}
    versus = rows['cnn_3']['vs_best_baseline']
    assert versus['n'] == 1 and versus['mean'] == pytest.approx(0.3)
    assert versus['low'] is None and versus['high'] is None
    assert '| +30.0 (one pair, no interval) vs minirocket |' in table(list(rows.values()))


def test_the_pareto_front_keeps_the_points_no_other_beats_in_cost_and_accuracy():
    points = [(10.0, 80.0), (1.0, 50.0), (5.0, 40.0), (2.0, 70.0), (20.0, 75.0), (1.0, 45.0)]
    assert pareto_front(points) == [(1.0, 50.0), (2.0, 70.0), (10.0, 80.0)]
    assert pareto_front([]) == []


@pytest.mark.parametrize('points, front', [
    ([(0.5, math.nan), (1.0, 60.0), (2.0, 70.0)], [(1.0, 60.0), (2.0, 70.0)]),
    ([(math.nan, 50.0), (1.0, 60.0), (2.0, 70.0), (0.5, 40.0)],
     [(0.5, 40.0), (1.0, 60.0), (2.0, 70.0)]),
    ([(math.inf, 99.0), (1.0, 60.0)], [(1.0, 60.0)]),
    ([(10**400, 99.0), (1.0, 60.0)], [(1.0, 60.0)]),  # a hand-edited summary's number
    ([(1.0, 60.0), (1.0, 60.0), (2.0, 60.0)], [(1.0, 60.0), (1.0, 60.0)]),
], ids=['nan-accuracy', 'nan-cost', 'inf-cost', 'huge-cost', 'ties'])
def test_points_that_cannot_be_compared_stay_off_the_front_and_ties_share_it(points, front):
    assert pareto_front(points) == front


def test_a_grid_run_grouped_only_has_no_leaky_columns_nor_words(tmp_path):
    results = [fake_result('cnn_1', 'grouped', fold, 0.7) for fold in (1, 2)]
    text = table(summarise(results, {64: ['a', 'b']}))
    assert 'honest' in text and 'leaky' not in text
    manifest = {'settings': {'folds': 2, 'epochs': 4, 'early_stopping': 0},
                'data': {'64': {'classes': ['a', 'b'], 'windows': 20, 'recordings': 4}}}
    report = write_report(tmp_path, results, manifest).read_text(encoding='utf-8')
    assert 'grouped by recording (honest);' in report and 'leaky' not in report


def test_a_grid_run_stratified_only_draws_no_cost_plot_and_claims_nothing_honest(tmp_path):
    results = [fake_result('cnn_1', 'stratified', fold, 0.9) for fold in (1, 2)]
    results += [fake_result('extratrees', 'stratified', fold, 0.8) for fold in (1, 2)]
    manifest = {'settings': {'folds': 2, 'epochs': 4, 'early_stopping': 0},
                'data': {'64': {'classes': ['a', 'b'], 'windows': 20, 'recordings': 4}}}
    report = write_report(tmp_path, results, manifest).read_text(encoding='utf-8')
    assert 'honest' not in report and 'No cost plot' in report
    assert not (tmp_path / 'cost.png').exists() and (tmp_path / 'accuracy.png').is_file()
    assert '| 10 | ' in report  # training seconds from the scheme that ran
    from tactex_classify.evaluation.grid_report import plot_grid  # (what `tactex plot` lists)
    rows = json.loads((tmp_path / 'summary.json').read_text())['rows']
    assert plot_grid(tmp_path, rows) == [tmp_path / 'accuracy.png']


def test_a_difference_that_is_not_a_number_gets_no_interval_either():
    from tactex_classify.evaluation.grid_report import paired_difference
    difference = paired_difference({1: float('nan'), 2: 0.5}, {1: 0.4, 2: 0.4})
    assert all(math.isnan(difference[key]) for key in ('mean', 'low', 'high'))


def test_datasets_at_several_windows_must_be_one_set_of_recordings():
    from tactex.commands.compare import check_one_source
    from tactex.errors import CommandError
    short, long = toy(window=32), toy(window=64)
    fewer = long.select(long.trial != 0)  # a recording too short for the longer window
    check_one_source([(short, 'w32.npz'), (fewer, 'w64.npz')])
    check_one_source([(short, 'w32.npz'), (toy(window=64, classes=2), 'w64.npz')])  # lost one
    rate = short.info['sampling_rate_hz']
    check_one_source([(short, 'w32.npz'), (Dataset(long.X, long.y, long.trial, long.t0,
                      long.classes, {**long.info, 'sampling_rate_hz': rate * 1.01}), 'w64')])
    others = Dataset(long.X, long.y, long.trial + 100, long.t0, long.classes, long.info)
    renamed = Dataset(long.X, long.y, long.trial, long.t0, ['a', 'b', 'c'], long.info)
    for dataset, differs in ((others, 'recordings'), (renamed, 'classes, recordings'),
                             (Dataset(long.X, long.y, long.trial, long.t0, long.classes,
                                      {**long.info, 'sampling_rate_hz': 1.2 * rate}), 'rate')):
        with pytest.raises(CommandError, match=f'w64.npz and w32.npz differ in {differs}'):
            check_one_source([(short, 'w32.npz'), (dataset, 'w64.npz')])
