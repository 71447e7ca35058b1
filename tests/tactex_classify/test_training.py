# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""Training, checkpoints, baselines and cross-validation on small synthetic windows."""

import dataclasses
import json
import pickle
import warnings

import numpy as np
import pytest
from support.toy_windows import CLASSES, STREAM, toy
import torch

from tactex_classify.data.dataset import Dataset
from tactex_classify.errors import CheckpointError, DatasetError, NotFittedError
from tactex_classify.evaluation.cross_validation import (
    confusion,
    cross_validate,
    decide_recordings,
    decision_measures,
    metrics,
    sequence_accuracy,
    splits,
    threshold_decisions,
)
from tactex_classify.models.baselines import MiniRocketRidge, StatsExtraTrees
from tactex_classify.models.checkpoint import CHECKSUM_FIELD, metadata_sha256, sha256
from tactex_classify.models.hydra import HydraRidge, MultiRocketHydraRidge
from tactex_classify.models.multirocket import MultiRocketRidge
from tactex_classify.models.windows import ChannelScaler
from tactex_classify.training.deep_classifier import (
    DeepClassifier,
    prepare_training_device,
    TrainingConfig,
)
from tactex_classify.training.validation import validation_split

FAST = TrainingConfig(model='cnn_3', epochs=3, seed=1)


def test_training_is_deterministic_for_a_seed():
    data = toy()
    first = DeepClassifier(FAST).fit(data.X, data.y, CLASSES).predict_proba(data.X)
    second = DeepClassifier(FAST).fit(data.X, data.y, CLASSES).predict_proba(data.X)
    np.testing.assert_array_equal(first, second)
    assert first.shape == (len(data.X), 3)


def test_training_on_a_gpu_lets_cudnn_autotune_and_on_the_cpu_leaves_it(monkeypatch):
    monkeypatch.setattr(torch.backends.cudnn, 'benchmark', False)
    assert prepare_training_device('cpu') == torch.device('cpu')
    assert torch.backends.cudnn.benchmark is False
    assert prepare_training_device('cuda:1') == torch.device('cuda:1')  # no GPU needed to choose
    assert torch.backends.cudnn.benchmark is True


def test_resume_from_checkpoint_gives_identical_predictions(tmp_path):
    data = toy()
    model = DeepClassifier(FAST).fit(data.X, data.y, CLASSES)
    loaded = DeepClassifier.load(model.save(tmp_path / 'ckpt', **STREAM))
    np.testing.assert_array_equal(model.predict_proba(data.X[:5]),
                                  loaded.predict_proba(data.X[:5]))
    assert loaded.classes_ == CLASSES and loaded.scaler_.offset == model.scaler_.offset


def test_a_checkpoint_with_a_foreign_pickle_payload_is_refused(tmp_path):
    data = toy()
    folder = DeepClassifier(FAST).fit(data.X, data.y, CLASSES).save(tmp_path / 'ckpt', **STREAM)

    class Payload:
        def __reduce__(self):
            return (print, ('this ran',))
    torch.save({'weights': Payload()}, folder / 'weights.pt')
    with pytest.raises(CheckpointError, match='does not match its SHA-256'):
        DeepClassifier.load(folder)
    rehash(folder)  # as an attacker would
    with pytest.raises(CheckpointError, match='refused'):
        DeepClassifier.load(folder)
    (folder / 'weights.pt').write_bytes(pickle.dumps([1, 2, 3]))
    rehash(folder)
    with pytest.raises(CheckpointError):
        DeepClassifier.load(folder)
    (folder / 'weights.pt').unlink()
    with pytest.raises(CheckpointError, match='missing weights.pt'):
        DeepClassifier.load(folder)


def rehash(folder, change=None):
    """Make checkpoint.json's checksums fit the model file, or checkpoint.json changed.

    With `change`, checkpoint.json is rewritten as `change(meta)`. What an attacker would
    do: whatever gets past the checksums must still be refused by the loader itself.
    """
    meta = json.loads((folder / 'checkpoint.json').read_text())
    if change is None:
        meta['files'] = {name: sha256(folder / name) for name in meta['files']}
    else:
        meta = change(meta)
    if isinstance(meta, dict):
        meta[CHECKSUM_FIELD] = metadata_sha256(meta)
    (folder / 'checkpoint.json').write_text(json.dumps(meta))


def test_nan_input_is_rejected_with_a_clear_error():
    data = toy()
    bad = data.X.copy()
    bad[3, 5, 2] = np.nan
    with pytest.raises(ValueError, match='NaN or inf in 1 window'):
        DeepClassifier(FAST).fit(bad, data.y, CLASSES)
    model = StatsExtraTrees(trees=10).fit(data.X, data.y, CLASSES)
    with pytest.raises(ValueError, match='NaN'):
        model.predict_proba(bad)
    with pytest.raises(ValueError, match='fitted on'):
        model.predict_proba(data.X[:, :48])


