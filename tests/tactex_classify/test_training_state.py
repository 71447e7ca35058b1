# Copyright 2026 The tactex authors
# SPDX-License-Identifier: Apache-2.0
"""A deep model's fit keeps its state between epochs and resumes as if never stopped."""

import numpy as np
import pytest
from support.toy_windows import toy
import torch

from tactex_classify.training.deep_classifier import DeepClassifier, TrainingConfig
from tactex_classify.training.training_state import forget, TrainingStateWarning

EPOCHS = 5


def config(model='cnn_3', **settings):
    """The modern profile: every random draw a fit makes (augmentation, mixup, dropout)."""
    return TrainingConfig.for_profile('modern', **{
        'model': model, 'epochs': EPOCHS, 'early_stopping': 3, 'warmup_epochs': 1, 'seed': 3,
        **settings})


class Interrupted(Exception):
    """What stops a fit after an epoch, as a kill would."""


def fit(data, settings, state_file=None, stop_after=None):
    def progress(record):
        if record['epoch'] == stop_after:
            raise Interrupted
    classifier = DeepClassifier(settings, state_file=state_file, state_every_s=0.0,
                                progress=progress if stop_after else None)
    classifier.fit(data.X, data.y, data.classes, groups=data.trial)
    return classifier


def same_fit(first, second):
    assert first.history_ == second.history_
    assert first.best_epoch_ == second.best_epoch_
    for (name, a), b in zip(first.model_.state_dict().items(),
                            second.model_.state_dict().values(), strict=True):
        assert torch.equal(a, b), name


def kept(state):
    return torch.load(state, weights_only=True)


@pytest.mark.parametrize('model', ['cnn_3', 'inception_time_ensemble'])
def test_an_interrupted_fit_resumes_bit_for_bit(tmp_path, model):
    data = toy(recordings_per_class=4, windows=4, window=96)
    straight = fit(data, config(model))
    state = tmp_path / 'state.pt'
    with pytest.raises(Interrupted):
        fit(data, config(model), state, stop_after=2)
    before = kept(state)
    assert (before['epoch'], before['finished']) == (2, False)
    resumed = fit(data, config(model), state)
    same_fit(straight, resumed)
    assert [record['epoch'] for record in resumed.history_] == list(
        range(1, len(straight.history_) + 1))
    assert resumed.resumed_seconds_ == before['seconds'] > 0  # the two epochs before the stop
    assert kept(state)['finished']  # kept until the caller has kept the result


def test_a_fit_whose_state_is_finished_only_restores_it(tmp_path):
    data = toy(recordings_per_class=4, windows=4, window=96)
    state = tmp_path / 'state.pt'
    first = fit(data, config(), state)
    epochs = []
    again = DeepClassifier(config(), state_file=state, progress=epochs.append)
    again.fit(data.X, data.y, data.classes, groups=data.trial)
    same_fit(first, again)
    assert epochs == []  # nothing trained
    assert again.resumed_seconds_ == kept(state)['seconds']


def test_forgetting_a_state_removes_it_its_partial_writes_and_its_empty_folders(tmp_path):
    folder = tmp_path / 'grid' / 'training_state'
    state = folder / 'cnn_3' / 'w96' / 'fold1.pt'
    state.parent.mkdir(parents=True)
    for path in (state, state.with_name('.fold1.pt.123.partial'),
                 state.with_name('fold2.pt')):
        path.write_bytes(b'x')
    forget(state, up_to=folder)
    assert sorted(p.name for p in state.parent.iterdir()) == ['fold2.pt']  # another's stays
    forget(state.with_name('fold2.pt'), up_to=folder)
    assert folder.is_dir() and not list(folder.iterdir())


def test_the_state_is_written_only_when_due(tmp_path):
    data = toy(recordings_per_class=4, windows=4, window=96)
    state = tmp_path / 'state.pt'
    classifier = DeepClassifier(config(), state_file=state, state_every_s=1e9,
                                progress=lambda record: (_ for _ in ()).throw(Interrupted))
    with pytest.raises(Interrupted):
        classifier.fit(data.X, data.y, data.classes, groups=data.trial)
    assert not state.exists()  # epoch 1 of 5: neither due nor the last


