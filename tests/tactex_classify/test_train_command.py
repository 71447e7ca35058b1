# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex train`: a run folder with both schemes side by side, plots, metrics, a checkpoint."""

import json
import math
import re

import numpy as np
import pytest
from support.movement_data import movement_dataset, movement_file
from support.toy_windows import toy

from tactex.cli import main
from tactex_classify.evaluation.cross_validation import CrossValidation
from tactex_classify.evaluation.training_report import convergence_notes
from tactex_classify.training.deep_classifier import DeepClassifier


def test_train_writes_the_report_with_both_schemes(tmp_path, capsys):
    data_path = toy().save(tmp_path / 'toy.npz')
    assert main(['train', str(data_path), '--model', 'extratrees', '--folds', '4',
                 '--out', str(tmp_path / 'run')]) == 0
    run = tmp_path / 'run'
    for name in ('report.md', 'metrics.json', 'confusion.png', 'learning_curves.png',
                 'accuracy_vs_time.png'):
        assert (run / name).stat().st_size > 0, name
    report = (run / 'report.md').read_text()
    assert 'grouped by recording (honest)' in report and 'stratified windows (leaky)' in report
    assert str(data_path) in report  # every result names its data
    metrics = json.loads((run / 'metrics.json').read_text())
    assert set(metrics['schemes']) == {'grouped', 'stratified'}
    assert metrics['schemes']['grouped']['sequence'][0]['windows'] == 1
    out = capsys.readouterr().out
    assert 'report:' in out
    assert out.count('accuracy') >= 8 + 2  # each fold of both schemes, then each scheme
    assert re.search(r'grouped by recording \(honest\): accuracy [\d.]+ % over all windows; '
                     r'per fold [\d.]+ / [\d.]+ / [\d.]+ / [\d.]+ \(mean [\d.]+ ± [\d.]+ %\)',
                     out)
    assert re.search(r'most confused: \w+ as \w+ \(\d+\)', out) or 'accuracy 100.0 %' in out


def test_train_keeps_a_deployable_checkpoint(tmp_path, capsys):
    data = toy()
    data_path = data.save(tmp_path / 'toy.npz')
    assert main(['train', str(data_path), '--model', 'cnn_3', '--epochs', '2', '--folds', '4',
                 '--cv', 'grouped', '--out', str(tmp_path / 'run')]) == 0
    model = DeepClassifier.load(tmp_path / 'run' / 'model')
    assert model.classes_ == data.classes
    from tactex_classify.models.checkpoint import read_checkpoint
    assert read_checkpoint(tmp_path / 'run' / 'model').trained_on == data.digest()
    assert model.predict_proba(data.X[:2]).shape == (2, 3)
    curves = json.loads((tmp_path / 'run' / 'metrics.json').read_text())
    assert len(curves['schemes']['grouped']['histories'][0]) == 2
    # Two epochs of a deep model leave no fold converged: every fold says so, and what to change
    out = capsys.readouterr().out
    assert out.count('not converged') == 4 and ('--epochs' in out or '--early-stopping' in out)
    assert 'not converged' in (tmp_path / 'run' / 'report.md').read_text()


def test_a_fold_whose_training_never_left_chance_is_named_with_what_to_change():
    chance = math.log(3)
    result = CrossValidation('grouped', np.zeros((2, 3)), np.zeros(2), histories=[
        [{'train_loss': chance}] * 50,  # every epoch on its first plateau
        [{'train_loss': chance}, {'train_loss': 0.2}] * 20,  # learned, then stopped early
        [{'train_loss': 1.0 - epoch / 100} for epoch in range(50)],  # still falling at 50
        []])  # a baseline: no history
    notes = convergence_notes(result, classes=3, epochs=50)
    assert len(notes) == 2
    assert notes[0].startswith('grouped fold 1: not converged: its training loss never fell '
                               'below chance (1.10') and 'raise --epochs' in notes[0]
    assert notes[1].startswith('grouped fold 3: not converged') and 'raise --epochs' in notes[1]


def test_a_baseline_given_deep_model_options_is_told_it_trains_without_them(tmp_path,
                                                                              capsys):
    data_path = toy().save(tmp_path / 'toy.npz')
    common = ['train', str(data_path), '--model', 'extratrees', '--folds', '2', '--cv',
              'grouped', '--no-final']
    assert main([*common, '--epochs', '60', '--profile', 'modern', '--out',
                 str(tmp_path / 'given')]) == 0
    assert ('note: --epochs 60, --profile modern: extratrees is a baseline, which trains '
            'without them') in capsys.readouterr().out
    assert main([*common, '--out', str(tmp_path / 'plain')]) == 0
    assert 'is a baseline' not in capsys.readouterr().out


def test_train_reports_a_missing_dataset(tmp_path, capsys):
    assert main(['train', str(tmp_path / 'none.npz'), '--out', str(tmp_path / 'r')]) == 1
    assert 'error:' in capsys.readouterr().err



def test_train_says_when_a_class_is_missing_from_a_training_fold(tmp_path, capsys):
    data = toy()
    keep = (data.y != 2) | (data.trial == 200)  # one recording of 'high' only
    from tactex_classify.data.dataset import Dataset
    small = Dataset(data.X[keep], data.y[keep], data.trial[keep], data.t0[keep], data.classes,
                    data.info)
    path = small.save(tmp_path / 'small.npz')
    assert main(['train', str(path), '--model', 'extratrees', '--folds', '2', '--cv', 'grouped',
                 '--out', str(tmp_path / 'run')]) == 0
    out = capsys.readouterr().out
    assert 'note: grouped fold' in out and "['high'] absent from training" in out


def test_a_failing_run_leaves_no_output_behind(tmp_path, capsys):
    path = toy(window=40).save(tmp_path / 'toy.npz')
    assert main(['train', str(path), '--model', 'cnn_3', '--epochs', '1', '--folds', '2',
                 '--out', str(tmp_path / 'run')]) == 1
    assert 'needs windows of at least 76' in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ['toy.json', 'toy.npz']


@pytest.mark.parametrize('command', [
    'train {data} --folds 2 --epochs 1',
    'train {data} --folds 2 --epochs 1 --movements {movements}',
    'report identification {data} --movements {movements} --folds 2 --inner-folds 2 --seeds 1',
])
def test_a_model_needing_longer_windows_is_refused_before_any_training(tmp_path, capsys,
                                                                       command):
    data = movement_dataset(tmp_path).save(tmp_path / 'data.npz')  # 32-sample windows
    argv = command.format(data=data, movements=movement_file(tmp_path)).split()
    assert main([*argv, '--model', 'cnn_1', '--out', str(tmp_path / 'run')]) == 1
    captured = capsys.readouterr()
    assert captured.out == ''  # nothing trained, not even a fold begun
    assert captured.err == ("error: --model cnn_1 needs windows of at least 40 samples, the "
                            "data's are 32: convert (or import) with --window 40 or more, or "
                            'choose another --model\n')
    assert not (tmp_path / 'run').exists()