def test_unfitted_use_is_a_clear_error():
    with pytest.raises(NotFittedError, match='DeepClassifier is not fitted'):
        DeepClassifier(FAST).predict(np.zeros((1, 32, 10)))
    with pytest.raises(NotFittedError, match='MiniRocketRidge'):
        MiniRocketRidge().predict_proba(np.zeros((1, 32, 10)))


def test_constant_channels_scale_without_dividing_by_zero():
    X = np.ones((4, 16, 10), np.float32)
    for kind in ('minmax', 'standard'):
        scaled = ChannelScaler(kind).fit(X).transform(X)
        assert np.all(np.isfinite(scaled))
    data = toy()
    constant = data.X.copy()
    constant[:, :, 4] = 7.0
    with warnings.catch_warnings():  # a constant channel's skew and kurtosis are 0, quietly
        warnings.simplefilter('error')
        proba = StatsExtraTrees(trees=10).fit(constant, data.y, CLASSES).predict_proba(constant)
        features = StatsExtraTrees.features(constant)
    assert np.all(np.isfinite(proba))
    assert np.all(np.isfinite(features))


def test_minmax_scaler_is_fitted_on_the_training_windows_only():
    data = toy()
    scaler = ChannelScaler().fit(data.X[:10])
    assert scaler.transform(data.X[:10]).max() <= 1.0 + 1e-6
    assert np.array(scaler.offset).shape == (10,)


@pytest.mark.parametrize('make', [lambda: StatsExtraTrees(trees=50), MiniRocketRidge,
                                  MultiRocketRidge, HydraRidge, MultiRocketHydraRidge])
def test_baselines_learn_the_toy_task_honestly(make):
    data = toy()
    result = cross_validate(data, make, 'grouped', folds=4)
    accuracy = metrics(confusion(data.y, result.proba.argmax(1), 3), CLASSES)['accuracy']
    assert accuracy > 0.8
    assert np.all(result.fold >= 0)


def test_a_deep_model_fits_and_generalises_to_held_out_recordings():
    # 14 training recordings per class: with 7, held-out accuracy swung between chance and
    # 0.7 with the seed, under either initialisation.
    data = toy(recordings_per_class=20, windows=8)
    train = data.trial % 100 < 14
    model = DeepClassifier(TrainingConfig('cnn_1', epochs=25, batch_size=16)).fit(
        data.X[train], data.y[train], CLASSES)
    assert model.history_[-1]['train_accuracy'] > 0.9
    held_out = np.mean(model.predict(data.X[~train]) == data.y[~train])
    assert held_out > 0.5  # well above the 1/3 of chance on unseen recordings


def test_a_training_cut_short_says_why_it_did_not_converge():
    data = toy()
    model = DeepClassifier(FAST).fit(data.X, data.y, CLASSES)  # 3 epochs: too few to tell
    assert model.unconverged_reason() in ('still falling', 'stalled at chance')


def test_grouped_folds_never_split_a_recording():
    data = toy()
    result = cross_validate(data, lambda: StatsExtraTrees(trees=5), 'grouped', folds=4)
    for trial in np.unique(data.trial):
        assert len(set(result.fold[data.trial == trial])) == 1


def test_a_class_absent_from_a_fold_is_noted_not_fatal():
    data = toy()
    keep = ~((data.y == 2) & (data.trial != 200))  # one recording left of class "high"
    small = Dataset(data.X[keep], data.y[keep], data.trial[keep], data.t0[keep], CLASSES,
                    data.info)
    result = cross_validate(small, lambda: StatsExtraTrees(trees=5), 'grouped', folds=4)
    assert any("['high'] absent" in note for note in result.notes)
    assert result.proba.shape == (len(small.X), 3)


def test_stratified_scheme_is_available_and_leaks_by_design():
    data = toy()
    result = cross_validate(data, lambda: StatsExtraTrees(trees=5), 'stratified', folds=4)
    shared = sum(len(set(result.fold[data.trial == t])) > 1 for t in np.unique(data.trial))
    assert shared > 0  # recordings on both sides: the leak the grouped scheme removes


