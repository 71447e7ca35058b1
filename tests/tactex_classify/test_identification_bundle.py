# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""`tactex train DATA --movements YAML`: the identification bundle, written and read back.

One checkpoint per movement with its temperature and calibrated out-of-fold evidence;
loading rebuilds the same evidence table and refuses an edited bundle, a movement file
whose movements differ in name, order or any parameter or whose window differs from the
checkpoints', and textures that differ from a checkpoint's; `tactex launch` refuses the
same before any node starts.
"""

import json
import re
import shutil

import numpy as np
import pytest
from support.movement_data import (
    movement_dataset,
    movement_file,
    MOVEMENTS,
    TEXTURES,
    WINDOW,
)

from tactex.cli import main
from tactex_classify.errors import CheckpointError
from tactex_classify.identification import bundle as bundle_module
from tactex_classify.identification.bundle import check_bundle, load_bundle
from tactex_classify.models.checkpoint import CHECKSUM_FIELD, metadata_sha256
from tactex_description.movements import load_movements


@pytest.fixture(scope='module')
def trained(tmp_path_factory):
    folder = tmp_path_factory.mktemp('bundle')
    movement_dataset(folder)
    assert main(['train', str(folder / 'data.npz'), '--movements',
                 str(movement_file(folder)), '--model', 'extratrees', '--folds', '2',
                 '--out', str(folder / 'run')]) == 0
    return folder


def test_the_bundle_holds_a_checkpoint_per_movement_and_rebuilds_the_evidence(trained):
    bundle = load_bundle(trained / 'run' / 'bundle', load_movements(trained / 'movements.yaml'))
    assert bundle.classes == tuple(TEXTURES)
    assert [m.name for m in bundle.movements] == list(MOVEMENTS)
    assert bundle.table.names == tuple(MOVEMENTS)
    assert bundle.table.seconds == pytest.approx([2.0, 1.0, 1.0])
    assert 0.05 <= bundle.table.tempering <= 4.0
    assert all(0.05 <= t <= 20 for t in bundle.temperatures)
    window = np.random.default_rng(1).normal(size=(2, 32, 10)).astype(np.float32)
    window[:, :, 0] += 6.0  # wood, under tells_all
    assert bundle.estimators[0].predict_proba(window).argmax(axis=1).tolist() == [2, 2]


def test_a_bundle_trained_for_other_movements_is_refused(trained, tmp_path):
    bundle = trained / 'run' / 'bundle'
    other = movement_file(tmp_path, contact_s=(2.0, 1.0, 1.5))
    with pytest.raises(CheckpointError, match='movement tells_nothing was trained as .*the file '
                                              'now says'):
        load_bundle(bundle, load_movements(other))
    renamed = tmp_path / 'renamed.yaml'
    renamed.write_text(other.read_text().replace('tells_wood', 'tells_cork'))
    with pytest.raises(CheckpointError, match='the bundle holds movements tells_all, tells_wood,'
                                              ' tells_nothing; the movement file lists'):
        load_bundle(bundle, load_movements(renamed))



def test_checking_a_bundle_refuses_what_loading_refuses_without_loading_a_model(
        trained, tmp_path, monkeypatch):
    def no_model(info):
        raise AssertionError(f'a model was loaded from {info.folder}')
    monkeypatch.setattr(bundle_module, 'load_estimator', no_model)
    bundle = trained / 'run' / 'bundle'
    check_bundle(bundle, load_movements(trained / 'movements.yaml'))
    other = movement_file(tmp_path, contact_s=(2.0, 1.0, 1.5))
    with pytest.raises(CheckpointError, match='movement tells_nothing was trained as'):
        check_bundle(bundle, load_movements(other))

def test_an_edited_or_missing_bundle_is_refused(trained, tmp_path):
    movements = load_movements(trained / 'movements.yaml')
    copy = tmp_path / 'bundle'
    shutil.copytree(trained / 'run' / 'bundle', copy)
    meta = json.loads((copy / 'bundle.json').read_text())
    meta['tempering'] = 0.5
    (copy / 'bundle.json').write_text(json.dumps(meta))
    with pytest.raises(CheckpointError, match='does not match its'):
        load_bundle(copy, movements)
    (copy / 'bundle.json').unlink()
    with pytest.raises(CheckpointError, match='missing bundle.json'):
        load_bundle(copy, movements)
    with pytest.raises(CheckpointError, match='missing bundle.json'):
        load_bundle(tmp_path / 'nothing', movements)


def test_a_movement_file_of_another_window_is_refused_naming_both(trained, tmp_path):
    other = movement_file(tmp_path)
    other.write_text(other.read_text().replace(f'window: {WINDOW}', f'window: {WINDOW * 2}'))
    with pytest.raises(CheckpointError, match=f'its checkpoints read windows of {WINDOW} '
                                              f'samples, the movement file says window: '
                                              f'{WINDOW * 2}: give the movement file'):
        load_bundle(trained / 'run' / 'bundle', load_movements(other))


def test_a_bundle_whose_window_differs_from_its_checkpoints_is_refused(trained, tmp_path):
    copy = tmp_path / 'bundle'
    shutil.copytree(trained / 'run' / 'bundle', copy)
    meta = json.loads((copy / 'bundle.json').read_text())
    meta['window'] = WINDOW * 2
    meta[CHECKSUM_FIELD] = metadata_sha256(meta)
    (copy / 'bundle.json').write_text(json.dumps(meta))
    with pytest.raises(CheckpointError, match=f'states a window of {WINDOW * 2} samples, its '
                                              f'checkpoints read {WINDOW}: train'):
        load_bundle(copy, load_movements(trained / 'movements.yaml'))


@pytest.mark.parametrize('change', [
    lambda meta: meta.update(tempering=10**400),  # JSON's long whole number, past float range
    lambda meta: meta['movements'][0].update(temperature=10**400),
    lambda meta: meta['movements'][0].update(vectors=[[10**400]]),
])
def test_a_checksummed_bundle_with_a_number_past_the_float_range_is_refused(trained, tmp_path,
                                                                            change):
    copy = tmp_path / 'bundle'
    shutil.copytree(trained / 'run' / 'bundle', copy)
    meta = json.loads((copy / 'bundle.json').read_text())
    change(meta)
    meta[CHECKSUM_FIELD] = metadata_sha256(meta)
    (copy / 'bundle.json').write_text(json.dumps(meta))
    with pytest.raises(CheckpointError, match='malformed bundle.json'):
        load_bundle(copy, load_movements(trained / 'movements.yaml'))


@pytest.mark.parametrize('key, value', [
    ('speed', '0.03'), ('press_depth', '0.003'), ('edge_tilt', '0.4'),
    ('direction', 'backward'), ('contact_length', '0.05')])
def test_a_movement_file_differing_in_any_parameter_is_refused(trained, tmp_path, key, value):
    text = (trained / 'movements.yaml').read_text()
    first, rest = text.split('\n  - ', 1)[0], text.split('\n  - ', 1)[1]
    changed = tmp_path / 'changed.yaml'
    changed.write_text(first + '\n  - ' + re.sub(f'{key}: [^,}}]+', f'{key}: {value}', rest,
                                                 count=1))
    with pytest.raises(CheckpointError, match='movement tells_all was trained as .*the file '
                                              'now says'):
        load_bundle(trained / 'run' / 'bundle', load_movements(changed))


def test_launching_with_a_movement_file_the_bundle_was_not_trained_for_is_refused(
        trained, tmp_path):
    from tactex.launching.arguments import check_arguments
    from tactex.launching.spec import LaunchError, load_launch_file
    other = movement_file(tmp_path)
    other.write_text(other.read_text().replace(f'window: {WINDOW}', f'window: {WINDOW * 2}'))
    launch = load_launch_file('identify')
    bundle = str(trained / 'run' / 'bundle')
    check_arguments(launch, launch.resolve({'bundle': bundle,
                                            'movements': str(trained / 'movements.yaml')}))
    with pytest.raises(LaunchError, match=r'^bundle:=.* with movements:=.*: .*its checkpoints '
                                          f'read windows of {WINDOW} samples'):
        check_arguments(launch, launch.resolve({'bundle': bundle, 'movements': str(other)}))


def test_a_deep_bundle_trains_with_the_options_the_report_takes_and_names_what_fell_short(
        tmp_path, capsys):
    movement_dataset(tmp_path)
    assert main(['train', str(tmp_path / 'data.npz'), '--movements',
                 str(movement_file(tmp_path)), '--model', 'cnn_2', '--profile', 'modern',
                 '--epochs', '2', '--scaling', 'window', '--early-stopping', '0', '--folds',
                 '2', '--out', str(tmp_path / 'run')]) == 0
    printed = capsys.readouterr().out
    for movement in MOVEMENTS:  # two folds and the final model, each cut short at 2 epochs
        assert len(re.findall(rf'note: {movement}: .* not converged \(', printed)) == 3
    assert re.search(r'note: tells_all: final model not converged \(still falling\): raise '
                     r'--epochs\n|note: tells_all: final model not converged \(stalled at '
                     r'chance\): raise --epochs, or try another --model\n', printed)
    config = json.loads((tmp_path / 'run' / 'bundle' / 'movements' / 'tells_all' /
                         'checkpoint.json').read_text())['config']
    assert (config['profile'], config['epochs'], config['scaling']) == ('modern', 2, 'window')


@pytest.fixture(scope='module')
def pretrained(tmp_path_factory):
    """A window-scaled cnn_2 checkpoint of the movement dataset's stream (one epoch)."""
    from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
    folder = tmp_path_factory.mktemp('pretrained')
    data = movement_dataset(folder)
    model = DeepClassifier(TrainingConfig(model='cnn_2', epochs=1, scaling='window')).fit(
        data.X, data.y, data.classes, channels=data.channels)
    return model.save(folder / 'model', hop=data.info['hop'],
                      sampling_rate_hz=data.info['sampling_rate_hz'])


