# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Fine-tuning (`tactex train --init`): a deep model starts from a pretrained checkpoint."""

import numpy as np
import pytest
from support.toy_windows import CLASSES, STREAM, toy
import torch

from tactex.cli import main
from tactex_classify.data.dataset import Dataset
from tactex_classify.models.architectures import build_model, output_parameters
from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
from tactex_classify.training.fine_tuning import start_from

torch.set_num_threads(1)


@pytest.fixture(scope='module')
def pretrained(tmp_path_factory):
    """A cnn_3 checkpoint trained on the toy set (window 96)."""
    data = toy()
    model = DeepClassifier(TrainingConfig(model='cnn_3', epochs=2)).fit(
        data.X, data.y, CLASSES, channels=data.channels)
    return model.save(tmp_path_factory.mktemp('pretrained') / 'model', **STREAM)


def _channels():
    return toy().channels


def test_the_same_classes_load_every_weight(pretrained):
    model = build_model('cnn_3', 96, 10, 3)
    assert start_from(model, str(pretrained), 'cnn_3', 96, _channels(), CLASSES) == []
    saved = DeepClassifier.load(pretrained).model_.state_dict()
    for name, value in model.state_dict().items():
        torch.testing.assert_close(value, saved[name])


def test_new_classes_get_a_fresh_output_layer_and_keep_the_rest(pretrained):
    torch.manual_seed(0)
    model = build_model('cnn_3', 96, 10, 3)
    fresh = {name: value.clone() for name, value in model.state_dict().items()}
    reset = start_from(model, str(pretrained), 'cnn_3', 96, _channels(), ['a', 'b', 'c'])
    assert set(reset) == output_parameters(model) and reset
    saved = DeepClassifier.load(pretrained).model_.state_dict()
    for name, value in model.state_dict().items():
        torch.testing.assert_close(value, fresh[name] if name in reset else saved[name])


def test_the_modern_models_name_their_output_layers():
    assert output_parameters(build_model('resnet', 64, 10, 3)) == {'head.weight', 'head.bias'}
    ensemble = output_parameters(build_model('inception_time_ensemble', 64, 10, 3))
    assert len(ensemble) == 10 and all('.head.' in name for name in ensemble)


@pytest.mark.parametrize('change, message', [
    ({'name': 'cnn_1'}, "model 'cnn_3', the training 'cnn_1'"),
    ({'window': 80}, 'window 96, the training 80'),
    ({'channels': [f'c{i}' for i in range(10)]}, 'channels'),
])
def test_another_model_window_or_channel_list_is_refused_by_name(pretrained, change, message):
    arguments = {'name': 'cnn_3', 'window': 96, 'channels': _channels(), **change}
    model = build_model('cnn_3', 96, 10, 3)
    with pytest.raises(ValueError, match=message):
        start_from(model, str(pretrained), arguments['name'], arguments['window'],
                   arguments['channels'], CLASSES)


def test_a_shifted_domain_with_one_recording_per_class_gains_from_pretraining(tmp_path):
    source = toy(recordings_per_class=12, windows=8, seed=1)
    settings = {'model': 'cnn_3', 'seed': 0, 'scaling': 'window', 'batchnorm_momentum': 0.1}
    checkpoint = DeepClassifier(TrainingConfig(epochs=15, **settings)).fit(
        source.X, source.y, CLASSES).save(tmp_path / 'sim', **STREAM)
    shifted = toy(recordings_per_class=5, windows=8, seed=2)
    shifted.X[..., :9] *= 1.7  # another gain and offset on the shifted "arm"
    shifted.X[..., :9] += 0.4
    train = shifted.trial % 100 == 0  # one recording per class
    accuracy = {}
    for name, init in (('scratch', ''), ('fine-tuned', str(checkpoint))):
        model = DeepClassifier(TrainingConfig(epochs=10, pretrained=init, **settings)).fit(
            shifted.X[train], shifted.y[train], CLASSES)
        accuracy[name] = np.mean(model.predict(shifted.X[~train]) == shifted.y[~train])
    assert accuracy['fine-tuned'] > accuracy['scratch'] + 0.1, accuracy


def test_train_init_fine_tunes_and_keeps_the_checkpoint_it_started_from(pretrained, tmp_path,
                                                                        capsys):
    path = toy(seed=3).save(tmp_path / 'other.npz')
    assert main(['train', str(path), '--init', str(pretrained), '--epochs', '2', '--folds',
                 '2', '--cv', 'grouped', '--out', str(tmp_path / 'run')]) == 0
    assert f'starts from the weights of {pretrained}' in capsys.readouterr().out
    tuned = DeepClassifier.load(tmp_path / 'run' / 'model')
    assert tuned.config.model == 'cnn_3' and tuned.config.pretrained == str(pretrained)
    assert tuned.config.scaling == 'minmax'  # the checkpoint's, unless --scaling says