def test_sequence_accuracy_grows_with_accumulated_windows():
    data = toy()
    proba = np.full((len(data.X), 3), 0.2)
    proba[np.arange(len(data.X)), data.y] = 0.6
    wrong = np.arange(len(data.X)) % 6 == 2  # one window in six wrong on its own
    proba[wrong] = np.roll(proba[wrong], 1, axis=1)
    curve = sequence_accuracy(data, proba)
    assert list(curve) == [1, 2, 4]
    assert curve[1]['accuracy'] < curve[4]['accuracy'] == 1.0


def test_a_sequence_row_says_which_recordings_and_classes_it_still_holds():
    data = toy()  # 6 windows per recording; the last class's recordings cut to 3
    short = ~((data.y == 2) & (data.t0 >= 0.3))
    cut = data.select(short)
    proba = np.full((len(cut.X), 3), 0.1)
    proba[np.arange(len(cut.X)), cut.y] = 0.8
    curve = sequence_accuracy(cut, proba)
    recordings = len(np.unique(cut.trial))
    assert curve[2] == {'accuracy': 1.0, 'recordings': recordings, 'classes': 3}
    assert curve[4]['classes'] == 2 and curve[4]['recordings'] < recordings


def test_threshold_decisions_replay_the_live_rule_on_each_recording():
    data = toy()  # 6 windows of 96 samples, hop 48, per recording; t0 every 0.1 s
    proba = np.full((len(data.X), 3), 0.2)
    proba[np.arange(len(data.X)), data.y] = 0.6
    first = threshold_decisions(data, proba, 0.5, 100.0)
    assert first['accuracy'] == 1.0
    assert first['median_contact_s'] == pytest.approx(0.96)  # one window: 96 samples
    whole = threshold_decisions(data, proba, 1.0, 100.0)  # never met: decided at the end
    assert whole['earliness'] == pytest.approx(1.0)
    assert whole['median_contact_s'] > first['median_contact_s']
    assert first['earliness'] < 1.0 and first['harmonic_mean'] > whole['harmonic_mean']


def test_deciding_live_asks_for_no_window_after_the_decision():
    data = toy()
    asked = []

    def proba_of(index):
        asked.append(index)
        row = np.full(3, 0.05)
        row[data.y[index]] = 0.9
        return row
    decisions = decide_recordings(data, proba_of, 0.99, 100.0)
    assert len(decisions) == len(np.unique(data.trial))
    assert all(d['correct'] and d['wall_s'] >= 0 for d in decisions)
    assert len(asked) == 2 * len(decisions)  # 0.9 / 0.1 ratios: two windows pass 0.99


def test_decision_measures_give_teasers_harmonic_mean():
    measures = decision_measures([(True, 1.0, 0.2), (False, 3.0, 0.6)])
    assert measures['accuracy'] == 0.5 and measures['earliness'] == pytest.approx(0.4)
    assert measures['median_contact_s'] == 2.0
    assert measures['harmonic_mean'] == pytest.approx(2 * 0.5 * 0.6 / 1.1)
    assert decision_measures([(False, 1.0, 1.0)])['harmonic_mean'] == 0.0


def test_metrics_from_a_confusion_matrix():
    matrix = np.array([[5, 0], [1, 4]])
    result = metrics(matrix, ['a', 'b'])
    assert result['accuracy'] == 0.9
    assert result['per_class']['a']['precision'] == pytest.approx(5 / 6)
    assert result['macro_recall'] == pytest.approx((1.0 + 0.8) / 2)


EARLY = TrainingConfig(model='cnn_3', epochs=4, seed=1, early_stopping=2,
                       validation_fraction=0.25)


def test_early_stopping_validation_recordings_never_move_the_scaler():
    data = toy()
    _, validation = validation_split(data.y, data.trial, EARLY)
    held = np.unique(data.trial[validation])
    assert held.size and not set(held) & set(np.unique(np.delete(data.trial, validation)))
    louder = data.X.copy()
    louder[validation] *= 100.0  # only the held-out recordings change
    scalers = [DeepClassifier(EARLY).fit(X, data.y, CLASSES, groups=data.trial).scaler_
               for X in (data.X, louder)]
    assert scalers[0] == scalers[1]
    training = ChannelScaler().fit(np.delete(data.X, validation, axis=0))
    assert scalers[0] == training


def test_early_stopping_keeps_the_epoch_of_least_validation_loss():
    data = toy()
    model = DeepClassifier(dataclasses.replace(EARLY, epochs=12)).fit(
        data.X, data.y, CLASSES, groups=data.trial)
    losses = [record['val_loss'] for record in model.history_]
    _, validation = validation_split(data.y, data.trial, EARLY)
    proba = model.predict_proba(data.X[validation])
    restored = -np.mean(np.log(proba[np.arange(validation.size), data.y[validation]]))
    assert restored == pytest.approx(min(losses), rel=1e-4)