def test_every_movements_model_can_start_from_a_pretrained_checkpoint(pretrained, tmp_path,
                                                                      capsys):
    movement_dataset(tmp_path)
    assert main(['train', str(tmp_path / 'data.npz'), '--movements',
                 str(movement_file(tmp_path)), '--init', str(pretrained), '--epochs', '1',
                 '--folds', '2', '--out', str(tmp_path / 'run')]) == 0
    assert 'bundle: ' in capsys.readouterr().out
    for movement in MOVEMENTS:  # the checkpoint's model and scaling, unless told otherwise
        config = json.loads((tmp_path / 'run' / 'bundle' / 'movements' / movement /
                             'checkpoint.json').read_text())['config']
        assert (config['model'], config['scaling'], config['pretrained']) == (
            'cnn_2', 'window', str(pretrained))
    assert main(['report', 'identification', str(tmp_path / 'data.npz'), '--movements',
                 str(movement_file(tmp_path)), '--init', str(pretrained), '--epochs', '1',
                 '--folds', '2', '--inner-folds', '2', '--seeds', '1', '--policies', 'active',
                 '--out', str(tmp_path / 'report')]) == 0
    settings = json.loads((tmp_path / 'report' / 'identification.json').read_text())['settings']
    assert (settings['model'], settings['scaling'], settings['pretrained']) == (
        'cnn_2', 'window', str(pretrained))
    assert f'fine-tuned from {pretrained}' in (tmp_path / 'report' /
                                               'identification.md').read_text()