def test_train_init_with_another_scaling_says_the_weights_saw_other_inputs(tmp_path, capsys):
    data = toy()
    window_scaled = DeepClassifier(TrainingConfig(model='cnn_3', epochs=1, scaling='window')
                                   ).fit(data.X, data.y, CLASSES, channels=data.channels)
    checkpoint = window_scaled.save(tmp_path / 'pretrained', **STREAM)
    path = toy(seed=3).save(tmp_path / 'other.npz')
    common = ['train', str(path), '--init', str(checkpoint), '--epochs', '1', '--folds', '2',
              '--cv', 'grouped']
    assert main([*common, '--out', str(tmp_path / 'same')]) == 0
    assert 'note: --scaling' not in capsys.readouterr().out
    assert DeepClassifier.load(tmp_path / 'same' / 'model').config.scaling == 'window'
    assert main([*common, '--no-final', '--scaling', 'minmax', '--out',
                 str(tmp_path / 'other')]) == 0
    assert ('note: --scaling minmax: ' + str(checkpoint) + ' was trained on window-scaled '
            'windows') in capsys.readouterr().out


@pytest.mark.parametrize('extra, message', [
    (['--model', 'cnn_1'], 'holds cnn_3, not --model cnn_1'),
    (['--window-of-another'], None),
    (['--channels-of-another'], None),
    (['--rate-of-another'], None),
])
def test_train_init_refuses_what_cannot_be_fine_tuned(pretrained, tmp_path, capsys, extra,
                                                      message):
    data = toy()
    if extra == ['--window-of-another']:
        short = Dataset(data.X[:, :80], data.y, data.trial, data.t0, data.classes, data.info)
        path, extra = short.save(tmp_path / 'short.npz'), []
        message = (f"--init {pretrained} was trained on 96-sample windows, DATA's are 80: "
                   'convert with --window 96, or start from a checkpoint of window 80')
    elif extra == ['--channels-of-another']:
        other = Dataset(data.X, data.y, data.trial, data.t0, data.classes, data.info,
                        channels=[f'c{i}' for i in range(10)])
        path, extra, message = other.save(tmp_path / 'other.npz'), [], 'DATA has c0, c1'
    elif extra == ['--rate-of-another']:
        fast = Dataset(data.X, data.y, data.trial, data.t0, data.classes,
                       {**data.info, 'sampling_rate_hz': 2 * STREAM['sampling_rate_hz']})
        path, extra = fast.save(tmp_path / 'fast.npz'), []
        rate = STREAM['sampling_rate_hz']
        message = (f'--init {pretrained} was trained at {rate:g} Hz, DATA is at {2 * rate:g} '
                   f'Hz: convert (or import) DATA with --resample {rate:g}')
    else:
        path = data.save(tmp_path / 'toy.npz')
    assert main(['train', str(path), '--init', str(pretrained), '--epochs', '1', '--folds',
                 '2', '--cv', 'grouped', '--out', str(tmp_path / 'run'), *extra]) == 1
    out, err = capsys.readouterr()
    assert err.startswith('error:') and message in err and 'Traceback' not in err
    assert 'fold' not in out  # refused before any training
    assert not (tmp_path / 'run').exists()


def test_train_init_refuses_a_baseline_and_a_missing_or_broken_checkpoint(tmp_path, capsys):
    path = toy().save(tmp_path / 'toy.npz')
    assert main(['train', str(path), '--model', 'extratrees', '--folds', '2', '--cv',
                 'grouped', '--out', str(tmp_path / 'forest')]) == 0
    (tmp_path / 'bad').mkdir()
    (tmp_path / 'bad' / 'checkpoint.json').write_text('{\n')
    for checkpoint, message in (
            (tmp_path / 'forest' / 'model', 'only a deep model'),
            (tmp_path / 'none', f'--init {tmp_path / "none"} does not exist'),
            (tmp_path / 'forest', f'missing checkpoint.json; give its checkpoint, '
                                  f'{tmp_path / "forest" / "model"}'),
            (tmp_path / 'bad', 'refused checkpoint.json: Expecting property name enclosed in '
                               'double quotes: line 2 column 1 (char 2); retrain or copy the '
                               'whole folder again')):
        capsys.readouterr()
        assert main(['train', str(path), '--init', str(checkpoint), '--folds', '2',
                     '--out', str(tmp_path / 'run')]) == 1
        assert message in capsys.readouterr().err