def test_early_stopping_never_ends_a_training_still_at_chance():
    # A learning rate too small to move the weights keeps the loss at ln(classes): the
    # validation loss cannot judge such a model yet, so patience does not run out.
    data = toy()
    stuck = dataclasses.replace(EARLY, epochs=8, early_stopping=1, learning_rate=1e-12)
    model = DeepClassifier(stuck).fit(data.X, data.y, CLASSES, groups=data.trial)
    assert len(model.history_) == 8
    assert model.unconverged_reason() == 'stalled at chance'


def test_early_stopping_without_recordings_is_refused():
    data = toy()
    with pytest.raises(ValueError, match='pass groups'):
        DeepClassifier(EARLY).fit(data.X, data.y, CLASSES)


def test_early_stopping_on_one_recording_is_refused():
    data = toy()
    with pytest.raises(ValueError, match='at least 2 recordings'):
        DeepClassifier(EARLY).fit(data.X, data.y, CLASSES, groups=np.zeros(len(data.y)))
    with pytest.raises(ValueError, match='leaves none to train on'):
        DeepClassifier(dataclasses.replace(EARLY, validation_fraction=0.9)).fit(
            data.X[:12], data.y[:12], CLASSES, groups=data.trial[:12])


@pytest.mark.parametrize('change, field', [
    (lambda meta: [], 'not a tactex checkpoint'),
    (lambda meta: {**meta, 'format_version': 99}, 'not a tactex checkpoint of format version'),
    (lambda meta: {**meta, 'format_version': 1}, 'retrain with `tactex train`'),
    (lambda meta: {**meta, 'hop': 0}, 'hop must be'),
    (lambda meta: {**meta, 'hop': 97}, 'hop must be <= window'),
    (lambda meta: {**meta, 'sampling_rate_hz': float('nan')}, 'sampling_rate_hz must be'),
    (lambda meta: {**meta, 'files': {'../../etc/passwd': 'ab'}}, 'files must be'),
    (lambda meta: {**meta, 'model': 'cnn_1'}, 'disagrees with its configuration'),
    (lambda meta: {k: v for k, v in meta.items() if k != 'classes'}, "missing 'classes'"),
    (lambda meta: {**meta, 'classes': 'low mid high'}, 'classes must be'),
    (lambda meta: {**meta, 'channels': ['ax'] * 10}, 'channels must be'),
    (lambda meta: {**meta, 'window': '96'}, 'window must be'),
    (lambda meta: {**meta, 'config': {**meta['config'], 'dropout': 0.3}}, 'dropout'),
    (lambda meta: {**meta, 'config': {**meta['config'], 'epochs': -1}}, 'epochs must be'),
    (lambda meta: {**meta, 'config': {**meta['config'], 'model': 'lstm_fcn'}}, 'unknown model'),
    (lambda meta: {**meta, 'config': None}, 'config must be'),
    (lambda meta: {**meta, 'scaler': {**meta['scaler'], 'offset': [0.0] * 9}},
     'offset must be 10 finite'),
    (lambda meta: {**meta, 'scaler': {**meta['scaler'], 'scale': [0.0] * 10}}, 'scale must be'),
    (lambda meta: {**meta, 'scaler': {**meta['scaler'], 'kind': 'robust'}}, 'scaler kind'),
    (lambda meta: {**meta, 'scaler': [1, 2]}, 'scaler must be'),
])
def test_a_malformed_checkpoint_json_is_a_checkpoint_error(tmp_path, change, field):
    data = toy()
    folder = DeepClassifier(FAST).fit(data.X, data.y, CLASSES).save(tmp_path / 'ckpt', **STREAM)
    rehash(folder, change)
    with pytest.raises(CheckpointError, match=field):
        DeepClassifier.load(folder)


@pytest.mark.parametrize('damage', ['binary json', 'truncated weights', 'nan weights',
                                    'tensor list', 'empty weights'])
def test_a_damaged_checkpoint_file_is_a_checkpoint_error(tmp_path, damage):
    data = toy()
    folder = DeepClassifier(FAST).fit(data.X, data.y, CLASSES).save(tmp_path / 'ckpt', **STREAM)
    weights = folder / 'weights.pt'
    if damage == 'binary json':
        (folder / 'checkpoint.json').write_bytes(b'\xff\xfe\x00garbage')
    elif damage == 'truncated weights':
        weights.write_bytes(weights.read_bytes()[:200])
    elif damage == 'nan weights':
        state = torch.load(weights, weights_only=True)
        next(iter(state.values())).fill_(float('nan'))
        torch.save(state, weights)
    elif damage == 'tensor list':
        torch.save([torch.zeros(3)], weights)
    else:
        weights.write_bytes(b'')
    if damage != 'binary json':
        rehash(folder)  # past the checksum: the loader itself must refuse it
    with pytest.raises(CheckpointError):
        DeepClassifier.load(folder)