@pytest.mark.parametrize('command', ['train', 'report'])
def test_a_baseline_checkpoint_cannot_be_fine_tuned(trained, tmp_path, capsys, command):
    movement_dataset(tmp_path)
    baseline = trained / 'run' / 'bundle' / 'movements' / 'tells_all'  # extratrees
    argv = (['train', str(tmp_path / 'data.npz'), '--folds', '2'] if command == 'train' else
            ['report', 'identification', str(tmp_path / 'data.npz')])
    assert main([*argv, '--movements', str(movement_file(tmp_path)), '--init', str(baseline),
                 '--out', str(tmp_path / 'run')]) == 1
    captured = capsys.readouterr()
    assert captured.out == ''
    assert captured.err == (f'error: --init: {baseline} holds the baseline extratrees; only a '
                            'deep model can be fine-tuned (train the baseline on the new data '
                            'alone)\n')
    assert not (tmp_path / 'run').exists()


@pytest.mark.parametrize('command', ['train', 'report'])
def test_a_checkpoint_of_another_model_is_refused_before_any_training(pretrained, tmp_path,
                                                                      capsys, command):
    movement_dataset(tmp_path)
    argv = (['train', str(tmp_path / 'data.npz'), '--folds', '2'] if command == 'train' else
            ['report', 'identification', str(tmp_path / 'data.npz')])
    assert main([*argv, '--movements', str(movement_file(tmp_path)), '--init', str(pretrained),
                 '--model', 'resnet', '--out', str(tmp_path / 'run')]) == 1
    captured = capsys.readouterr()
    assert captured.out == ''
    assert captured.err == (f'error: --init: {pretrained} holds cnn_2, not --model resnet; '
                            "leave --model out to fine-tune the checkpoint's model\n")
    assert not (tmp_path / 'run').exists()