def test_a_state_that_cannot_be_written_only_warns(tmp_path):
    data = toy(recordings_per_class=4, windows=4, window=96)
    (tmp_path / 'file').write_bytes(b'')
    with pytest.warns(TrainingStateWarning, match='cannot be kept'):
        unkept = fit(data, config(), tmp_path / 'file' / 'state.pt')
    same_fit(fit(data, config()), unkept)


def test_a_state_that_does_not_fit_the_model_is_set_aside(tmp_path):
    data = toy(recordings_per_class=4, windows=4, window=96)
    state = tmp_path / 'state.pt'
    with pytest.raises(Interrupted):
        fit(data, config(), state, stop_after=2)
    damaged = kept(state)
    damaged['model'] = {'renamed.weight': torch.zeros(1)}  # the key still matches
    torch.save(damaged, state)
    with pytest.warns(TrainingStateWarning, match='does not fit this model'):
        started_over = fit(data, config(), state)
    same_fit(fit(data, config()), started_over)
    assert started_over.resumed_seconds_ == 0.0


def test_a_fit_without_a_state_file_writes_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    data = toy(recordings_per_class=4, windows=4, window=96)
    classifier = fit(data, config())
    assert classifier.resumed_seconds_ == 0.0
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize('change', [{'seed': 4}, {'learning_rate': 2e-3}, {'threads': 2},
                                    'data'])
def test_a_state_kept_for_another_fit_is_set_aside_and_the_fit_starts_over(tmp_path, change):
    data = toy(recordings_per_class=4, windows=4, window=96)
    state = tmp_path / 'state.pt'
    with pytest.raises(Interrupted):
        fit(data, config(), state, stop_after=1)
    other = toy(recordings_per_class=4, windows=4, window=96, seed=9) if change == 'data' \
        else data
    settings = config() if change == 'data' else config(**change)
    with pytest.warns(TrainingStateWarning, match='kept for other data or settings'):
        started_over = fit(other, settings, state)
    same_fit(fit(other, settings), started_over)
    assert started_over.resumed_seconds_ == 0.0


@pytest.mark.parametrize('content', [b'', b'not a torch file', b'\x80\x04K\x01.'])
def test_a_damaged_or_foreign_state_file_is_set_aside(tmp_path, content):
    state = tmp_path / 'state.pt'
    state.write_bytes(content)
    data = toy(recordings_per_class=4, windows=4, window=96)
    with pytest.warns(TrainingStateWarning, match='is not a training state'):
        same_fit(fit(data, config()), fit(data, config(), state))


def test_a_state_file_with_a_pickled_object_is_never_unpickled(tmp_path):
    class Payload:
        def __reduce__(self):
            return (exec, ("raise SystemExit('unpickled')",))
    state = tmp_path / 'state.pt'
    torch.save({'key': 'x', 'payload': Payload()}, state)
    data = toy(recordings_per_class=4, windows=4, window=96)
    with pytest.warns(TrainingStateWarning, match='is not a training state'):
        fit(data, config(), state)


def test_the_numpy_generator_state_survives_the_restricted_load(tmp_path):
    from tactex_classify.training.training_state import (
        random_states,
        restore_random_states,
        TrainingState,
    )
    rng = np.random.default_rng(12345)
    rng.random(7)
    generator = torch.Generator().manual_seed(1)
    keeper = TrainingState(tmp_path / 's.pt', 'key', every_s=0.0)
    keeper.save({'random': random_states(generator, rng)})
    expected = rng.random(3), torch.rand(2, generator=generator)
    fresh_rng, fresh_generator = np.random.default_rng(0), torch.Generator()
    restore_random_states(keeper.load()['random'], fresh_generator, fresh_rng)
    assert np.array_equal(fresh_rng.random(3), expected[0])
    assert torch.equal(torch.rand(2, generator=fresh_generator), expected[1])