def test_channel_names_are_kept_and_checked_against_the_data(tmp_path):
    data = toy()
    names = [f'c{i}' for i in range(10)]
    model = DeepClassifier(FAST).fit(data.X, data.y, CLASSES, channels=names)
    loaded = DeepClassifier.load(model.save(tmp_path / 'ckpt', **STREAM))
    assert loaded.channels_ == names
    loaded.predict(data.X[:2], channels=names)
    with pytest.raises(ValueError, match="the data has channels \\['c1', 'c0'"):
        loaded.predict(data.X[:2], channels=[names[1], names[0], *names[2:]])
    with pytest.raises(ValueError, match='fitted on'):
        loaded.predict(data.X[:2, :, :9])


THREE_AXES = ['ax', 'ay', 'az']


def three_channel(data):
    """The toy set as a 3-axis sensor's dataset (channel 0 carries the class)."""
    return Dataset(data.X[:, :, :3].copy(), data.y, data.trial, data.t0, data.classes,
                   data.info, THREE_AXES)


@pytest.mark.parametrize('name', ['cnn_bilstm_1', 'cnn_bilstm_2', 'cnn_bilstm_3', 'cnn_1',
                                  'cnn_2', 'cnn_3', 'bilstm_1', 'bilstm_2'])
def test_every_model_trains_on_any_channel_set_and_its_checkpoint_names_them(tmp_path, name):
    data = three_channel(toy(recordings_per_class=1, windows=3))
    model = DeepClassifier(TrainingConfig(model=name, epochs=1)).fit(
        data.X, data.y, data.classes, channels=data.channels)
    assert model.channels_ == THREE_AXES
    loaded = DeepClassifier.load(model.save(tmp_path / 'ckpt', **STREAM))
    assert loaded.channels_ == THREE_AXES and loaded.n_channels_ == 3
    np.testing.assert_allclose(loaded.predict_proba(data.X[:2]), model.predict_proba(data.X[:2]),
                               rtol=1e-5, atol=1e-6)


def test_baselines_and_cross_validation_carry_the_dataset_channels():
    data = three_channel(toy())
    for model in (StatsExtraTrees(trees=10), MiniRocketRidge(dilations=2)):
        assert model.fit(data.X, data.y, data.classes, channels=data.channels
                         ).channels_ == THREE_AXES
    result = cross_validate(data, lambda: StatsExtraTrees(trees=10), 'grouped', folds=2)
    assert result.proba.shape == (len(data.y), 3)


def test_channel_names_are_required_beyond_the_ten_and_must_fit():
    data = three_channel(toy(recordings_per_class=1, windows=2))
    with pytest.raises(ValueError, match='pass their names'):
        StatsExtraTrees(trees=2).fit(data.X, data.y, data.classes)
    with pytest.raises(ValueError, match='2 channel names for 3 channels'):
        StatsExtraTrees(trees=2).fit(data.X, data.y, data.classes, channels=['a', 'b'])
    scaler = ChannelScaler().fit(data.X)
    with pytest.raises(ValueError, match='fitted on 3'):
        scaler.transform(np.zeros((1, 4, 10)))


def test_a_dataset_keeps_its_channel_names_through_save_and_load(tmp_path):
    data = three_channel(toy(recordings_per_class=1, windows=2))
    loaded = Dataset.load(data.save(tmp_path / 'three.npz'))
    assert loaded.channels == THREE_AXES and loaded.X.shape[2] == 3
    with pytest.raises(DatasetError, match='3 channel names for 10 channels'):
        Dataset(toy().X, toy().y, toy().trial, toy().t0, CLASSES, {}, THREE_AXES)


@pytest.mark.parametrize('scheme', ['grouped', 'stratified'])
def test_more_folds_than_a_class_has_windows_raise_no_scikit_learn_warning(scheme):
    data = toy()  # 4 recordings of 6 windows per class
    keep = (data.y != 0) | (data.trial == data.trial[data.y == 0][0])  # one of class 0
    data = Dataset(data.X[keep], data.y[keep], data.trial[keep], data.t0[keep], data.classes,
                   data.info)
    with warnings.catch_warnings():
        warnings.simplefilter('error')  # scikit-learn's count of class 0's windows stays out
        folds = splits(data, scheme, 8, seed=0)
    assert sorted(np.concatenate([test for _, test in folds]).tolist()) == \
        list(range(len(data.y)))
